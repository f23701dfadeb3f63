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

// Whether a shader module may read its input at `location`: true if an Input variable
// decorated with that location is loaded, accessed through a chain, copied, interpolated or
// passed to a function; conservatively true too if such a read Input variable is an
// aggregate (array, matrix, struct, 64-bit vector) at an earlier location, if a block member
// carries a location, or if the module is malformed. Read from the SPIR-V alone; false for
// an empty module.
bool shaderReadsInput(std::span<const uint32_t> spirv, uint32_t location);

VkPipeline createComputePipeline(VkDevice device, VkPipelineLayout layout, std::span<const uint32_t> spirv);

struct GraphicsPipelineDesc {
    std::span<const uint32_t> vertexSpirv;
    std::span<const uint32_t> fragmentSpirv;  // empty: no fragment stage (depth-only passes)
    // Values of the vertex stage's 32-bit specialization constants 0, 1, ... (constant_id = i).
    std::vector<uint32_t> vertexConstants;
    // The same for the fragment stage's.
    std::vector<uint32_t> fragmentConstants;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    PassDescription pass;  // formats, depth/stencil state, render pass
    // Colour attachments 1.. get write mask 0 (a fragment shader writing location 0 only);
    // needs the independentBlend feature when there are several. Else every attachment is written.
    bool writeFirstAttachmentOnly = false;
    // Empty for ngi's own buffer-less grid draw; set for an ordinary vertex-buffer mesh.
    std::vector<VkVertexInputBindingDescription> vertexBindings;
    std::vector<VkVertexInputAttributeDescription> vertexAttributes;
};

// Triangle lists, no culling (cut surfaces are two-sided), the pass's depth/stencil state
// (depth test when it has a depth format), dynamic viewport and scissor (and depth bias when
// asked), no blending; dynamic rendering with the pass's formats, or the pass's render pass
// and subpass.
VkPipeline createGraphicsPipeline(VkDevice device, const GraphicsPipelineDesc& desc);

}  // namespace ngi::vk
