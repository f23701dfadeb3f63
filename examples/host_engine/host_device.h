// ngi-host-demo: the host's own Vulkan instance and device (what an engine already has before
// it adopts ngi: Context::adopt, not Context::create), with the validation layer on request.
#pragma once

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include <vulkan/vulkan.h>

#include <cstdio>
#include <vector>

namespace host {

inline int gValidationMessages = 0;

inline VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                                const VkDebugUtilsMessengerCallbackDataEXT* data, void*)
{
    ++gValidationMessages;
    std::fprintf(stderr, "validation: %s\n", data->pMessage ? data->pMessage : "");
    return VK_FALSE;
}

// The first Vulkan 1.3 device with a graphics + compute queue family; dynamic rendering on
// (what ngi needs, ngi::vk::missingDeviceRequirements).
struct HostDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t family = 0;
    uint32_t timestampValidBits = 0;
    VkPhysicalDeviceProperties properties{};
    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    VkDeviceCreateInfo createInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    float priority = 1.0f;

    explicit HostDevice(bool validation)
    {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "ngi-host-demo";
        app.apiVersion = VK_API_VERSION_1_3;
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const char* debugExtension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        info.pApplicationInfo = &app;
        info.enabledLayerCount = validation ? 1 : 0;
        info.ppEnabledLayerNames = &layer;
        info.enabledExtensionCount = validation ? 1 : 0;
        info.ppEnabledExtensionNames = &debugExtension;
        NGI_VK_CHECK(vkCreateInstance(&info, nullptr, &instance));
        if (validation) {
            VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            m.messageSeverity =
                VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
            m.pfnUserCallback = onMessage;
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
            NGI_VK_CHECK(create(instance, &m, nullptr, &messenger));
        }
        uint32_t count = 0;
        vkEnumeratePhysicalDevices(instance, &count, nullptr);
        std::vector<VkPhysicalDevice> devices(count);
        vkEnumeratePhysicalDevices(instance, &count, devices.data());
        for (VkPhysicalDevice pd : devices) {
            vkGetPhysicalDeviceProperties(pd, &properties);
            if (properties.apiVersion < VK_API_VERSION_1_3) continue;
            uint32_t n = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
            std::vector<VkQueueFamilyProperties> families(n);
            vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
            for (uint32_t f = 0; f < n && !physical; ++f)
                if ((families[f].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
                    (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
                    physical = pd;
                    family = f;
                    timestampValidBits = families[f].timestampValidBits;
                }
            if (physical) break;
        }
        if (!physical) throw ngi::Error("ngi-host-demo: no Vulkan 1.3 device with a graphics+compute queue");
        features13.dynamicRendering = VK_TRUE;
        features.pNext = &features13;
        // ngi's selection on the GPU draws indirectly from a first instance (GpuTileSelection).
        VkPhysicalDeviceFeatures supported{};
        vkGetPhysicalDeviceFeatures(physical, &supported);
        features.features.drawIndirectFirstInstance = supported.drawIndirectFirstInstance;
        queueInfo.queueFamilyIndex = family;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;
        createInfo.pNext = &features;
        createInfo.queueCreateInfoCount = 1;
        createInfo.pQueueCreateInfos = &queueInfo;
        NGI_VK_CHECK(vkCreateDevice(physical, &createInfo, nullptr, &device));
        vkGetDeviceQueue(device, family, 0, &queue);
    }
    ~HostDevice()
    {
        if (device) vkDestroyDevice(device, nullptr);
        if (messenger) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            destroy(instance, messenger, nullptr);
        }
        if (instance) vkDestroyInstance(instance, nullptr);
    }
    HostDevice(const HostDevice&) = delete;
    HostDevice& operator=(const HostDevice&) = delete;

    // The first of `candidates` usable with optimal tiling for all of `features`.
    VkFormat pickFormat(std::initializer_list<VkFormat> candidates, VkFormatFeatureFlags needed) const
    {
        for (VkFormat f : candidates) {
            VkFormatProperties p;
            vkGetPhysicalDeviceFormatProperties(physical, f, &p);
            if ((p.optimalTilingFeatures & needed) == needed) return f;
        }
        throw ngi::Error("ngi-host-demo: no depth format with the needed features");
    }
};

}  // namespace host
