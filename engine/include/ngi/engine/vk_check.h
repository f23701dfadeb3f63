// ngi engine: the one Vulkan result check. Works in release builds and reports the file,
// line, the failing call and the result's name, as an ngi::Error.
#pragma once

#include <vulkan/vulkan.h>

namespace ngi::vk {

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" etc.; "VkResult(<n>)" for values it does not know.
const char* resultName(VkResult result);

[[noreturn]] void throwVulkanError(VkResult result, const char* call, const char* file, int line);

}  // namespace ngi::vk

#define NGI_VK_CHECK(call)                                                                                             \
    do {                                                                                                               \
        const VkResult ngiResult_ = (call);                                                                            \
        if (ngiResult_ < 0) ::ngi::vk::throwVulkanError(ngiResult_, #call, __FILE__, __LINE__);                        \
    } while (0)
