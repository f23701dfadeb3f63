// ngi engine: the pipelines that build a geometry image's mip chain on the GPU and draw its
// grid at any level of detail. One Renderer per device; every GeometryImageSurface built
// with it can be drawn with it, into the caller's own command buffer. The renderer's own
// draw pipeline matches RendererOptions' pass (one colour attachment, depth, dynamic
// rendering: the tools' offscreen target); a host engine describes each of its own passes
// (colour attachments 0..N, depth/stencil formats, compare op, samples, dynamic rendering
// or a VkRenderPass subpass, depth-only shadow passes) with a PassDescription and draws
// through a SurfacePipeline made for it; many instances are drawn in few calls by a
// DrawBatch (draw_batch.h). Nothing here submits to the queue or waits.
#pragma once

#include "ngi/engine/context.h"
#include "ngi/engine/mip_chain.h"
#include "ngi/engine/resources.h"
#include "ngi/engine/surface.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <vulkan/vulkan.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ngi::vk {

class AssetSurface;
class GeometryImageSurface;

enum class ShadingMode : uint32_t { Shaded = 0, Normals = 1, Wireframe = 2, Lod = 3, BaseColour = 4 };

// "shaded", "normals", "wireframe", "lod", "colour" (or "color": the base colour unlit, adaptive
// draws); ngi::Error listing the valid names otherwise.
ShadingMode parseShadingMode(const std::string& name);

// The host pass (or subpass) a draw pipeline is recorded in, and the depth/stencil state the
// surface is drawn with. Every field must match the pass the draw is recorded in (Vulkan's
// pipeline/rendering compatibility rules; the validation layer names a mismatch).
struct PassDescription {
    // Colour attachments 0..N-1. ngi's fragment shader writes attachment 0 (the shaded
    // colour); attachments 1.. are left untouched (colour write mask 0, which needs the
    // independentBlend feature: Context::independentBlend). Empty: a depth-only
    // pass (shadow maps): no fragment shader unless SurfacePipeline is given one.
    std::vector<VkFormat> colorFormats{VK_FORMAT_R8G8B8A8_UNORM};
    VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;  // VK_FORMAT_UNDEFINED: no depth attachment
    // The pass's stencil attachment format. A combined format (D24_UNORM_S8_UINT,
    // D32_SFLOAT_S8_UINT) bound as both depth and stencil attachment: set it in both fields.
    VkFormat stencilFormat = VK_FORMAT_UNDEFINED;
    VkCompareOp depthCompare = VK_COMPARE_OP_LESS_OR_EQUAL;  // VK_COMPARE_OP_GREATER_OR_EQUAL: reverse-Z
    bool depthWrite = true;
    // Stencil test applied to the surface's fragments (front and back); unset: no stencil test.
    std::optional<VkStencilOpState> stencil;
    // Depth bias as dynamic state (vkCmdSetDepthBias before the draw), for shadow maps.
    bool dynamicDepthBias = false;
    VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
    // Set: a classic render pass; the pipeline is made for `subpass` of it (the formats above
    // then describe that subpass: colorFormats.size() colour attachments). Null: dynamic
    // rendering (Vulkan 1.3) with exactly these formats.
    VkRenderPass renderPass = VK_NULL_HANDLE;
    uint32_t subpass = 0;
};

struct RendererOptions {
    VkFormat colorFormat = VK_FORMAT_R8G8B8A8_UNORM;
    VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;
    VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
    // Draw grids through one shared topology-only 16-bit quad index buffer (4 vertex shader
    // invocations per quad, 192 KiB, the same for every asset and grid size) instead of
    // 6 non-indexed vertices per quad. Neither uses per-asset vertex or index data.
    bool quadIndexBuffer = true;
    // Draw a level's grid with shared vertices (a sample runs the vertex shader once per
    // post-transform cache miss, not 4 times per quad) through the index buffer that
    // Renderer::recordGridExpansion writes at run time before the pass, where that expansion
    // was recorded; false: always one of the per-quad ways above (quadIndexBuffer), and
    // recordGridExpansion records nothing.
    bool gridExpansion = true;

    // The pass of the renderer's own draw pipeline: one colour attachment, depth, dynamic
    // rendering, less-or-equal depth test.
    PassDescription pass() const;
};

class Renderer;

