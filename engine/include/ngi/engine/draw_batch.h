// ngi engine: batched drawing of many instances of many assets in few calls.
//
// A host adds its instances (an asset or a chart, a world matrix, a continuous LoD) once per
// frame; DrawBatch::record sorts them into buckets of one chart at one mip level (the
// descriptor set a draw binds), writes one gpu::DrawInstance per chart per instance into a
// host-visible buffer (clip and world transforms, eye, geomorph factor) and records ONE
// instanced draw per bucket (per 16384-quad chunk of the bucket's grid): the vertex shader
// reads its instance by gl_InstanceIndex (shaders/surface.vert, instanced = 1). The draw
// count is the number of distinct (chart, level) pairs, not the number of instances.
// Instanced direct draws rather than indirect ones: the LoD is chosen on the CPU (lod.h), so
// the buckets and their counts are known when recording and an indirect buffer would add a
// write and a read without saving a bind (each bucket binds its own level's set anyway).
//
// Each instance is drawn exactly as Renderer::recordDraw draws it with the same world
// matrix and LoD (the same transforms, computed the same way, and the same grid): a batch is
// pixel-identical to the single draws in bucket order (tests/engine/host_batch_test.cpp).
//
// Shared vertices (Renderer::recordGridExpansion): recordGridExpansion, before the passes,
// expands each bucket's level once when all of the bucket's instances have the same
// geomorph factor (every instance at an integer LoD, or at the same LoD), and record() then
// draws that bucket with shared vertices. A bucket whose instances differ in the factor is
// drawn per quad: their diagonals may differ, and one expansion per instance would cost
// more than it saves on the few instances that share a level that finely.
#pragma once

#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace ngi::vk {

class AssetSurface;
class GeometryImageSurface;

// The pass-wide part of a batched draw (the per-instance part is DrawBatch::add's).
struct BatchParams {
    glm::mat4 viewProjection{1.0f};  // world -> Vulkan clip space of this pass
    glm::vec3 eye{0.0f};             // camera position in world space (shading)
    ShadingMode mode = ShadingMode::Shaded;
    float wireWidth = 1.0f;
    // The host's pipeline (its pass); null: the renderer's own.
    const SurfacePipeline* pipeline = nullptr;
    // As DrawParams::viewport / scissor (unset: the extent given to record, or the host's).
    std::optional<VkViewport> viewport;
    std::optional<VkRect2D> scissor;
    // Skip each chart whose bounding sphere (around its stored samples' box, 25% wider for
    // the restored detail, placed by the world matrix) lies outside viewProjection's frustum
    // (Vulkan's clip volume, 0 <= z <= w: reverse-Z too): such a chart has no pixel in the pass.
    bool frustumCull = true;
};

struct BatchStats {
    uint32_t instances = 0;      // instances added
    uint32_t records = 0;        // gpu::DrawInstance records written (one per drawn chart per instance)
    uint32_t culled = 0;         // charts outside the frustum (BatchParams::frustumCull), not drawn
    uint32_t buckets = 0;        // distinct (chart, level) pairs drawn
    uint32_t drawCalls = 0;      // vkCmdDraw* calls recorded
    uint32_t sharedBuckets = 0;  // buckets drawn with shared vertices (expanded levels)
    uint64_t triangles = 0;      // summed over every instance's charts
    uint64_t vertexInvocations = 0;
};

class DrawBatch {
public:
    // `capacity`: instance records the batch's buffer holds (160 bytes each), summed over
    // every record() between two clear()s: an instance of a C-chart asset drawn in P passes
    // takes C * P. ngi::Error on failure.
    DrawBatch(const Renderer& renderer, uint32_t capacity);
    DrawBatch(const DrawBatch&) = delete;
    DrawBatch& operator=(const DrawBatch&) = delete;

    // Forgets the instances and rewinds the record buffer. Only once the GPU has finished
    // every command buffer recorded from this batch since the last clear (a host with F
    // frames in flight keeps F batches).
    void clear();
    // One instance: every chart of `asset` (each at its own level for `lod`, as
    // AssetSurface::recordDraw), or one chart `surface`, placed by `world` (object -> world;
    // the asset's de-normalization is applied by ngi, as DrawParams::world). The surface must
    // outlive the batch's last record() and must have been built before the draw runs.
    void add(const AssetSurface& asset, const glm::mat4& world, float lod);
    void add(const GeometryImageSurface& surface, const glm::mat4& world, float lod);
    size_t instanceCount() const { return instances_; }

    // Records, OUTSIDE any render pass, the grid expansion of each (chart, level) bucket of
    // the instances added since clear() whose instances share one geomorph factor (see
    // above; Renderer::recordGridExpansion's rules, caching and ordering): every record()
    // after it draws such a bucket with shared vertices while its level's expansion holds
    // that factor. Frustum culling is not applied here (the passes may differ). Returns the
    // number of levels expanded (cached ones are not).
    uint32_t recordGridExpansion(VkCommandBuffer cmd);

    // Records the draws of every instance added since clear() inside the pass that
    // params.pipeline was made for (several passes: one record() each, e.g. a shadow map
    // and the main pass). Binds its pipeline, sets 0 and 1 and the push constants; viewport
    // and scissor as Renderer::recordDraw. ngi::Error when the records exceed the capacity.
    BatchStats record(VkCommandBuffer cmd, const BatchParams& params, std::optional<VkExtent2D> extent = std::nullopt);

private:
    // The level, geomorph factor and grid of an entry (Renderer::recordDraw's rule), and its
    // LoD clamped to the surface's finest level.
    struct Selection {
        uint32_t level;
        float morph;
        uint32_t gridSize;
        float lod;
    };
    struct Entry;
    static Selection select(const Entry& e);
    struct Entry {
        const GeometryImageSurface* surface;
        glm::mat4 world;
        float lod;  // this chart's continuous LoD (the asset's, shifted and clamped)
    };
    const Renderer& renderer_;
    uint32_t capacity_;
    uint32_t used_ = 0;  // records written since clear()
    size_t instances_ = 0;
    std::vector<Entry> entries_;
    UniqueBuffer records_;
    UniqueDescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
};

}  // namespace ngi::vk
