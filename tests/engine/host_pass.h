// Test support: a host engine's pass as a test builds it -- any colour attachments, a depth or
// depth/stencil attachment, dynamic rendering or a classic VkRenderPass -- with read-back of
// colour attachment 0 (RGBA8) and of the depth aspect (D32 formats). Single-sampled.
#pragma once

#include "ngi/engine/context.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"
#include "ngi/engine/vk_check.h"

#include <cstring>
#include <functional>
#include <vector>

namespace ngi::test {

inline bool hasStencil(VkFormat f)
{
    return f == VK_FORMAT_D32_SFLOAT_S8_UINT || f == VK_FORMAT_D24_UNORM_S8_UINT || f == VK_FORMAT_D16_UNORM_S8_UINT ||
        f == VK_FORMAT_S8_UINT;
}

class HostPass {
public:
    // `pass.renderPass` is ignored: with `useRenderPass` this target makes its own render pass
    // (one subpass) and writes it into pass() for the pipeline.
    HostPass(const vk::Context& c, vk::PassDescription pass, uint32_t width, uint32_t height,
             bool useRenderPass = false)
        : c_(c), pass_(std::move(pass)), width_(width), height_(height)
    {
        for (VkFormat f : pass_.colorFormats)
            colors_.emplace_back(c, width, height, f,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT);
        if (pass_.depthFormat != VK_FORMAT_UNDEFINED)
            depth_ = vk::UniqueImage(c, width, height, pass_.depthFormat,
                                     VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                     depthAspects());
        readback_ = vk::UniqueBuffer(c, VkDeviceSize(width) * height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                     VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        pass_.renderPass = VK_NULL_HANDLE;
        if (useRenderPass) createRenderPass();
    }
    ~HostPass()
    {
        if (framebuffer_) vkDestroyFramebuffer(c_.device, framebuffer_, nullptr);
        if (renderPass_) vkDestroyRenderPass(c_.device, renderPass_, nullptr);
    }
    HostPass(const HostPass&) = delete;
    HostPass& operator=(const HostPass&) = delete;

    const vk::PassDescription& pass() const { return pass_; }
    VkExtent2D extent() const { return {width_, height_}; }

    // Clears every attachment (colour to `clear`, depth to `clearDepth`, stencil to 0), runs
    // `draw` inside the pass, reads back colour attachment `readAttachment` (RGBA8) or,
    // without colour, depth. Returns RGBA8 bytes, or 32-bit floats' bytes for depth.
    std::vector<uint8_t> render(const std::function<void(VkCommandBuffer)>& draw, float clearDepth,
                                VkClearColorValue clear = {{0.0f, 0.0f, 0.0f, 1.0f}}, size_t readAttachment = 0)
    {
        c_.submitAndWait([&](VkCommandBuffer cmd) {
            for (auto& img : colors_)
                vk::imageBarrier(cmd, img->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                                 VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                                 VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
            if (depth_)
                vk::imageBarrier(cmd, depth_->image, depthAspects(), VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                                 VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
                                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                     VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
                                 VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
            if (renderPass_) {
                std::vector<VkClearValue> clears(colors_.size());
                for (auto& v : clears) v.color = clear;
                if (depth_) {
                    VkClearValue d{};
                    d.depthStencil = {clearDepth, 0};
                    clears.push_back(d);
                }
                VkRenderPassBeginInfo begin{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
                begin.renderPass = renderPass_;
                begin.framebuffer = framebuffer_;
                begin.renderArea = {{0, 0}, {width_, height_}};
                begin.clearValueCount = uint32_t(clears.size());
                begin.pClearValues = clears.data();
                vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
                draw(cmd);
                vkCmdEndRenderPass(cmd);
            } else {
                std::vector<VkRenderingAttachmentInfo> colorInfos;
                for (auto& img : colors_) {
                    VkRenderingAttachmentInfo a{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
                    a.imageView = img->view;
                    a.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
                    a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
                    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
                    a.clearValue.color = clear;
                    colorInfos.push_back(a);
                }
                VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
                if (depth_) {
                    depthInfo.imageView = depth_->view;
                    depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
                    depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
                    depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
                    depthInfo.clearValue.depthStencil = {clearDepth, 0};
                }
                VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
                rendering.renderArea = {{0, 0}, {width_, height_}};
                rendering.layerCount = 1;
                rendering.colorAttachmentCount = uint32_t(colorInfos.size());
                rendering.pColorAttachments = colorInfos.data();
                rendering.pDepthAttachment = depth_ ? &depthInfo : nullptr;
                rendering.pStencilAttachment = depth_ && hasStencil(pass_.depthFormat) ? &depthInfo : nullptr;
                vkCmdBeginRendering(cmd, &rendering);
                draw(cmd);
                vkCmdEndRendering(cmd);
            }
            const bool readColor = !colors_.empty();
            const VkImage source = readColor ? colors_.at(readAttachment)->image : depth_->image;
            const VkImageAspectFlags aspect = readColor ? VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT)
                                                        : VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT);
            vk::imageBarrier(cmd, source, readColor ? aspect : depthAspects(),
                             VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
                             VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT * readColor |
                                 VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT * !readColor,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                             readColor ? VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL
                                       : VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                             VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
            VkBufferImageCopy copy{};
            copy.imageSubresource = {aspect, 0, 0, 1};
            copy.imageExtent = {width_, height_, 1};
            vkCmdCopyImageToBuffer(cmd, source, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_->buffer, 1, &copy);
            vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                              VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
        });
        std::vector<uint8_t> bytes(size_t(width_) * height_ * 4);
        std::memcpy(bytes.data(), readback_->mapped, bytes.size());
        return bytes;
    }

private:
    VkImageAspectFlags depthAspects() const
    {
        return VK_IMAGE_ASPECT_DEPTH_BIT | (hasStencil(pass_.depthFormat) ? VK_IMAGE_ASPECT_STENCIL_BIT : 0);
    }

    void createRenderPass()
    {
        std::vector<VkAttachmentDescription> attachments;
        std::vector<VkAttachmentReference> colorRefs;
        for (VkFormat f : pass_.colorFormats) {
            colorRefs.push_back({uint32_t(attachments.size()), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
            attachments.push_back({0, f, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_CLEAR,
                                   VK_ATTACHMENT_STORE_OP_STORE, VK_ATTACHMENT_LOAD_OP_DONT_CARE,
                                   VK_ATTACHMENT_STORE_OP_DONT_CARE, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL});
        }
        const VkAttachmentReference depthRef{uint32_t(attachments.size()),
                                             VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
        if (depth_)
            attachments.push_back({0, pass_.depthFormat, VK_SAMPLE_COUNT_1_BIT, VK_ATTACHMENT_LOAD_OP_CLEAR,
                                   VK_ATTACHMENT_STORE_OP_STORE, VK_ATTACHMENT_LOAD_OP_CLEAR,
                                   VK_ATTACHMENT_STORE_OP_STORE, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
                                   VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL});
        VkSubpassDescription subpass{};
        subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
        subpass.colorAttachmentCount = uint32_t(colorRefs.size());
        subpass.pColorAttachments = colorRefs.data();
        subpass.pDepthStencilAttachment = depth_ ? &depthRef : nullptr;
        VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
        info.attachmentCount = uint32_t(attachments.size());
        info.pAttachments = attachments.data();
        info.subpassCount = 1;
        info.pSubpasses = &subpass;
        NGI_VK_CHECK(vkCreateRenderPass(c_.device, &info, nullptr, &renderPass_));
        std::vector<VkImageView> views;
        for (auto& img : colors_) views.push_back(img->view);
        if (depth_) views.push_back(depth_->view);
        VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fb.renderPass = renderPass_;
        fb.attachmentCount = uint32_t(views.size());
        fb.pAttachments = views.data();
        fb.width = width_;
        fb.height = height_;
        fb.layers = 1;
        NGI_VK_CHECK(vkCreateFramebuffer(c_.device, &fb, nullptr, &framebuffer_));
        pass_.renderPass = renderPass_;
        pass_.subpass = 0;
    }

    const vk::Context& c_;
    vk::PassDescription pass_;
    uint32_t width_, height_;
    std::vector<vk::UniqueImage> colors_;
    vk::UniqueImage depth_;
    vk::UniqueBuffer readback_;
    VkRenderPass renderPass_ = VK_NULL_HANDLE;
    VkFramebuffer framebuffer_ = VK_NULL_HANDLE;
};

}  // namespace ngi::test