// A draw pipeline of ngi's surface vertex stage (shaders/surface.vert, the public vertex
// stage: its sets, push constants, per-instance data and outputs are documented at the top
// of that file) for one host pass. A host's own fragment shader reads the vertex stage's
// outputs (location 0 = normal, 1 = position, both in the asset's normalized space,
// 2 = barycentric (noperspective), 3 = flat (camera in normalized space, LoD), 4/5 = world-
// space position/normal in batched draws) and may use sets 2.. of its own: `hostSetLayouts`
// are appended to ngi's sets 0 (level) and 1 (instances) in this pipeline's layout(), which
// the host binds its sets with (before or after ngi's draw: ngi binds sets 0 and 1 and the
// push constants with the same layout, which leaves the host's sets bound).
class SurfacePipeline {
public:
    // The set number of the first of hostSetLayouts (NGI_DRAW_HOST_SET in ngi_shared.h).
    static constexpr uint32_t firstHostSet = 2;
    // `fragmentSpirv` empty: ngi's shading (surface.frag) when the pass has a colour
    // attachment, none for a depth-only pass. ngi::Error (naming the pass) on failure.
    SurfacePipeline(const Renderer& renderer, const PassDescription& pass, std::span<const uint32_t> fragmentSpirv = {},
                    std::span<const VkDescriptorSetLayout> hostSetLayouts = {});
    const PassDescription& pass() const { return pass_; }
    // The pipeline of one way of placing the grid's vertices (`way`: NGI_WAY_* in
    // ngi_shared.h, 0 .. wayCount - 1): per quad on a level's samples (0, the default), per
    // quad sampled bilinearly, or shared vertices; for single draws (Renderer::recordDraw)
    // or batched ones (DrawBatch, `instanced`). Each is the public vertex stage specialized
    // to that way and kind of draw (its specialization constants NGI_SPEC_VERTEX_WAY and
    // NGI_SPEC_INSTANCED): six pipelines (twelve with ngi's shading, below), one layout.
    // With ngi's own shading each comes twice: without and with the base colour's alpha test
    // (`cutOut`, NGI_SPEC_CUT_OUT: for a surface whose colour cutsOut()); a host's fragment
    // shader has one of each, whatever `cutOut` says.
    static constexpr uint32_t wayCount = 3;
    VkPipeline pipeline(uint32_t way = 0, bool instanced = false, bool cutOut = false) const
    {
        return pipelines_[cutOut && ownShading_][instanced][way].get();
    }
    // Renderer::drawLayout(), or with host sets this pipeline's own (sets 0, 1, then the host's).
    VkPipelineLayout layout() const { return layout_; }
    // Whether the fragment stage reads the vertex stage's barycentrics (location 2) in
    // `mode`: ngi's own shading in wireframe mode, a host's fragment shader if its SPIR-V
    // reads that input (shaderReadsInput), a depth-only pass never. Such draws keep a
    // per-quad way (shared vertices have no triangle corners to tell apart).
    bool readsBarycentrics(ShadingMode mode) const
    {
        return ownShading_ ? mode == ShadingMode::Wireframe : hostReadsBarycentrics_;
    }

private:
    bool ownShading_ = false;             // surface.frag
    bool hostReadsBarycentrics_ = false;  // a host fragment shader that reads location 2
    PassDescription pass_;
    UniquePipelineLayout ownLayout_;  // only with host sets
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    UniquePipeline pipelines_[2][2][wayCount];  // [cut out][instanced][way]
};

struct DrawParams {
    // World space -> Vulkan clip space. Without `world`, world space is the surface's
    // normalized asset space ([0,1]^3, the tools' framing of boundsMin/boundsMax).
    glm::mat4 viewProjection{1.0f};
    glm::vec3 eye{0.0f};  // camera position in world space (shading, not LoD)
    // Object -> world matrix of this instance. ngi applies the asset's de-normalization
    // (Asset::offset/scale, GeometryImageSurface::objectFromNormalized) itself, so object
    // space is the space of the mesh the asset was baked from.
    std::optional<glm::mat4> world;
    float lod = 0.0f;       // continuous LoD, 0 = full resolution (used when gridSize == 0)
    uint32_t gridSize = 0;  // > 0: draw a fixed N x N vertex grid instead (2 .. full size)
    ShadingMode mode = ShadingMode::Shaded;
    float wireWidth = 1.0f;  // wireframe line width, pixels
    // The host's pipeline (its pass); null: the renderer's own (RendererOptions::pass).
    const SurfacePipeline* pipeline = nullptr;
    // Viewport and scissor (e.g. one half of a split screen). Unset: the `extent` given to
    // recordDraw (the whole target), or, without one, left as the host set them (both are
    // dynamic state of every ngi pipeline).
    std::optional<VkViewport> viewport;
    std::optional<VkRect2D> scissor;
};

