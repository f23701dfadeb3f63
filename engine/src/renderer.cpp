// Pipelines for the GPU mip chain and the any-LoD grid draw.
#include "ngi/engine/renderer.h"

#include "ngi/engine/pipelines.h"
#include "ngi/engine/surface.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi_shared.h"

#include "ngi_shaders/mip_downsample_comp.h"
#include "ngi_shaders/mip_upsample_comp.h"
#include "ngi_shaders/morph_targets_comp.h"
#include "ngi_shaders/quad_diagonals_comp.h"
#include "ngi_shaders/surface_frag.h"
#include "ngi_shaders/surface_vert.h"

#include <array>
#include <span>

namespace ngi::vk {
namespace {

VkDescriptorSetLayout createSetLayout(VkDevice device, VkDescriptorType type, VkShaderStageFlags stages)
{
    // Three images: a level, its geomorph targets, its quad diagonals (compute passes that
    // need fewer leave the rest unwritten; they never access them).
    std::array<VkDescriptorSetLayoutBinding, 3> bindings{};
    for (uint32_t i = 0; i < 3; ++i) bindings[i] = {i, type, 1, stages, nullptr};
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = uint32_t(bindings.size());
    info.pBindings = bindings.data();
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &info, nullptr, &layout));
    return layout;
}

VkPipelineLayout createPipelineLayout(VkDevice device, VkDescriptorSetLayout set, VkShaderStageFlags stages, uint32_t size)
{
    VkPushConstantRange range{stages, 0, size};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = 1;
    info.pSetLayouts = &set;
    info.pushConstantRangeCount = 1;
    info.pPushConstantRanges = &range;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkCreatePipelineLayout(device, &info, nullptr, &layout));
    return layout;
}

} // namespace

ShadingMode parseShadingMode(const std::string& name)
{
    if (name == "shaded") return ShadingMode::Shaded;
    if (name == "normals") return ShadingMode::Normals;
    if (name == "wireframe") return ShadingMode::Wireframe;
    if (name == "lod") return ShadingMode::Lod;
    throw Error("unknown shading mode '" + name + "' (valid: shaded, normals, wireframe, lod)");
}

Renderer::Renderer(const Context& context, const RendererOptions& options) : context_(context), options_(options)
{
    const VkDevice device = context.device;
    try {
        computeSetLayout_ = createSetLayout(device, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT);
        drawSetLayout_ = createSetLayout(device, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_SHADER_STAGE_VERTEX_BIT);
        computeLayout_ = createPipelineLayout(device, computeSetLayout_, VK_SHADER_STAGE_COMPUTE_BIT, sizeof(gpu::MipPushConstants));
        drawLayout_ = createPipelineLayout(device, drawSetLayout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                           sizeof(gpu::DrawPushConstants));
        downsample_ = createComputePipeline(device, computeLayout_, mip_downsample_comp_spv);
        upsample_ = createComputePipeline(device, computeLayout_, mip_upsample_comp_spv);
        morph_ = createComputePipeline(device, computeLayout_, morph_targets_comp_spv);
        quadDiagonals_ = createComputePipeline(device, computeLayout_, quad_diagonals_comp_spv);

        VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        samplerInfo.magFilter = samplerInfo.minFilter = VK_FILTER_NEAREST;
        samplerInfo.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        NGI_VK_CHECK(vkCreateSampler(device, &samplerInfo, nullptr, &sampler_));

        GraphicsPipelineDesc desc;
        desc.vertexSpirv = surface_vert_spv;
        desc.fragmentSpirv = surface_frag_spv;
        desc.layout = drawLayout_;
        desc.formats = options;
        draw_ = createGraphicsPipeline(device, desc);
    } catch (...) {
        destroy();
        throw;
    }
}

Renderer::~Renderer() { destroy(); }

void Renderer::destroy()
{
    const VkDevice device = context_.device;
    for (VkPipeline p : {draw_, quadDiagonals_, morph_, upsample_, downsample_})
        if (p) vkDestroyPipeline(device, p, nullptr);
    if (sampler_) vkDestroySampler(device, sampler_, nullptr);
    if (drawLayout_) vkDestroyPipelineLayout(device, drawLayout_, nullptr);
    if (computeLayout_) vkDestroyPipelineLayout(device, computeLayout_, nullptr);
    if (drawSetLayout_) vkDestroyDescriptorSetLayout(device, drawSetLayout_, nullptr);
    if (computeSetLayout_) vkDestroyDescriptorSetLayout(device, computeSetLayout_, nullptr);
    draw_ = quadDiagonals_ = morph_ = upsample_ = downsample_ = VK_NULL_HANDLE;
    sampler_ = VK_NULL_HANDLE;
    drawLayout_ = computeLayout_ = VK_NULL_HANDLE;
    drawSetLayout_ = computeSetLayout_ = VK_NULL_HANDLE;
}

DrawStats Renderer::recordDraw(VkCommandBuffer cmd, const GeometryImageSurface& surface, const DrawParams& params,
                               VkExtent2D extent) const
{
    DrawStats stats;
    if (params.gridSize > 0) {
        stats.level = levelForGridSize(surface.fullSize(), params.gridSize);
        stats.gridSize = params.gridSize;
    } else {
        const LodSelection s = selectLod(surface.levelCount(), surface.fullSize(), params.lod);
        stats.level = s.level;
        stats.morph = s.morph;
        stats.gridSize = s.gridSize;
    }
    stats.triangles = gridTriangleCount(stats.gridSize);

    gpu::DrawPushConstants pc{};
    pc.viewProjection = params.viewProjection;
    pc.eye = glm::vec4(params.eye, 1.0f);
    pc.gridSize = stats.gridSize;
    pc.levelSize = surface.levelSize(stats.level);
    pc.morph = stats.morph;
    pc.mode = uint32_t(params.mode);
    pc.lod = params.gridSize > 0 ? float(stats.level) : params.lod;
    pc.wireWidth = params.wireWidth;

    const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, draw_);
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    const VkDescriptorSet set = surface.drawSet(stats.level);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, drawLayout_, 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, drawLayout_, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(pc), &pc);
    const uint64_t vertices = stats.triangles * 3;
    vkCmdDraw(cmd, uint32_t(vertices), 1, 0, 0);
    return stats;
}

} // namespace ngi::vk
