// ngi engine: shader modules and pipelines from embedded SPIR-V (one place that knows the
// fixed-function state ngi draws with).
#pragma once

#include "ngi/engine/renderer.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <vector>

namespace ngi::vk {

VkShaderModule createShaderModule(VkDevice device, std::span<const uint32_t> spirv);

VkPipeline createComputePipeline(VkDevice device, VkPipelineLayout layout, std::span<const uint32_t> spirv);

struct GraphicsPipelineDesc {
    std::span<const uint32_t> vertexSpirv;
    std::span<const uint32_t> fragmentSpirv;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    RendererOptions formats;
    // Empty for ngi's own buffer-less grid draw; set for an ordinary vertex-buffer mesh.
    std::vector<VkVertexInputBindingDescription> vertexBindings;
    std::vector<VkVertexInputAttributeDescription> vertexAttributes;
};

// Triangle lists, no culling (cut surfaces are two-sided), depth test less-or-equal, dynamic
// viewport and scissor, dynamic rendering with the given formats.
VkPipeline createGraphicsPipeline(VkDevice device, const GraphicsPipelineDesc& desc);

} // namespace ngi::vk
