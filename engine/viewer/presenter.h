// ngi-view: getting frames onto the window. Owns the swapchain (recreated on resize,
// minimize, out-of-date and vsync changes), the depth and MSAA targets the surface is drawn
// into, the frames in flight (command buffer, fence, semaphores, GPU timestamps) and the
// overlay render pass Dear ImGui 1.86 needs (it cannot use dynamic rendering).
//
// A frame: begin() -> beginScene() .. the surface draw (dynamic rendering) .. endScene()
// -> beginOverlay() .. ImGui .. endOverlay() -> end(), which submits, presents and, when
// asked, returns the finished image (scene + overlay) as RGBA8.
#pragma once

#include "ngi/engine/context.h"
#include "ngi/engine/resources.h"

#include <glm/vec4.hpp>
#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace ngi::view {

struct GpuFrameTimes {
    bool valid = false;
    double sceneMs = 0.0;  // the surface pass (dynamic rendering)
    double frameMs = 0.0;  // the whole command buffer: scene + overlay
};

class Presenter {
public:
    static constexpr uint32_t kFramesInFlight = 2;

    // Picks a B8G8R8A8/R8G8B8A8 UNORM surface format (the same colours ngi-render writes),
    // creates the swapchain for `size`. ngi::Error when the surface cannot be used.
    Presenter(const vk::Context& context, VkSurfaceKHR surface, VkExtent2D size, bool vsync,
              VkSampleCountFlagBits samples);
    ~Presenter();
    Presenter(const Presenter&) = delete;
    Presenter& operator=(const Presenter&) = delete;

    VkFormat colorFormat() const { return format_.format; }
    VkFormat depthFormat() const { return VK_FORMAT_D32_SFLOAT; }
    VkSampleCountFlagBits samples() const { return samples_; }
    VkRenderPass overlayPass() const { return overlayPass_; }
    uint32_t minImageCount() const { return minImageCount_; }
    uint32_t imageCount() const { return uint32_t(images_.size()); }
    VkExtent2D extent() const { return extent_; }
    bool timestamps() const { return timestampPeriodNs_ > 0.0; }
    bool vsync() const { return vsync_; }
    const char* presentModeName() const;
    // Asks for a new swapchain with the other present mode before the next frame.
    void setVsync(bool on);

    struct Frame {
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        uint32_t slot = 0;   // frame in flight
        uint32_t image = 0;  // swapchain image
        VkExtent2D extent{};
    };

    // Waits for the oldest frame in flight, recreates the swapchain if `framebufferSize`
    // changed or it went out of date, acquires an image and begins the command buffer.
    // nullopt while the window has no area (minimized).
    std::optional<Frame> begin(VkExtent2D framebufferSize);
    // Dynamic rendering into the swapchain image (through the MSAA target when samples > 1),
    // colour cleared to `clear`, depth to 1.
    void beginScene(const Frame& frame, glm::vec4 clear);
    void endScene(const Frame& frame);
    // The overlay render pass: loads the scene, ends in PRESENT_SRC.
    void beginOverlay(const Frame& frame);
    void endOverlay(const Frame& frame);
    // Submits and presents. With `capture`, also copies the image and returns its RGBA8
    // pixels (row-major from the top-left; waits for the GPU).
    std::vector<uint8_t> end(const Frame& frame, bool capture);

    // Timestamps of the most recently completed frame (valid when the device has them).
    GpuFrameTimes lastGpuTimes() const { return gpuTimes_; }
    // Swapchains created so far (1 + recreations).
    uint32_t swapchainGeneration() const { return generation_; }

private:
    void createSwapchain(VkExtent2D size);
    void destroySwapchainResources();
    const vk::Context& context_;
    VkDevice device_;
    VkSurfaceKHR surface_;
    VkSurfaceFormatKHR format_{};
    VkSampleCountFlagBits samples_;
    bool vsync_;
    bool recreate_ = false;
    bool canCapture_ = false;
    uint32_t generation_ = 0;
    double timestampPeriodNs_ = 0.0;

    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkExtent2D extent_{};
    uint32_t minImageCount_ = 2;
    std::vector<VkImage> images_;
    std::vector<VkImageView> views_;
    std::vector<VkFramebuffer> framebuffers_;
    std::vector<VkSemaphore> renderDone_;  // per swapchain image: presentation waits on it
    vk::Image depth_, msaaColor_;
    VkRenderPass overlayPass_ = VK_NULL_HANDLE;

    VkCommandPool pool_ = VK_NULL_HANDLE;
    struct Slot {
        VkCommandBuffer cmd = VK_NULL_HANDLE;
        VkFence done = VK_NULL_HANDLE;
        VkSemaphore acquired = VK_NULL_HANDLE;
        VkQueryPool queries = VK_NULL_HANDLE;
        bool submitted = false;
    };
    std::array<Slot, kFramesInFlight> slots_{};
    uint32_t nextSlot_ = 0;
    GpuFrameTimes gpuTimes_;
    vk::Buffer readback_;
};

}  // namespace ngi::view
