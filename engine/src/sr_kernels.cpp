// The super-resolution ops' compute pipelines (shaders/sr_*.comp), all created when the network loads.
#include "sr_kernels.h"

#include "ngi/engine/pipelines.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include "ngi_shaders/sr_attention_comp.h"
#include "ngi_shaders/sr_bilinear_skip_comp.h"
#include "ngi_shaders/sr_conv_comp.h"
#include "ngi_shaders/sr_input_comp.h"
#include "ngi_shaders/sr_output_comp.h"
#include "ngi_shaders/sr_pixel_shuffle_comp.h"

#include <algorithm>
#include <atomic>
#include <span>
#include <thread>
#include <vector>

namespace ngi::vk {

SuperResolution::Kernels::Kernels(const Context& c) : context(c)
{
    const VkShaderStageFlags stage = VK_SHADER_STAGE_COMPUTE_BIT;
    const VkDescriptorSetLayoutBinding bindings[] = {
        {NGI_SR_BINDING_IN0, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, stage, nullptr},
        {NGI_SR_BINDING_IN1, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, stage, nullptr},
        {NGI_SR_BINDING_IN2, VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1, stage, nullptr},
        {NGI_SR_BINDING_OUT, VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 1, stage, nullptr},
        {NGI_SR_BINDING_WEIGHTS, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 1, stage, nullptr},
        {NGI_SR_BINDING_LEVEL, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, stage, nullptr},
        {NGI_SR_BINDING_STORED, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, stage, nullptr},
        {NGI_SR_BINDING_CHECK, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stage, nullptr},
    };
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = uint32_t(std::size(bindings));
    setInfo.pBindings = bindings;
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(c.device, &setInfo, nullptr, &setLayout));
    VkPushConstantRange range{stage, 0, sizeof(gpu::SrPushConstants)};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = 1;
    info.pSetLayouts = &setLayout;
    info.pushConstantRangeCount = 1;
    info.pPushConstantRanges = &range;
    const VkResult r = vkCreatePipelineLayout(c.device, &info, nullptr, &layout);
    if (r < 0) {
        vkDestroyDescriptorSetLayout(c.device, setLayout, nullptr);
        NGI_VK_CHECK(r);
    }
}

SuperResolution::Kernels::~Kernels()
{
    for (auto& [key, p] : pipelines_) vkDestroyPipeline(context.device, p, nullptr);
    vkDestroyPipelineLayout(context.device, layout, nullptr);
    vkDestroyDescriptorSetLayout(context.device, setLayout, nullptr);
}

void SuperResolution::Kernels::create(const std::vector<SrPipelineKey>& keys, VkPipelineCache cache)
{
    std::vector<SrPipelineKey> todo;
    for (const SrPipelineKey& k : keys)
        if (!pipelines_.count(k) && std::find(todo.begin(), todo.end(), k) == todo.end()) todo.push_back(k);
    std::vector<VkPipeline> created(todo.size(), VK_NULL_HANDLE);
    std::vector<VkResult> results(todo.size(), VK_SUCCESS);
    auto compile = [&](size_t i) {
        const SrPipelineKey& key = todo[i];
        std::span<const uint32_t> spirv;
        uint32_t constantCount = 0;
        switch (key.shader) {
        case SrShader::Conv:
            spirv = sr_conv_comp_spv;
            constantCount = 5;
            break;
        case SrShader::Attention:
            spirv = sr_attention_comp_spv;
            constantCount = 3;
            break;
        case SrShader::PixelShuffle:
            spirv = sr_pixel_shuffle_comp_spv;
            constantCount = 1;
            break;
        case SrShader::BilinearSkip:
            spirv = sr_bilinear_skip_comp_spv;
            constantCount = 2;
            break;  // KIND, BLEND
        case SrShader::Input: spirv = sr_input_comp_spv; break;
        case SrShader::Output: spirv = sr_output_comp_spv; break;
        }
        const VkSpecializationMapEntry entries[5] = {{0, 0, 4}, {1, 4, 4}, {2, 8, 4}, {3, 12, 4}, {4, 16, 4}};
        const VkSpecializationInfo specialization{constantCount, entries, sizeof(uint32_t) * constantCount,
                                                  key.constants.data()};
        VkShaderModuleCreateInfo moduleInfo{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        moduleInfo.codeSize = spirv.size_bytes();
        moduleInfo.pCode = spirv.data();
        VkShaderModule module = VK_NULL_HANDLE;
        if ((results[i] = vkCreateShaderModule(context.device, &moduleInfo, nullptr, &module)) < 0) return;
        VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                      nullptr,
                      0,
                      VK_SHADER_STAGE_COMPUTE_BIT,
                      module,
                      "main",
                      constantCount ? &specialization : nullptr};
        info.layout = layout;
        results[i] = vkCreateComputePipelines(context.device, cache, 1, &info, nullptr, &created[i]);
        vkDestroyShaderModule(context.device, module, nullptr);
    };
    // Vulkan lets threads create pipelines on one device concurrently (a pipeline cache is
    // internally synchronized); the largest (conv) pipelines are spread first.
    const size_t threads = std::min<size_t>({todo.size(), 4, std::max(1u, std::thread::hardware_concurrency())});
    std::atomic<size_t> next{0};
    auto worker = [&] {
        for (size_t i; (i = next.fetch_add(1)) < todo.size();) compile(i);
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    VkResult failure = VK_SUCCESS;
    for (size_t i = 0; i < todo.size(); ++i) {
        if (created[i]) pipelines_.emplace(todo[i], created[i]);
        if (results[i] < 0 && failure == VK_SUCCESS) failure = results[i];
    }
    NGI_VK_CHECK(failure);
}

VkPipeline SuperResolution::Kernels::pipeline(const SrPipelineKey& key) const
{
    const auto it = pipelines_.find(key);
    if (it == pipelines_.end()) throw Error("super-resolution: a pipeline was not created with the network");
    return it->second;
}

void SuperResolution::Kernels::dispatch(VkCommandBuffer cmd, VkPipeline p, VkDescriptorSet set, uint32_t weightsOffset,
                                        const gpu::SrPushConstants& push, uint32_t gx, uint32_t gy, uint32_t gz) const
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 1, &weightsOffset);
    vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, gx, gy, gz);
}

}  // namespace ngi::vk
