// Swapchain, render targets, frames in flight, the overlay render pass and frame capture.
#include "presenter.h"

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include <algorithm>
#include <cstring>

namespace ngi::view {
namespace {

template <typename T, typename F> std::vector<T> enumerate(F&& query)
{
    uint32_t count = 0;
    query(&count, nullptr);
    std::vector<T> items(count);
    query(&count, items.data());
    items.resize(count);
    return items;
}

VkRenderPass createOverlayPass(VkDevice device, VkFormat format)
{
    VkAttachmentDescription attachment{};
    attachment.format = format;
    attachment.samples = VK_SAMPLE_COUNT_1_BIT;
    attachment.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;  // the surface drawn by the scene pass
    attachment.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    attachment.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    attachment.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    attachment.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    attachment.finalLayout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    VkAttachmentReference colour{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass{};
    subpass.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    subpass.colorAttachmentCount = 1;
    subpass.pColorAttachments = &colour;
    VkSubpassDependency dependency{};
    dependency.srcSubpass = VK_SUBPASS_EXTERNAL;
    dependency.dstSubpass = 0;
    dependency.srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependency.srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    dependency.dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    dependency.dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    VkRenderPassCreateInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    info.attachmentCount = 1;
    info.pAttachments = &attachment;
    info.subpassCount = 1;
    info.pSubpasses = &subpass;
    info.dependencyCount = 1;
    info.pDependencies = &dependency;
    VkRenderPass pass = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkCreateRenderPass(device, &info, nullptr, &pass));
    return pass;
}

}  // namespace

Presenter::Presenter(const vk::Context& context, VkSurfaceKHR surface, VkExtent2D size, bool vsync,
                     VkSampleCountFlagBits samples)
    : context_(context), device_(context.device), surface_(surface), samples_(samples), vsync_(vsync)
{
    VkBool32 supported = VK_FALSE;
    NGI_VK_CHECK(
        vkGetPhysicalDeviceSurfaceSupportKHR(context.physicalDevice, context.queueFamily, surface, &supported));
    if (!supported)
        throw Error(std::string("the Vulkan device '") + context.properties.deviceName +
                    "' cannot present to this window");
    const auto formats = enumerate<VkSurfaceFormatKHR>([&](uint32_t* n, VkSurfaceFormatKHR* f) {
        NGI_VK_CHECK(vkGetPhysicalDeviceSurfaceFormatsKHR(context.physicalDevice, surface, n, f));
    });
    if (formats.empty()) throw Error("the window surface offers no pixel format");
    format_ = formats[0];
    for (VkFormat wanted : {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM})
        if (auto it = std::find_if(formats.begin(), formats.end(), [&](const auto& f) { return f.format == wanted; });
            it != formats.end()) {
            format_ = *it;
            break;
        }

    const auto families = enumerate<VkQueueFamilyProperties>([&](uint32_t* n, VkQueueFamilyProperties* p) {
        vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice, n, p);
    });
    if (families[context.queueFamily].timestampValidBits > 0 && context.properties.limits.timestampPeriod > 0.0f)
        timestampPeriodNs_ = context.properties.limits.timestampPeriod;

