// ngi engine: buffers and images as plain structs with explicit create/destroy (the owner
// destroys them in reverse order of creation), and the one place that records barriers.
#pragma once

#include "ngi/engine/context.h"

#include <vulkan/vulkan.h>

#include <cstdint>

namespace ngi::vk {

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    void* mapped = nullptr;  // persistently mapped when host-visible
};

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0;
    VkDeviceSize bytes = 0;  // device memory size
};

// A buffer with its own memory; host-visible memory is mapped. ngi::Error on failure.
Buffer createBuffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags memory);
void destroyBuffer(const Context& context, Buffer& buffer);

// A 2D image (one mip level, one layer) in device-local memory with a view of `aspect`.
Image createImage(const Context& context, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect, VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT);
void destroyImage(const Context& context, Image& image);

// Barriers (synchronization 1, so any Vulkan 1.3 device or host engine can use them).
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkPipelineStageFlags srcStage,
                  VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess,
                  VkImageLayout oldLayout, VkImageLayout newLayout);
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

} // namespace ngi::vk
