// Shader modules and pipelines from embedded SPIR-V.
#include "ngi/engine/pipelines.h"

#include "ngi/engine/vk_check.h"

#include <vector>

namespace ngi::vk {

VkShaderModule createShaderModule(VkDevice device, std::span<const uint32_t> spirv)
{
    VkShaderModuleCreateInfo info{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    info.codeSize = spirv.size_bytes();
    info.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkCreateShaderModule(device, &info, nullptr, &module));
    return module;
}

bool shaderReadsInput(std::span<const uint32_t> spirv, uint32_t location)
{
    // SPIR-V 1.6 specification, section 2.3 (physical layout) and 3.32 (opcodes).
    constexpr uint32_t opExtInst = 12, opTypeBool = 20, opTypeInt = 21, opTypeFloat = 22, opTypeVector = 23,
                       opTypePointer = 32, opFunctionCall = 57, opVariable = 59, opLoad = 61, opCopyMemory = 63,
                       opAccessChain = 65, opInBoundsAccessChain = 66, opPtrAccessChain = 67, opDecorate = 71,
                       opMemberDecorate = 72, opCopyMemorySized = 64;
    constexpr uint32_t decorationLocation = 30, storageInput = 1;
    if (spirv.size() < 5) return false;
    std::vector<uint32_t> locationOf(spirv[3], UINT32_MAX);  // id bound: spirv[3]
    std::vector<bool> simple(spirv[3], false), input(spirv[3], false);
    std::vector<uint32_t> pointee(spirv[3], 0);
    std::vector<bool> used(spirv[3], false);
    bool memberLocation = false;
    auto valid = [&](uint32_t id) { return id < spirv[3]; };
    for (size_t i = 5; i < spirv.size();) {
        const uint32_t count = spirv[i] >> 16, op = spirv[i] & 0xffff;
        if (count == 0 || i + count > spirv.size()) return true;  // malformed: assume it reads
        const uint32_t* w = &spirv[i];
        if (op == opDecorate && count >= 4 && w[2] == decorationLocation && valid(w[1])) locationOf[w[1]] = w[3];
        if (op == opMemberDecorate && count >= 5 && w[3] == decorationLocation) memberLocation = true;
        // One location each: 32-bit scalars and vectors of them (a 64-bit vector may take two).
        if (op == opTypeBool && valid(w[1])) simple[w[1]] = true;
        if ((op == opTypeInt || op == opTypeFloat) && count >= 3 && valid(w[1])) simple[w[1]] = w[2] <= 32;
        if (op == opTypeVector && count >= 3 && valid(w[1]) && valid(w[2])) simple[w[1]] = simple[w[2]];
        if (op == opTypePointer && count >= 4 && valid(w[1])) pointee[w[1]] = w[3];
        if (op == opVariable && count >= 4 && w[3] == storageInput && valid(w[2]) && valid(w[1])) {
            input[w[2]] = true;
            pointee[w[2]] = pointee[w[1]];
        }
        // Pointer operands of the instructions that read through a pointer.
        auto mark = [&](size_t from, size_t to) {
            for (size_t k = from; k < to && k < count; ++k)
                if (valid(w[k])) used[w[k]] = true;
        };
        if (op == opLoad) mark(3, 4);
        if (op == opAccessChain || op == opInBoundsAccessChain || op == opPtrAccessChain) mark(3, 4);
        if (op == opCopyMemory || op == opCopyMemorySized) mark(2, 3);
        if (op == opExtInst) mark(5, count);       // InterpolateAt* take the input's pointer
        if (op == opFunctionCall) mark(4, count);  // a pointer argument
        i += count;
    }
    if (memberLocation) return true;
    for (uint32_t id = 0; id < spirv[3]; ++id) {
        if (!input[id] || locationOf[id] == UINT32_MAX) continue;
        if (locationOf[id] == location && used[id]) return true;
        // An aggregate (array, matrix, struct, 64-bit vector) may span several locations from its own.
        if (locationOf[id] < location && !(valid(pointee[id]) && simple[pointee[id]]) && used[id]) return true;
    }
    return false;
}

VkPipeline createComputePipeline(VkDevice device, VkPipelineLayout layout, std::span<const uint32_t> spirv)
{
    VkShaderModule module = createShaderModule(device, spirv);
    VkComputePipelineCreateInfo info{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    info.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                  nullptr,
                  0,
                  VK_SHADER_STAGE_COMPUTE_BIT,
                  module,
                  "main",
                  nullptr};
    info.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    const VkResult r = vkCreateComputePipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
    vkDestroyShaderModule(device, module, nullptr);
    NGI_VK_CHECK(r);
    return pipeline;
}

VkPipeline createGraphicsPipeline(VkDevice device, const GraphicsPipelineDesc& desc)
{
    const PassDescription& pass = desc.pass;
    VkPipeline pipeline = VK_NULL_HANDLE;
    std::vector<VkPipelineShaderStageCreateInfo> stages;
    VkShaderModule vert = createShaderModule(device, desc.vertexSpirv);
    VkShaderModule frag = VK_NULL_HANDLE;
    std::vector<VkSpecializationMapEntry> entries;
    for (uint32_t i = 0; i < desc.vertexConstants.size(); ++i) entries.push_back({i, i * 4, 4});
    const VkSpecializationInfo specialization{uint32_t(entries.size()), entries.data(),
                                              desc.vertexConstants.size() * sizeof(uint32_t),
                                              desc.vertexConstants.data()};
    stages.push_back({VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_VERTEX_BIT, vert,
                      "main", entries.empty() ? nullptr : &specialization});
    std::vector<VkSpecializationMapEntry> fragmentEntries;
    for (uint32_t i = 0; i < desc.fragmentConstants.size(); ++i) fragmentEntries.push_back({i, i * 4, 4});
    const VkSpecializationInfo fragmentSpecialization{uint32_t(fragmentEntries.size()), fragmentEntries.data(),
                                                      desc.fragmentConstants.size() * sizeof(uint32_t),
                                                      desc.fragmentConstants.data()};
    if (!desc.fragmentSpirv.empty()) {
        try {
            frag = createShaderModule(device, desc.fragmentSpirv);
        } catch (...) {
            vkDestroyShaderModule(device, vert, nullptr);
            throw;
        }
        stages.push_back({VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_FRAGMENT_BIT,
                          frag, "main", fragmentEntries.empty() ? nullptr : &fragmentSpecialization});
    }
    VkPipelineVertexInputStateCreateInfo vertexInput{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
    vertexInput.vertexBindingDescriptionCount = uint32_t(desc.vertexBindings.size());
    vertexInput.pVertexBindingDescriptions = desc.vertexBindings.data();
    vertexInput.vertexAttributeDescriptionCount = uint32_t(desc.vertexAttributes.size());
    vertexInput.pVertexAttributeDescriptions = desc.vertexAttributes.data();
    VkPipelineInputAssemblyStateCreateInfo assembly{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
    assembly.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
    VkPipelineViewportStateCreateInfo viewport{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
    viewport.viewportCount = 1;
    viewport.scissorCount = 1;
    VkPipelineRasterizationStateCreateInfo raster{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
    raster.polygonMode = VK_POLYGON_MODE_FILL;
    raster.cullMode = VK_CULL_MODE_NONE;  // cut-open surfaces are seen from both sides
    raster.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
    raster.depthBiasEnable = pass.dynamicDepthBias;
    raster.lineWidth = 1.0f;
    VkPipelineMultisampleStateCreateInfo multisample{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
    multisample.rasterizationSamples = pass.samples;
    VkPipelineDepthStencilStateCreateInfo depth{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
    depth.depthTestEnable = pass.depthFormat != VK_FORMAT_UNDEFINED;
    depth.depthWriteEnable = depth.depthTestEnable && pass.depthWrite;
    depth.depthCompareOp = pass.depthCompare;
    if (pass.stencil) {
        depth.stencilTestEnable = VK_TRUE;
        depth.front = depth.back = *pass.stencil;
    }
    // With writeFirstAttachmentOnly, attachments 1.. keep what the host wrote (a write mask
    // of 0 also tells the validation layer that the shader writes nothing there).
    std::vector<VkPipelineColorBlendAttachmentState> blendAttachments(pass.colorFormats.size());
    for (size_t i = 0; i < blendAttachments.size(); ++i)
        if (i == 0 || !desc.writeFirstAttachmentOnly)
            blendAttachments[i].colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
    VkPipelineColorBlendStateCreateInfo blend{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
    blend.attachmentCount = uint32_t(blendAttachments.size());
    blend.pAttachments = blendAttachments.data();
    std::vector<VkDynamicState> dynamicStates{VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
    if (pass.dynamicDepthBias) dynamicStates.push_back(VK_DYNAMIC_STATE_DEPTH_BIAS);
    VkPipelineDynamicStateCreateInfo dynamic{VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO};
    dynamic.dynamicStateCount = uint32_t(dynamicStates.size());
    dynamic.pDynamicStates = dynamicStates.data();
    VkPipelineRenderingCreateInfo rendering{VK_STRUCTURE_TYPE_PIPELINE_RENDERING_CREATE_INFO};
    rendering.colorAttachmentCount = uint32_t(pass.colorFormats.size());
    rendering.pColorAttachmentFormats = pass.colorFormats.data();
    rendering.depthAttachmentFormat = pass.depthFormat;
    rendering.stencilAttachmentFormat = pass.stencilFormat;
    VkGraphicsPipelineCreateInfo info{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
    info.pNext = pass.renderPass ? nullptr : &rendering;
    info.renderPass = pass.renderPass;
    info.subpass = pass.subpass;
    info.stageCount = uint32_t(stages.size());
    info.pStages = stages.data();
    info.pVertexInputState = &vertexInput;
    info.pInputAssemblyState = &assembly;
    info.pViewportState = &viewport;
    info.pRasterizationState = &raster;
    info.pMultisampleState = &multisample;
    info.pDepthStencilState = &depth;
    info.pColorBlendState = &blend;
    info.pDynamicState = &dynamic;
    info.layout = desc.layout;
    const VkResult r = vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &info, nullptr, &pipeline);
    vkDestroyShaderModule(device, vert, nullptr);
    if (frag) vkDestroyShaderModule(device, frag, nullptr);
    NGI_VK_CHECK(r);
    return pipeline;
}

}  // namespace ngi::vk
