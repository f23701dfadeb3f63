// ngi engine: the mip-chain compute pipelines (see mip_chain.h). Nested mip levels after Gu,
// Gortler and Hoppe 2002 ("Geometry images"): level L + 1 = the even samples of level L.
#include "ngi/engine/mip_chain.h"

#include "ngi/engine/pipelines.h"
#include "ngi/engine/vk_check.h"
#include "ngi_shared.h"

#include "ngi_shaders/mip_downsample_comp.h"
#include "ngi_shaders/mip_upsample_comp.h"
#include "ngi_shaders/mip_cubic_restore_comp.h"
#include "ngi_shaders/morph_targets_comp.h"
#include "ngi_shaders/quad_diagonals_comp.h"
#include "ngi_shaders/seam_weld_comp.h"
#include "ngi_shaders/seam_weld_group_comp.h"

#include <array>

namespace ngi::vk {

VkDescriptorSetLayout createLevelSetLayout(VkDevice device, VkDescriptorType type, VkShaderStageFlags stages)
{
    // Compute passes that need fewer than three images leave the rest unwritten; they never
    // access them.
    std::array<VkDescriptorSetLayoutBinding, 3> bindings{};
    for (uint32_t i = 0; i < 3; ++i) bindings[i] = {i, type, 1, stages, nullptr};
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = uint32_t(bindings.size());
    info.pBindings = bindings.data();
    VkDescriptorSetLayout layout = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &info, nullptr, &layout));
    return layout;
}

VkPipelineLayout createPipelineLayout(VkDevice device, VkDescriptorSetLayout set, VkShaderStageFlags stages,
                                      uint32_t size)
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

MipChainPipelines::MipChainPipelines(const Context& context)
    : setLayout_(context.device), weldSetLayout_(context.device), groupWeldSetLayout_(context.device),
      layout_(context.device), weldLayout_(context.device), groupWeldLayout_(context.device),
      downsample_(context.device), upsample_(context.device), cubicRestore_(context.device), morph_(context.device),
      quadDiagonals_(context.device), weld_(context.device), groupWeld_(context.device)
{
    const VkDevice device = context.device;
    *setLayout_.out() = createLevelSetLayout(device, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, VK_SHADER_STAGE_COMPUTE_BIT);
    *layout_.out() =
        createPipelineLayout(device, setLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, sizeof(gpu::MipPushConstants));
    *downsample_.out() = createComputePipeline(device, layout_.get(), mip_downsample_comp_spv);
    *upsample_.out() = createComputePipeline(device, layout_.get(), mip_upsample_comp_spv);
    *cubicRestore_.out() = createComputePipeline(device, layout_.get(), mip_cubic_restore_comp_spv);
    *morph_.out() = createComputePipeline(device, layout_.get(), morph_targets_comp_spv);
    *quadDiagonals_.out() = createComputePipeline(device, layout_.get(), quad_diagonals_comp_spv);

    const std::array<VkDescriptorSetLayoutBinding, 2> weldBindings{{
        {0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
    }};
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = uint32_t(weldBindings.size());
    info.pBindings = weldBindings.data();
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &info, nullptr, weldSetLayout_.out()));
    *weldLayout_.out() = createPipelineLayout(device, weldSetLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT,
                                              sizeof(gpu::SeamWeldPushConstants));
    *weld_.out() = createComputePipeline(device, weldLayout_.get(), seam_weld_comp_spv);

    const std::array<VkDescriptorSetLayoutBinding, 3> groupBindings{{
        {0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
    }};
    info.bindingCount = uint32_t(groupBindings.size());
    info.pBindings = groupBindings.data();
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &info, nullptr, groupWeldSetLayout_.out()));
    *groupWeldLayout_.out() = createPipelineLayout(device, groupWeldSetLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT,
                                                   sizeof(gpu::GroupWeldPushConstants));
    *groupWeld_.out() = createComputePipeline(device, groupWeldLayout_.get(), seam_weld_group_comp_spv);
}

}  // namespace ngi::vk
