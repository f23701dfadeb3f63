// Offscreen colour/depth target with read-back.
#include "ngi/engine/offscreen.h"

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include <cstring>

namespace ngi::vk {

OffscreenTarget::OffscreenTarget(const Renderer& renderer, uint32_t width, uint32_t height)
    : renderer_(renderer), width_(width), height_(height)
{
    const Context& c = renderer.context();
    const RendererOptions& o = renderer.options();
    if (o.colorFormat != VK_FORMAT_R8G8B8A8_UNORM && o.colorFormat != VK_FORMAT_R8G8B8A8_SRGB)
        throw Error("offscreen target: colour format must be RGBA8");
    const uint32_t limit = c.properties.limits.maxFramebufferWidth;
    if (width == 0 || height == 0 || width > limit || height > c.properties.limits.maxFramebufferHeight)
        throw Error("offscreen target: size " + std::to_string(width) + "x" + std::to_string(height) +
                    " is outside this device's framebuffer limits");
    const bool msaa = o.samples != VK_SAMPLE_COUNT_1_BIT;
    color_ = UniqueImage(c, width, height, o.colorFormat,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | (msaa ? 0 : VK_IMAGE_USAGE_TRANSFER_SRC_BIT),
                         VK_IMAGE_ASPECT_COLOR_BIT, o.samples);
    if (msaa)
        resolve_ = UniqueImage(c, width, height, o.colorFormat,
                               VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                               VK_IMAGE_ASPECT_COLOR_BIT);
    depth_ = UniqueImage(c, width, height, o.depthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                         VK_IMAGE_ASPECT_DEPTH_BIT, o.samples);
    readback_ = UniqueBuffer(c, VkDeviceSize(width) * height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                             VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
}

std::vector<uint8_t> OffscreenTarget::render(const std::function<void(VkCommandBuffer)>& draw, glm::vec4 clear,
                                             const std::function<void(VkCommandBuffer)>& beforeRendering)
{
    const Context& c = renderer_.context();
    const bool msaa = bool(resolve_);
    const Image& output = msaa ? *resolve_ : *color_;
    c.submitAndWait([&](VkCommandBuffer cmd) {
        if (beforeRendering) beforeRendering(cmd);
        imageBarrier(cmd, color_->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                     VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                     VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        if (msaa)
            imageBarrier(cmd, resolve_->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                         VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        imageBarrier(cmd, depth_->image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                     VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
                     VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
                     VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);

        VkRenderingAttachmentInfo colorAttachment{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        colorAttachment.imageView = color_->view;
        colorAttachment.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        colorAttachment.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        colorAttachment.storeOp = msaa ? VK_ATTACHMENT_STORE_OP_DONT_CARE : VK_ATTACHMENT_STORE_OP_STORE;
        colorAttachment.clearValue.color = {{clear.r, clear.g, clear.b, clear.a}};
        if (msaa) {
            colorAttachment.resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT;
            colorAttachment.resolveImageView = resolve_->view;
            colorAttachment.resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        }
        VkRenderingAttachmentInfo depthAttachment{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depthAttachment.imageView = depth_->view;
        depthAttachment.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        depthAttachment.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depthAttachment.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        depthAttachment.clearValue.depthStencil = {1.0f, 0};
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, {width_, height_}};
        rendering.layerCount = 1;
        rendering.colorAttachmentCount = 1;
        rendering.pColorAttachments = &colorAttachment;
        rendering.pDepthAttachment = &depthAttachment;
        vkCmdBeginRendering(cmd, &rendering);
        draw(cmd);
        vkCmdEndRendering(cmd);

        imageBarrier(cmd, output.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                     VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {width_, height_, 1};
        vkCmdCopyImageToBuffer(cmd, output.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_->buffer, 1, &copy);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                      VK_ACCESS_HOST_READ_BIT);
    });
    std::vector<uint8_t> pixels(size_t(width_) * height_ * 4);
    std::memcpy(pixels.data(), readback_->mapped, pixels.size());
    return pixels;
}

}  // namespace ngi::vk
