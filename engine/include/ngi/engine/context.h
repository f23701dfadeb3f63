// ngi engine: the Vulkan instance, device and queue ngi works with.
//
// Two ways in: `Context::create` makes its own headless instance and device (prefers a real
// GPU, falls back to lavapipe; `ContextOptions::device` or NGI_DEVICE picks one), or
// `Context::adopt` wraps a host engine's VkInstance/VkDevice/queue without owning them, so
// ngi can record its work into the host's command buffers.
#pragma once

#include <vulkan/vulkan.h>

#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace ngi::vk {

struct DeviceInfo {
    uint32_t index = 0;
    std::string name;
    std::string type;  // "discrete GPU", "integrated GPU", "virtual GPU", "CPU", "other"
    uint32_t apiVersion = 0;
    bool suitable = false;  // Vulkan 1.3 with a graphics+compute queue
    std::string unsuitableBecause;
};

struct ContextOptions {
    // Enables VK_LAYER_KHRONOS_validation and a debug messenger that records every warning
    // and error (see Context::validationMessages). Also on when NGI_VALIDATION=1.
    bool validation = false;
    // Device by index ("0") or case-insensitive name substring ("llvmpipe"); empty: the
    // NGI_DEVICE environment variable, else the best device (discrete > integrated > CPU).
    std::string device;
    std::vector<std::string> instanceExtensions;  // e.g. a window system's surface extensions
    std::vector<std::string> deviceExtensions;    // e.g. VK_KHR_swapchain
    // Extra queue-family requirement (e.g. presentation support); null: graphics+compute only.
    std::function<bool(VkInstance, VkPhysicalDevice, uint32_t family)> queueFamilyFilter;
};

class Context {
public:
    // Creates instance, device and queue. Throws ngi::Error with one clear message when no
    // Vulkan driver or no suitable device exists, or the named device is not found.
    static std::unique_ptr<Context> create(const ContextOptions& options = {});

    // Wraps handles owned by a host engine; ngi never destroys them. `enabled` is the
    // VkDeviceCreateInfo the host created `device` with (Vulkan cannot be asked what a device
    // enabled; only pEnabledFeatures, its pNext chain and the extension names are read, the
    // queue infos are not). Throws ngi::Error listing everything missing
    // (missingDeviceRequirements): see there for what ngi needs.
    static std::unique_ptr<Context> adopt(VkInstance instance, VkPhysicalDevice physicalDevice, VkDevice device,
                                          VkQueue queue, uint32_t family, const VkDeviceCreateInfo& enabled);

    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkPhysicalDeviceProperties properties{};
    VkPhysicalDeviceMemoryProperties memoryProperties{};
    bool pipelineStatistics = false;         // pipelineStatisticsQuery feature enabled
    bool independentBlend = false;           // independentBlend feature enabled (passes of several colour attachments)
    bool drawIndirectFirstInstance = false;  // drawIndirectFirstInstance enabled (GpuTileSelection)

    // Validation warnings and errors seen so far (empty when validation is off).
    std::vector<std::string> validationMessages() const;

    // Records work with `record`, submits it to the queue and waits for it to finish.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& record) const;

    // Memory type index with `required` flags among `typeBits`; ngi::Error if none.
    uint32_t memoryType(uint32_t typeBits, VkMemoryPropertyFlags required) const;

private:
    Context() = default;
    bool owns_ = false;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkCommandPool commandPool_ = VK_NULL_HANDLE;
    mutable std::mutex messagesMutex_;
    std::vector<std::string> messages_;
    friend VKAPI_ATTR VkBool32 VKAPI_CALL onValidationMessage(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                              VkDebugUtilsMessageTypeFlagsEXT,
                                                              const VkDebugUtilsMessengerCallbackDataEXT*, void*);
};

// What ngi needs of a device, against what a host enabled (`enabled`: the create info of
// its device; `properties` and `familyFlags`: of its physical device and queue family). One
// line per missing requirement, empty when none: a Vulkan 1.3 device, a queue family with
// graphics and compute, the dynamicRendering feature (VkPhysicalDeviceVulkan13Features or
// VkPhysicalDeviceDynamicRenderingFeatures in the pNext chain), maxPushConstantsSize of at
// least the draw's push constants, and 2D images of at least 1025 texels (a 1024-cell
// chart). Optional: independentBlend (passes of several colour attachments),
// drawIndirectFirstInstance (the adaptive selection on the GPU, GpuTileSelection),
// pipelineStatisticsQuery (tests and benchmarks), timestamps (profiling).
std::vector<std::string> missingDeviceRequirements(const VkPhysicalDeviceProperties& properties,
                                                   VkQueueFlags familyFlags, const VkDeviceCreateInfo& enabled);

// Lists the physical devices (with a temporary instance). ngi::Error if there is no driver.
std::vector<DeviceInfo> listDevices();

}  // namespace ngi::vk
