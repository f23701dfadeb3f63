// The geometry image as a flat picture.
#include "flat_image.h"

#include "ngi/engine/pipelines.h"
#include "ngi/engine/vk_check.h"
#include "ngi/octahedral.h"

#include "ngi_view_shaders/flat_image_frag.h"
#include "ngi_view_shaders/flat_image_vert.h"

#include <glm/vec4.hpp>

#include <algorithm>
#include <cstring>

namespace ngi::view {

FlatImageView::FlatImageView(const vk::Renderer& renderer)
    : renderer_(renderer), setLayout_(renderer.context().device), layout_(renderer.context().device),
      pipeline_(renderer.context().device), sampler_(renderer.context().device), pool_(renderer.context().device)
{
    const VkDevice device = renderer.context().device;
    VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT,
                                         nullptr};
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = 1;
    setInfo.pBindings = &binding;
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, setLayout_.out()));
    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(glm::vec4)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = 1;
    const VkDescriptorSetLayout setLayouts[] = {setLayout_.get()};
    layoutInfo.pSetLayouts = setLayouts;
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    NGI_VK_CHECK(vkCreatePipelineLayout(device, &layoutInfo, nullptr, layout_.out()));
    vk::GraphicsPipelineDesc desc;
    desc.vertexSpirv = flat_image_vert_spv;
    desc.fragmentSpirv = flat_image_frag_spv;
    desc.layout = layout_.get();
    desc.pass = renderer.options().pass();
    *pipeline_.out() = vk::createGraphicsPipeline(device, desc);

    VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    samplerInfo.magFilter = samplerInfo.minFilter = VK_FILTER_NEAREST;
    samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW =
        VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    NGI_VK_CHECK(vkCreateSampler(device, &samplerInfo, nullptr, sampler_.out()));
    VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &poolSize;
    NGI_VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, pool_.out()));
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = pool_.get();
    alloc.descriptorSetCount = 1;
    alloc.pSetLayouts = setLayouts;
    NGI_VK_CHECK(vkAllocateDescriptorSets(device, &alloc, &set_));
}

FlatImageView::~FlatImageView()
{
    const vk::Context& context = renderer_.context();
    vkDeviceWaitIdle(context.device);  // frames in flight may still draw the picture; the owners free it next
}

void FlatImageView::show(const vk::GeometryImageSurface& surface, uint64_t generation, uint32_t level,
                         FlatChannel channel)
{
    level = std::min(level, surface.levelCount() - 1);
    if (generation == shownGeneration_ && level == shownLevel_ && channel == shownChannel_ && texture_) return;
    const vk::Context& context = renderer_.context();
    const uint32_t size = surface.levelSize(level);
    const std::vector<glm::uvec4> texels = surface.readLevel(level, false);
    std::vector<uint8_t> rgba(size_t(size) * size * 4);
    for (size_t i = 0; i < texels.size(); ++i) {
        glm::vec3 c;
        if (channel == FlatChannel::Positions) {
            std::memcpy(&c.x, &texels[i].x, 4);
            std::memcpy(&c.y, &texels[i].y, 4);
            std::memcpy(&c.z, &texels[i].z, 4);
        } else {
            c = unpackNormalOctahedral(texels[i].w) * 0.5f + 0.5f;
        }
        for (int k = 0; k < 3; ++k) rgba[i * 4 + k] = uint8_t(std::clamp(c[k], 0.0f, 1.0f) * 255.0f + 0.5f);
        rgba[i * 4 + 3] = 255;
    }

    vkDeviceWaitIdle(context.device);  // the previous picture may still be drawn by frames in flight
    if (texture_->width != size) {
        texture_.reset();
        texture_ =
            vk::UniqueImage(context, size, size, VK_FORMAT_R8G8B8A8_UNORM,
                            VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    }
    const vk::UniqueBuffer staging(context, rgba.size(), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                   VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    std::memcpy(staging->mapped, rgba.data(), rgba.size());
    context.submitAndWait([&](VkCommandBuffer cmd) {
        vk::imageBarrier(cmd, texture_->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {size, size, 1};
        vkCmdCopyBufferToImage(cmd, staging->buffer, texture_->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        vk::imageBarrier(cmd, texture_->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    });

    VkDescriptorImageInfo image{sampler_.get(), texture_->view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = set_;
    write.dstBinding = 0;
    write.descriptorCount = 1;
    write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    write.pImageInfo = &image;
    vkUpdateDescriptorSets(context.device, 1, &write, 0, nullptr);
    shownGeneration_ = generation;
    shownLevel_ = level;
    shownChannel_ = channel;
}

void FlatImageView::record(VkCommandBuffer cmd, VkExtent2D extent, float leftMargin) const
{
    if (!texture_) return;
    const float w = float(extent.width), h = float(extent.height);
    const float regionW = std::max(w - leftMargin, 1.0f);
    const float side = 0.9f * std::min(regionW, h);
    const float cx = leftMargin + 0.5f * regionW, cy = 0.5f * h;
    // Pixel rectangle -> NDC (Vulkan: y down). Row 0 of the image (v = 0) at the top.
    const glm::vec4 rect((cx - side / 2) / w * 2 - 1, (cy - side / 2) / h * 2 - 1, (cx + side / 2) / w * 2 - 1,
                         (cy + side / 2) / h * 2 - 1);
    const VkViewport viewport{0.0f, 0.0f, w, h, 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline_.get());
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, layout_.get(), 0, 1, &set_, 0, nullptr);
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(rect), &rect);
    vkCmdDraw(cmd, 6, 1, 0, 0);
}

}  // namespace ngi::view