struct DrawStats {
    uint32_t level = 0;      // mip level sampled
    float morph = 0.0f;      // geomorph factor
    uint32_t gridSize = 0;   // vertices per side drawn
    uint64_t triangles = 0;  // 2 (N - 1)^2
    // Vertex shader runs: 4 per quad (quad index buffer) or 6; with shared vertices the
    // N^2 samples (a lower bound: the driver's post-transform cache may run a sample again).
    uint64_t vertexInvocations = 0;
    bool sharedVertices = false;  // drawn through the level's expanded index buffer
};

class Renderer {
public:
    // Creates the compute and graphics pipelines and the shared quad index buffer (in host-
    // visible memory, written by the CPU: no queue submission, no wait). ngi::Error on failure.
    Renderer(const Context& context, const RendererOptions& options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Records, OUTSIDE any render pass (compute), what lets a later recordDraw of `surface`
    // with the same level, geomorph factor, pipeline and mode draw shared vertices: the grid
    // expansion (shaders/grid_expansion.comp), which writes the level's index buffer with
    // each quad's diagonal chosen for this factor (6 (N - 1)^2 indices kept by the surface,
    // made on the level's first expansion: GeometryImageSurface::expandedGrid; the vertex
    // shader geomorphs the samples itself), then a barrier that makes them visible to the
    // index fetch. Nothing is recorded when the buffer
    // already holds this level and factor (a still LoD costs no expansion), or when that
    // draw takes a per-quad way anyway: RendererOptions::gridExpansion off, a grid size that
    // is not a nested level size, a fragment stage that reads the barycentrics
    // (SurfacePipeline::readsBarycentrics), or a level whose index buffer exceeds the
    // device's maxStorageBufferRange. A draw recorded without a matching expansion
    // (none, or a later one of the same level for another factor) takes the per-quad way:
    // the same pixels, slower. Returns the number of levels expanded (0 or 1).
    // The command buffer must be submitted after those of earlier recordDraws of the surface,
    // on the same queue (the barrier orders the rewrite after their reads).
    uint32_t recordGridExpansion(VkCommandBuffer cmd, const GeometryImageSurface& surface,
                                 const DrawParams& params) const;
    // The same for every chart of `asset` as AssetSurface::recordDraw draws it with `params`.
    // Returns the number of charts expanded.
    uint32_t recordGridExpansion(VkCommandBuffer cmd, const AssetSurface& asset, const DrawParams& params) const;

    // Records the draw of `surface` at params.lod (or params.gridSize) with params.pipeline
    // (or the renderer's own), inside the pass that pipeline was made for. Viewport and
    // scissor: params.viewport/scissor, else the whole `extent`, else the host's (no
    // extent). The surface must have been built (GeometryImageSurface::recordBuild) and
    // that work must be ordered before this draw (same queue, earlier submission or same
    // buffer). Binds its pipeline, sets 0 and 1 and the push constants with the pipeline's
    // layout: a host rebinds its own pipeline after; its sets 2.. (SurfacePipeline) stay.
    // The vertex stage's world-space outputs (locations 4, 5) are normalized-space ones here
    // (no world matrix on the GPU): a host material that needs world space uses DrawBatch.
    // Shared vertices when recordGridExpansion was recorded for this draw, else per quad.
    DrawStats recordDraw(VkCommandBuffer cmd, const GeometryImageSurface& surface, const DrawParams& params,
                         std::optional<VkExtent2D> extent = std::nullopt) const;

    const Context& context() const { return context_; }
    const RendererOptions& options() const { return options_; }

    // The build step before the draw (restore -> mip chain -> draw): used by
    // GeometryImageSurface::recordBuild.
    const MipChainPipelines& mipChain() const { return mipChain_; }
    // What a surface's draw sets are made of: three combined image samplers (a level, its
    // geomorph targets, its quad diagonals).
    VkDescriptorSetLayout drawSetLayout() const { return drawSetLayout_; }
    // Set 1 of the draw: one storage buffer of gpu::DrawInstance (vertex stage).
    VkDescriptorSetLayout instanceSetLayout() const { return instanceSetLayout_.get(); }
    // The grid expansion's set: a level's quad diagonals (storage image) and its index
    // buffer (storage buffer); see NGI_EXPANSION_BINDING_* in ngi_shared.h.
    VkDescriptorSetLayout gridExpansionSetLayout() const { return expansionSetLayout_.get(); }
    VkSampler texelSampler() const { return sampler_; }

    // Sets 0 (drawSetLayout) and 1 (instanceSetLayout), gpu::DrawPushConstants for the
    // vertex and fragment stages.
    VkPipelineLayout drawLayout() const { return drawLayout_; }

private:
    friend class DrawBatch;
    friend class AdaptiveSurface;
    friend class GpuTileSelection;
    void destroy();
    void createQuadIndices();
    const SurfacePipeline& pipelineFor(const SurfacePipeline* pipeline) const { return pipeline ? *pipeline : *draw_; }
    // The dynamic viewport and scissor of a draw (see DrawParams::viewport).
    static void setViewportScissor(VkCommandBuffer cmd, const std::optional<VkViewport>& viewport,
                                   const std::optional<VkRect2D>& scissor, std::optional<VkExtent2D> extent);
    // The draw calls of an N-grid of `quads` quads, `instanceCount` instances from
    // `firstInstance`, with the pipeline, sets and push constants bound: through `shared`'s
    // index buffer, chunk by chunk (NGI_GRID_SHARED_VERTICES), if not null, else per quad
    // (perQuadTopology()). Returns the calls made.
    uint32_t recordGrid(VkCommandBuffer cmd, uint64_t quads, uint32_t instanceCount, uint32_t firstInstance,
                        const GeometryImageSurface::ExpandedGrid* shared = nullptr) const;
    // NGI_GRID_QUAD_INDEXED or NGI_GRID_NON_INDEXED: this renderer's per-quad way.
    uint32_t perQuadTopology() const;
    // Whether a level of `levelSize` samples may be expanded: RendererOptions::gridExpansion
    // and the device's storage buffer range (its index buffer).
    bool expandable(uint32_t levelSize) const;
    // Whether a draw of an N-grid on a level of `levelSize` samples with `pipeline` in `mode`
    // may use shared vertices (RendererOptions::gridExpansion, a nested size, no barycentrics,
    // within the device's image size limit).
    bool sharesVertices(const SurfacePipeline& pipeline, ShadingMode mode, uint32_t gridSize, uint32_t levelSize) const;
    // One grid expansion: `level` of `surface` for geomorph factor `morph`.
    struct Expansion {
        const GeometryImageSurface* surface;
        uint32_t level;
        float morph;
    };
    // Records the expansions of expandable levels whose buffers do not already hold them (one
    // barrier before and one after all of them). Returns the number recorded.
    uint32_t recordExpansions(VkCommandBuffer cmd, std::span<const Expansion> expansions) const;
    // A set of instanceSetLayout() from `pool` holding all of `buffer`.
    VkDescriptorSet allocateInstanceSet(VkDescriptorPool pool, VkBuffer buffer) const;
    const Context& context_;
    RendererOptions options_;
    MipChainPipelines mipChain_;
    VkDescriptorSetLayout drawSetLayout_ = VK_NULL_HANDLE;
    UniqueDescriptorSetLayout instanceSetLayout_;
    VkPipelineLayout drawLayout_ = VK_NULL_HANDLE;
    // Set 1 of single draws: a one-record buffer the shader never reads (instanced = 0), bound
    // because the pipeline's vertex stage declares the set.
    Buffer unusedInstances_;
    UniqueDescriptorPool instancePool_;
    VkDescriptorSet unusedInstanceSet_ = VK_NULL_HANDLE;
    UniqueDescriptorSetLayout expansionSetLayout_;
    UniquePipelineLayout expansionLayout_;
    UniquePipeline expansion_;             // grid_expansion.comp
    std::optional<SurfacePipeline> draw_;  // the renderer's own pass
    VkSampler sampler_ = VK_NULL_HANDLE;
    Buffer quadIndices_;
};

}  // namespace ngi::vk