    overlayPass_ = createOverlayPass(device_, format_.format);
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    poolInfo.queueFamilyIndex = context.queueFamily;
    NGI_VK_CHECK(vkCreateCommandPool(device_, &poolInfo, nullptr, &pool_));
    for (Slot& s : slots_) {
        VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        alloc.commandPool = pool_;
        alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        alloc.commandBufferCount = 1;
        NGI_VK_CHECK(vkAllocateCommandBuffers(device_, &alloc, &s.cmd));
        VkFenceCreateInfo fence{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        fence.flags = VK_FENCE_CREATE_SIGNALED_BIT;
        NGI_VK_CHECK(vkCreateFence(device_, &fence, nullptr, &s.done));
        VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        NGI_VK_CHECK(vkCreateSemaphore(device_, &semaphore, nullptr, &s.acquired));
        if (timestamps()) {
            VkQueryPoolCreateInfo query{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
            query.queryType = VK_QUERY_TYPE_TIMESTAMP;
            query.queryCount = 3;
            NGI_VK_CHECK(vkCreateQueryPool(device_, &query, nullptr, &s.queries));
        }
    }
    createSwapchain(size);
}

Presenter::~Presenter()
{
    vkDeviceWaitIdle(device_);
    destroySwapchainResources();
    if (swapchain_) vkDestroySwapchainKHR(device_, swapchain_, nullptr);
    vk::destroyBuffer(context_, readback_);
    for (Slot& s : slots_) {
        if (s.queries) vkDestroyQueryPool(device_, s.queries, nullptr);
        if (s.acquired) vkDestroySemaphore(device_, s.acquired, nullptr);
        if (s.done) vkDestroyFence(device_, s.done, nullptr);
    }
    if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
    if (overlayPass_) vkDestroyRenderPass(device_, overlayPass_, nullptr);
}

const char* Presenter::presentModeName() const { return vsync_ ? "vsync (FIFO)" : "no vsync"; }

void Presenter::setVsync(bool on)
{
    if (on != vsync_) recreate_ = true;
    vsync_ = on;
}

void Presenter::destroySwapchainResources()
{
    for (VkFramebuffer f : framebuffers_) vkDestroyFramebuffer(device_, f, nullptr);
    for (VkImageView v : views_) vkDestroyImageView(device_, v, nullptr);
    for (VkSemaphore s : renderDone_) vkDestroySemaphore(device_, s, nullptr);
    framebuffers_.clear();
    views_.clear();
    renderDone_.clear();
    images_.clear();
    vk::destroyImage(context_, msaaColor_);
    vk::destroyImage(context_, depth_);
}

void Presenter::createSwapchain(VkExtent2D size)
{
    vkDeviceWaitIdle(device_);
    destroySwapchainResources();
    VkSurfaceCapabilitiesKHR caps{};
    NGI_VK_CHECK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(context_.physicalDevice, surface_, &caps));
    extent_ = caps.currentExtent.width != UINT32_MAX
        ? caps.currentExtent
        : VkExtent2D{std::clamp(size.width, caps.minImageExtent.width, caps.maxImageExtent.width),
                     std::clamp(size.height, caps.minImageExtent.height, caps.maxImageExtent.height)};
    const auto modes = enumerate<VkPresentModeKHR>([&](uint32_t* n, VkPresentModeKHR* m) {
        NGI_VK_CHECK(vkGetPhysicalDeviceSurfacePresentModesKHR(context_.physicalDevice, surface_, n, m));
    });
    VkPresentModeKHR mode = VK_PRESENT_MODE_FIFO_KHR;  // always available
    if (!vsync_)
        for (VkPresentModeKHR wanted : {VK_PRESENT_MODE_MAILBOX_KHR, VK_PRESENT_MODE_IMMEDIATE_KHR})
            if (std::find(modes.begin(), modes.end(), wanted) != modes.end()) {
                mode = wanted;
                break;
            }
    minImageCount_ = caps.minImageCount + 1;
    if (caps.maxImageCount > 0) minImageCount_ = std::min(minImageCount_, caps.maxImageCount);
    minImageCount_ = std::max(minImageCount_, 2u);
    canCapture_ = caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT;

    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface_;
    info.minImageCount = minImageCount_;
    info.imageFormat = format_.format;
    info.imageColorSpace = format_.colorSpace;
    info.imageExtent = extent_;
    info.imageArrayLayers = 1;
    info.imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | (canCapture_ ? VK_IMAGE_USAGE_TRANSFER_SRC_BIT : 0);
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    if (!(caps.supportedCompositeAlpha & info.compositeAlpha))
        info.compositeAlpha = VkCompositeAlphaFlagBitsKHR(caps.supportedCompositeAlpha & -caps.supportedCompositeAlpha);
    info.presentMode = mode;
    info.clipped = VK_TRUE;
    info.oldSwapchain = swapchain_;
    VkSwapchainKHR created = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkCreateSwapchainKHR(device_, &info, nullptr, &created));
    if (swapchain_) vkDestroySwapchainKHR(device_, swapchain_, nullptr);
    swapchain_ = created;
    ++generation_;
    recreate_ = false;

