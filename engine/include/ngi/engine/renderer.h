// ngi engine: the pipelines that build a geometry image's mip chain on the GPU and draw its
// grid at any level of detail. One Renderer per device and colour/depth format; every
// GeometryImageSurface built with it can be drawn with it, into the caller's own command
// buffer (inside dynamic rendering the caller began), so a host engine can use it as is.
#pragma once

#include "ngi/engine/context.h"
#include "ngi/engine/mip_chain.h"
#include "ngi/engine/resources.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include <vulkan/vulkan.h>

#include <cstdint>
#include <string>

namespace ngi::vk {

class GeometryImageSurface;

enum class ShadingMode : uint32_t { Shaded = 0, Normals = 1, Wireframe = 2, Lod = 3 };

// "shaded", "normals", "wireframe", "lod"; ngi::Error listing the valid names otherwise.
ShadingMode parseShadingMode(const std::string& name);

struct RendererOptions {
    VkFormat colorFormat = VK_FORMAT_R8G8B8A8_UNORM;
    VkFormat depthFormat = VK_FORMAT_D32_SFLOAT;
    VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT;
    // Draw grids through one shared topology-only 16-bit quad index buffer (4 vertex shader
    // invocations per quad, 192 KiB, the same for every asset and grid size) instead of
    // 6 non-indexed vertices per quad. Neither uses per-asset vertex or index data.
    bool quadIndexBuffer = true;
};

struct DrawParams {
    glm::mat4 viewProjection{1.0f};  // normalized asset space -> Vulkan clip space
    glm::vec3 eye{0.0f};             // camera position in normalized asset space
    float lod = 0.0f;                // continuous LoD, 0 = full resolution (used when gridSize == 0)
    uint32_t gridSize = 0;           // > 0: draw a fixed N x N vertex grid instead (2 .. full size)
    ShadingMode mode = ShadingMode::Shaded;
    float wireWidth = 1.0f;          // wireframe line width, pixels
};

struct DrawStats {
    uint32_t level = 0;       // mip level sampled
    float morph = 0.0f;       // geomorph factor
    uint32_t gridSize = 0;    // vertices per side drawn
    uint64_t triangles = 0;   // 2 (N - 1)^2
    uint64_t vertexInvocations = 0;  // vertex shader runs: 4 per quad (quad index buffer) or 6
};

class Renderer {
public:
    // Creates the compute and graphics pipelines. ngi::Error on failure.
    Renderer(const Context& context, const RendererOptions& options = {});
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    // Records the draw of `surface` at params.lod (or params.gridSize). Must be inside
    // dynamic rendering with this renderer's formats; sets viewport/scissor to `extent`.
    // The surface must have been built (GeometryImageSurface::recordBuild) and that work
    // must be ordered before this draw (same queue, earlier submission or same buffer).
    DrawStats recordDraw(VkCommandBuffer cmd, const GeometryImageSurface& surface, const DrawParams& params,
                         VkExtent2D extent) const;

    const Context& context() const { return context_; }
    const RendererOptions& options() const { return options_; }

    // The build step before the draw (restore -> mip chain -> draw): used by
    // GeometryImageSurface::recordBuild.
    const MipChainPipelines& mipChain() const { return mipChain_; }
    // What a surface's draw sets are made of.
    VkDescriptorSetLayout drawSetLayout() const { return drawSetLayout_; }
    VkSampler texelSampler() const { return sampler_; }

    VkPipelineLayout drawLayout() const { return drawLayout_; }

private:
    void destroy();
    void createQuadIndices();
    const Context& context_;
    RendererOptions options_;
    MipChainPipelines mipChain_;
    VkDescriptorSetLayout drawSetLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout drawLayout_ = VK_NULL_HANDLE;
    VkPipeline draw_ = VK_NULL_HANDLE;
    VkSampler sampler_ = VK_NULL_HANDLE;
    Buffer quadIndices_;
};

} // namespace ngi::vk
