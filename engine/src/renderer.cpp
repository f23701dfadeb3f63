// The any-LoD grid draw (the mip chain's pipelines are mip_chain.cpp's).
#include "ngi/engine/renderer.h"

#include "ngi/engine/pipelines.h"
#include "ngi/engine/mip_chain.h"
#include "ngi/engine/surface.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/network_weights.h"
#include "ngi_shared.h"

#include "ngi_shaders/surface_frag.h"
#include "ngi_shaders/surface_vert.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <span>

namespace ngi::vk {

// C++ enums whose values the shaders read as NGI_* constants (push constants hold
// uint32_t(enum)): one definition each, so a value changed on one side fails the build.
static_assert(uint32_t(ShadingMode::Shaded) == NGI_MODE_SHADED);
static_assert(uint32_t(ShadingMode::Normals) == NGI_MODE_NORMALS);
static_assert(uint32_t(ShadingMode::Wireframe) == NGI_MODE_WIREFRAME);
static_assert(uint32_t(ShadingMode::Lod) == NGI_MODE_LOD);
// The network's activations (ngi/network_weights.h), which SuperResolution writes into
// SrPushConstants::activation.
static_assert(uint32_t(Activation::None) == NGI_SR_ACT_NONE);
static_assert(uint32_t(Activation::ReLU) == NGI_SR_ACT_RELU);
static_assert(uint32_t(Activation::LeakyReLU) == NGI_SR_ACT_LEAKY);

ShadingMode parseShadingMode(const std::string& name)
{
    if (name == "shaded") return ShadingMode::Shaded;
    if (name == "normals") return ShadingMode::Normals;
    if (name == "wireframe") return ShadingMode::Wireframe;
    if (name == "lod") return ShadingMode::Lod;
    throw Error("unknown shading mode '" + name + "' (valid: shaded, normals, wireframe, lod)");
}

PassDescription RendererOptions::pass() const
{
    PassDescription p;
    p.colorFormats = {colorFormat};
    p.depthFormat = depthFormat;
    p.samples = samples;
    return p;
}

SurfacePipeline::SurfacePipeline(const Renderer& renderer, const PassDescription& pass,
                                 std::span<const uint32_t> fragmentSpirv)
    : pass_(pass), pipeline_(renderer.context().device)
{
    GraphicsPipelineDesc desc;
    desc.vertexSpirv = surface_vert_spv;
    desc.fragmentSpirv = !fragmentSpirv.empty() ? fragmentSpirv
                         : pass.colorFormats.empty() ? std::span<const uint32_t>{}
                                                     : std::span<const uint32_t>(surface_frag_spv);
    desc.layout = renderer.drawLayout();
    desc.pass = pass;
    desc.writeFirstAttachmentOnly = fragmentSpirv.empty();
    if (desc.writeFirstAttachmentOnly && pass.colorFormats.size() > 1 && !renderer.context().independentBlend)
        throw Error("surface pipeline: ngi's fragment shader writes colour attachment 0 only; a pass of " +
                    std::to_string(pass.colorFormats.size()) +
                    " colour attachments needs the independentBlend device feature (or your own fragment shader)");
    try {
        *pipeline_.out() = createGraphicsPipeline(renderer.context().device, desc);
    } catch (const Error& e) {
        throw Error(std::string("surface pipeline for a pass of ") + std::to_string(pass.colorFormats.size()) +
                    " colour attachment(s)" + (pass.renderPass ? " (render pass)" : " (dynamic rendering)") + ": " +
                    e.what());
    }
}

Renderer::Renderer(const Context& context, const RendererOptions& options)
    : context_(context), options_(options), mipChain_(context)
{
    const VkDevice device = context.device;
    try {
        drawSetLayout_ = createLevelSetLayout(device, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_VERTEX_BIT);
        drawLayout_ = createPipelineLayout(device, drawSetLayout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                           sizeof(gpu::DrawPushConstants));

        VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        samplerInfo.magFilter = samplerInfo.minFilter = VK_FILTER_NEAREST;
        samplerInfo.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        NGI_VK_CHECK(vkCreateSampler(device, &samplerInfo, nullptr, &sampler_));

        draw_.emplace(*this, options.pass());
        if (options.quadIndexBuffer) createQuadIndices();
    } catch (...) {
        destroy();
        throw;
    }
}

Renderer::~Renderer() { destroy(); }

void Renderer::createQuadIndices()
{
    const VkDeviceSize bytes = VkDeviceSize(NGI_QUADS_PER_CHUNK) * 6 * sizeof(uint16_t);
    quadIndices_ = createBuffer(context_, bytes, VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    const UniqueBuffer staging(context_, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    auto* indices = static_cast<uint16_t*>(staging->mapped);
    for (uint32_t q = 0; q < NGI_QUADS_PER_CHUNK; ++q) {
        const uint16_t base = uint16_t(4 * q);
        const uint16_t quad[6] = {base, uint16_t(base + 1), uint16_t(base + 2), base, uint16_t(base + 2), uint16_t(base + 3)};
        std::copy(quad, quad + 6, indices + 6 * q);
    }
    context_.submitAndWait([&](VkCommandBuffer cmd) {
        const VkBufferCopy copy{0, 0, bytes};
        vkCmdCopyBuffer(cmd, staging->buffer, quadIndices_.buffer, 1, &copy);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_VERTEX_INPUT_BIT, VK_ACCESS_INDEX_READ_BIT);
    });
}

void Renderer::destroy()
{
    const VkDevice device = context_.device;
    destroyBuffer(context_, quadIndices_);
    draw_.reset();
    if (sampler_) vkDestroySampler(device, sampler_, nullptr);
    if (drawLayout_) vkDestroyPipelineLayout(device, drawLayout_, nullptr);
    if (drawSetLayout_) vkDestroyDescriptorSetLayout(device, drawSetLayout_, nullptr);
    sampler_ = VK_NULL_HANDLE;
    drawLayout_ = VK_NULL_HANDLE;
    drawSetLayout_ = VK_NULL_HANDLE;
}

DrawStats Renderer::recordDraw(VkCommandBuffer cmd, const GeometryImageSurface& surface, const DrawParams& params,
                               std::optional<VkExtent2D> extent) const
{
    DrawStats stats;
    if (params.gridSize > 0) {
        stats.level = levelForGridSize(surface.fullSize(), params.gridSize);
        stats.gridSize = params.gridSize;
    } else {
        // Never coarser than the coarsest level whose seams stay closed (surface.h).
        const LodSelection s = selectLod(surface.drawnLevelCount(), surface.fullSize(), params.lod);
        stats.level = s.level;
        stats.morph = s.morph;
        stats.gridSize = s.gridSize;
    }
    stats.triangles = gridTriangleCount(stats.gridSize);

    // The shaders work in the surface's normalized space: fold the instance's object -> world
    // and the asset's normalized -> object matrices into the clip transform, and take the
    // eye back into normalized space (exact for any invertible world matrix).
    gpu::DrawPushConstants pc{};
    if (params.world) {
        const glm::mat4 worldFromNormalized = *params.world * surface.objectFromNormalized();
        pc.viewProjection = params.viewProjection * worldFromNormalized;
        pc.eye = glm::inverse(worldFromNormalized) * glm::vec4(params.eye, 1.0f);
        pc.eye /= pc.eye.w;
    } else {
        pc.viewProjection = params.viewProjection;
        pc.eye = glm::vec4(params.eye, 1.0f);
    }
    pc.gridSize = stats.gridSize;
    pc.levelSize = surface.levelSize(stats.level);
    pc.morph = stats.morph;
    pc.mode = uint32_t(params.mode);
    pc.lod = params.gridSize > 0 ? float(stats.level) : params.lod;
    pc.wireWidth = params.wireWidth;
    pc.quadIndexed = quadIndices_.buffer != VK_NULL_HANDLE;

    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, (params.pipeline ? *params.pipeline : *draw_).pipeline());
    if (params.viewport || extent) {
        const VkViewport viewport = params.viewport.value_or(
            VkViewport{0.0f, 0.0f, float(extent->width), float(extent->height), 0.0f, 1.0f});
        vkCmdSetViewport(cmd, 0, 1, &viewport);
    }
    if (params.scissor || extent) {
        const VkRect2D scissor = params.scissor.value_or(VkRect2D{{0, 0}, *extent});
        vkCmdSetScissor(cmd, 0, 1, &scissor);
    }
    const VkDescriptorSet set = surface.drawSet(stats.level);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, drawLayout_, 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, drawLayout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(pc), &pc);
    const uint64_t quads = stats.triangles / 2;
    stats.vertexInvocations = quads * (pc.quadIndexed ? 4 : 6);
    if (pc.quadIndexed) {
        vkCmdBindIndexBuffer(cmd, quadIndices_.buffer, 0, VK_INDEX_TYPE_UINT16);
        for (uint64_t first = 0; first < quads; first += NGI_QUADS_PER_CHUNK) {
            const uint32_t count = uint32_t(std::min<uint64_t>(NGI_QUADS_PER_CHUNK, quads - first));
            vkCmdDrawIndexed(cmd, 6 * count, 1, 0, int32_t(4 * first), 0);
        }
    } else {
        vkCmdDraw(cmd, uint32_t(6 * quads), 1, 0, 0);
    }
    return stats;
}

} // namespace ngi::vk