    images_ = enumerate<VkImage>(
        [&](uint32_t* n, VkImage* i) { NGI_VK_CHECK(vkGetSwapchainImagesKHR(device_, swapchain_, n, i)); });
    for (VkImage image : images_) {
        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.image = image;
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.format = format_.format;
        view.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        NGI_VK_CHECK(vkCreateImageView(device_, &view, nullptr, &views_.emplace_back()));
        VkFramebufferCreateInfo fb{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
        fb.renderPass = overlayPass_;
        fb.attachmentCount = 1;
        fb.pAttachments = &views_.back();
        fb.width = extent_.width;
        fb.height = extent_.height;
        fb.layers = 1;
        NGI_VK_CHECK(vkCreateFramebuffer(device_, &fb, nullptr, &framebuffers_.emplace_back()));
        VkSemaphoreCreateInfo semaphore{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        NGI_VK_CHECK(vkCreateSemaphore(device_, &semaphore, nullptr, &renderDone_.emplace_back()));
    }
    depth_ = vk::createImage(context_, extent_.width, extent_.height, depthFormat(),
                             VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT, samples_);
    if (samples_ != VK_SAMPLE_COUNT_1_BIT)
        msaaColor_ = vk::createImage(context_, extent_.width, extent_.height, format_.format,
                                     VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
                                     VK_IMAGE_ASPECT_COLOR_BIT, samples_);
}

std::optional<Presenter::Frame> Presenter::begin(VkExtent2D framebufferSize)
{
    if (framebufferSize.width == 0 || framebufferSize.height == 0) return std::nullopt;
    Slot& slot = slots_[nextSlot_];
    NGI_VK_CHECK(vkWaitForFences(device_, 1, &slot.done, VK_TRUE, UINT64_MAX));
    if (slot.submitted && slot.queries) {
        uint64_t ticks[3] = {};
        if (vkGetQueryPoolResults(device_, slot.queries, 0, 3, sizeof(ticks), ticks, sizeof(uint64_t),
                                  VK_QUERY_RESULT_64_BIT) == VK_SUCCESS) {
            gpuTimes_.valid = true;
            gpuTimes_.sceneMs = double(ticks[1] - ticks[0]) * timestampPeriodNs_ * 1e-6;
            gpuTimes_.frameMs = double(ticks[2] - ticks[0]) * timestampPeriodNs_ * 1e-6;
        }
    }
    if (recreate_ || framebufferSize.width != extent_.width || framebufferSize.height != extent_.height)
        createSwapchain(framebufferSize);

    uint32_t image = 0;
    VkResult r = vkAcquireNextImageKHR(device_, swapchain_, UINT64_MAX, slot.acquired, VK_NULL_HANDLE, &image);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        createSwapchain(framebufferSize);
        r = vkAcquireNextImageKHR(device_, swapchain_, UINT64_MAX, slot.acquired, VK_NULL_HANDLE, &image);
        if (r == VK_ERROR_OUT_OF_DATE_KHR) return std::nullopt;  // still resizing: try next frame
    }
    if (r == VK_SUBOPTIMAL_KHR)
        recreate_ = true;  // draw this one, recreate for the next
    else
        NGI_VK_CHECK(r);

    NGI_VK_CHECK(vkResetFences(device_, 1, &slot.done));
    NGI_VK_CHECK(vkResetCommandBuffer(slot.cmd, 0));
    VkCommandBufferBeginInfo beginInfo{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    beginInfo.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    NGI_VK_CHECK(vkBeginCommandBuffer(slot.cmd, &beginInfo));
    if (slot.queries) {
        vkCmdResetQueryPool(slot.cmd, slot.queries, 0, 3);
        vkCmdWriteTimestamp(slot.cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, slot.queries, 0);
    }
    Frame frame{slot.cmd, nextSlot_, image, extent_};
    nextSlot_ = (nextSlot_ + 1) % kFramesInFlight;
    return frame;
}

void Presenter::beginScene(const Frame& frame, glm::vec4 clear)
{
    const VkCommandBuffer cmd = frame.cmd;
    // One depth (and MSAA) target shared by the frames in flight: each frame's first use
    // waits for the previous frame's writes.
    vk::imageBarrier(cmd, images_[frame.image], VK_IMAGE_ASPECT_COLOR_BIT,
                     VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                     VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    const VkPipelineStageFlags depthStages =
        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    vk::imageBarrier(cmd, depth_.image, VK_IMAGE_ASPECT_DEPTH_BIT, depthStages,
                     VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, depthStages,
                     VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                     VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
    if (msaaColor_.image)
        vk::imageBarrier(cmd, msaaColor_.image, VK_IMAGE_ASPECT_COLOR_BIT,
                         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                         VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                         VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);

    VkRenderingAttachmentInfo colour{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    colour.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colour.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    colour.clearValue.color = {{clear.r, clear.g, clear.b, clear.a}};
    if (msaaColor_.image) {
        colour.imageView = msaaColor_.view;
        colour.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        colour.resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT;
        colour.resolveImageView = views_[frame.image];
        colour.resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    } else {
        colour.imageView = views_[frame.image];
        colour.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    }
    VkRenderingAttachmentInfo depth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depth.imageView = depth_.view;
    depth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
    depth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depth.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depth.clearValue.depthStencil = {1.0f, 0};
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, frame.extent};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &colour;
    rendering.pDepthAttachment = &depth;
    vkCmdBeginRendering(cmd, &rendering);
}

void Presenter::endScene(const Frame& frame)
{
    vkCmdEndRendering(frame.cmd);
    if (slots_[frame.slot].queries)
        vkCmdWriteTimestamp(frame.cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, slots_[frame.slot].queries, 1);
}

void Presenter::beginOverlay(const Frame& frame)
{
    VkRenderPassBeginInfo info{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    info.renderPass = overlayPass_;
    info.framebuffer = framebuffers_[frame.image];
    info.renderArea = {{0, 0}, frame.extent};
    vkCmdBeginRenderPass(frame.cmd, &info, VK_SUBPASS_CONTENTS_INLINE);
}

void Presenter::endOverlay(const Frame& frame) { vkCmdEndRenderPass(frame.cmd); }

std::vector<uint8_t> Presenter::end(const Frame& frame, bool capture)
{
    Slot& slot = slots_[frame.slot];
    const VkCommandBuffer cmd = frame.cmd;
    const VkDeviceSize bytes = VkDeviceSize(frame.extent.width) * frame.extent.height * 4;
    if (capture && !canCapture_) capture = false;
    if (capture) {
        if (readback_.size < bytes) {
            vk::destroyBuffer(context_, readback_);
            readback_ = vk::createBuffer(context_, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        }
        vk::imageBarrier(cmd, images_[frame.image], VK_IMAGE_ASPECT_COLOR_BIT,
                         VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                         VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                         VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        VkBufferImageCopy region{};
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {frame.extent.width, frame.extent.height, 1};
        vkCmdCopyImageToBuffer(cmd, images_[frame.image], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback_.buffer, 1,
                               &region);
        vk::imageBarrier(cmd, images_[frame.image], VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_ACCESS_TRANSFER_READ_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0,
                         VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR);
        vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                          VK_ACCESS_HOST_READ_BIT);
    }
    if (slot.queries) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, slot.queries, 2);
    NGI_VK_CHECK(vkEndCommandBuffer(cmd));

    const VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.waitSemaphoreCount = 1;
    submit.pWaitSemaphores = &slot.acquired;
    submit.pWaitDstStageMask = &waitStage;
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    submit.signalSemaphoreCount = 1;
    submit.pSignalSemaphores = &renderDone_[frame.image];
    NGI_VK_CHECK(vkQueueSubmit(context_.queue, 1, &submit, slot.done));
    slot.submitted = true;

    VkPresentInfoKHR present{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    present.waitSemaphoreCount = 1;
    present.pWaitSemaphores = &renderDone_[frame.image];
    present.swapchainCount = 1;
    present.pSwapchains = &swapchain_;
    present.pImageIndices = &frame.image;
    const VkResult r = vkQueuePresentKHR(context_.queue, &present);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR)
        recreate_ = true;
    else
        NGI_VK_CHECK(r);

    std::vector<uint8_t> pixels;
    if (capture) {
        NGI_VK_CHECK(vkWaitForFences(device_, 1, &slot.done, VK_TRUE, UINT64_MAX));
        pixels.resize(bytes);
        std::memcpy(pixels.data(), readback_.mapped, bytes);
        const bool bgra = format_.format == VK_FORMAT_B8G8R8A8_UNORM || format_.format == VK_FORMAT_B8G8R8A8_SRGB;
        for (size_t i = 0; i < pixels.size(); i += 4) {
            if (bgra) std::swap(pixels[i], pixels[i + 2]);
            pixels[i + 3] = 255;
        }
    }
    return pixels;
}

}  // namespace ngi::view
