// ngi engine: buffers and images as plain structs with explicit create/destroy, thin
// move-only owners of them (UniqueBuffer, UniqueImage, UniqueHandle) so that cleanup after a
// throw needs no hand-written try/catch, and the one place that records barriers.
#pragma once

#include "ngi/engine/context.h"

#include <vulkan/vulkan.h>

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

namespace ngi::vk {

struct Buffer {
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;
    VkDeviceSize size = 0;
    void* mapped = nullptr;  // persistently mapped when host-visible
};

struct Image {
    VkImage image = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;  // owned by the image; null for a pooled image (ImagePool)
    VkImageView view = VK_NULL_HANDLE;
    VkFormat format = VK_FORMAT_UNDEFINED;
    uint32_t width = 0, height = 0;
    VkDeviceSize bytes = 0;  // device memory size
};

// A buffer with its own memory; host-visible memory is mapped. ngi::Error on failure.
Buffer createBuffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags memory);
// A mapped buffer the CPU writes and the GPU reads every frame: host-visible and coherent
// memory, device-local too where the device has such a type for it (resizable BAR, unified
// memory). ngi::Error on failure.
Buffer createHostWrittenBuffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage);
void destroyBuffer(const Context& context, Buffer& buffer);

// A 2D image (one layer, `mipLevels` mip levels) in device-local memory with a view of
// `aspect` over every level.
Image createImage(const Context& context, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect, VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT,
                  uint32_t mipLevels = 1);
void destroyImage(const Context& context, Image& image);

// Owns one Buffer: destroys it (destroyBuffer) when it goes out of scope or is reset, so a
// staging buffer or a member of a half-built object is freed on every path, exceptions
// included. Move-only; a moved-from owner is empty. `context` must outlive the owner.
class UniqueBuffer {
public:
    UniqueBuffer() = default;
    // createBuffer(context, size, usage, memory), owned. ngi::Error on failure.
    UniqueBuffer(const Context& context, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags memory);
    // Takes ownership of `buffer` (which may be partly created: null handles are skipped).
    UniqueBuffer(const Context& context, const Buffer& buffer) noexcept : context_(&context), buffer_(buffer) {}
    ~UniqueBuffer() { reset(); }
    UniqueBuffer(UniqueBuffer&& other) noexcept
        : context_(other.context_), buffer_(std::exchange(other.buffer_, Buffer{}))
    {}
    UniqueBuffer& operator=(UniqueBuffer&& other) noexcept;
    UniqueBuffer(const UniqueBuffer&) = delete;
    UniqueBuffer& operator=(const UniqueBuffer&) = delete;

    const Buffer& get() const { return buffer_; }
    const Buffer& operator*() const { return buffer_; }
    const Buffer* operator->() const { return &buffer_; }
    Buffer* operator->() { return &buffer_; }  // for filling a partly created buffer
    explicit operator bool() const { return buffer_.buffer != VK_NULL_HANDLE; }
    // Destroys the buffer now; the owner is empty afterwards.
    void reset() noexcept;
    // Gives the buffer up without destroying it; the caller destroys it (destroyBuffer).
    Buffer release() noexcept { return std::exchange(buffer_, Buffer{}); }

private:
    const Context* context_ = nullptr;
    Buffer buffer_;
};

// Owns one Image, as UniqueBuffer owns a Buffer (destroyImage on scope exit or reset).
class UniqueImage {
public:
    UniqueImage() = default;
    // createImage(...), owned. ngi::Error on failure.
    UniqueImage(const Context& context, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                VkImageAspectFlags aspect, VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT);
    // Takes ownership of `image` (which may be partly created: null handles are skipped).
    UniqueImage(const Context& context, const Image& image) noexcept : context_(&context), image_(image) {}
    ~UniqueImage() { reset(); }
    UniqueImage(UniqueImage&& other) noexcept : context_(other.context_), image_(std::exchange(other.image_, Image{}))
    {}
    UniqueImage& operator=(UniqueImage&& other) noexcept;
    UniqueImage(const UniqueImage&) = delete;
    UniqueImage& operator=(const UniqueImage&) = delete;

    const Image& get() const { return image_; }
    const Image& operator*() const { return image_; }
    const Image* operator->() const { return &image_; }
    Image* operator->() { return &image_; }  // for filling a partly created image
    explicit operator bool() const { return image_.image != VK_NULL_HANDLE; }
    void reset() noexcept;
    Image release() noexcept { return std::exchange(image_, Image{}); }

private:
    const Context* context_ = nullptr;
    Image image_;
};

// Owns one device-level handle (descriptor pool, pipeline, sampler, fence, query pool, ...)
// and destroys it with `Destroy` (vkDestroyDescriptorPool, ...) on scope exit or reset.
// Move-only; a moved-from owner is empty. The device must outlive the owner.
template <class Handle, void (*Destroy)(VkDevice, Handle, const VkAllocationCallbacks*)> class UniqueHandle {
public:
    UniqueHandle() = default;
    explicit UniqueHandle(VkDevice device, Handle handle = VK_NULL_HANDLE) noexcept : device_(device), handle_(handle)
    {}
    ~UniqueHandle() { reset(); }
    UniqueHandle(UniqueHandle&& other) noexcept
        : device_(other.device_), handle_(std::exchange(other.handle_, Handle(VK_NULL_HANDLE)))
    {}
    UniqueHandle& operator=(UniqueHandle&& other) noexcept
    {
        if (this != &other) {
            reset();
            device_ = other.device_;
            handle_ = std::exchange(other.handle_, Handle(VK_NULL_HANDLE));
        }
        return *this;
    }
    UniqueHandle(const UniqueHandle&) = delete;
    UniqueHandle& operator=(const UniqueHandle&) = delete;

    Handle get() const { return handle_; }
    // Where a vkCreate* call writes the new handle; the owner must be empty (reset first).
    Handle* out() { return &handle_; }
    explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }
    void reset() noexcept
    {
        if (handle_ != VK_NULL_HANDLE) Destroy(device_, handle_, nullptr);
        handle_ = VK_NULL_HANDLE;
    }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    Handle handle_ = VK_NULL_HANDLE;
};

using UniqueDescriptorPool = UniqueHandle<VkDescriptorPool, vkDestroyDescriptorPool>;
using UniqueDescriptorSetLayout = UniqueHandle<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using UniquePipelineLayout = UniqueHandle<VkPipelineLayout, vkDestroyPipelineLayout>;
using UniquePipeline = UniqueHandle<VkPipeline, vkDestroyPipeline>;
using UniqueSampler = UniqueHandle<VkSampler, vkDestroySampler>;
using UniqueFence = UniqueHandle<VkFence, vkDestroyFence>;
using UniqueQueryPool = UniqueHandle<VkQueryPool, vkDestroyQueryPool>;
using UniqueDeviceMemory = UniqueHandle<VkDeviceMemory, vkFreeMemory>;

// One 2D image (one mip level, one layer, optimal tiling, single-sampled) of an ImagePool.
struct ImageDesc {
    uint32_t width = 0, height = 0;
    VkFormat format = VK_FORMAT_UNDEFINED;
    VkImageUsageFlags usage = 0;
    VkImageAspectFlags aspect = VK_IMAGE_ASPECT_COLOR_BIT;
};

// Device-local images that share few VkDeviceMemory allocations: each image is bound at an
// offset aligned to its own requirement, in one allocation per memory type the images can
// share (one when every image accepts the same device-local type, as for ngi's surfaces),
// a new one only past the device's maxMemoryAllocationSize. Vulkan guarantees only 4096
// live allocations (maxMemoryAllocationCount), so a surface of ~32 images must not take 32.
// The pool owns the memory; its images (Image::memory null) are destroyed before it.
class ImagePool {
public:
    ImagePool() = default;
    // Creates every image of `descs` in that order, binds and views them. ngi::Error on failure.
    ImagePool(const Context& context, std::span<const ImageDesc> descs);
    // A moved-from pool holds nothing (no images, no memory, 0 bytes).
    ImagePool(ImagePool&& other) noexcept
        : memory_(std::move(other.memory_)), images_(std::move(other.images_)),
          allocatedBytes_(std::exchange(other.allocatedBytes_, 0))
    {
        other.memory_.clear();
        other.images_.clear();
    }
    ImagePool& operator=(ImagePool&& other) noexcept
    {
        if (this != &other) {
            images_ = std::move(other.images_);  // the images before their memory
            memory_ = std::move(other.memory_);
            allocatedBytes_ = std::exchange(other.allocatedBytes_, 0);
            other.images_.clear();
            other.memory_.clear();
        }
        return *this;
    }

    const Image& operator[](size_t i) const { return *images_.at(i); }
    size_t size() const { return images_.size(); }
    uint32_t allocationCount() const { return uint32_t(memory_.size()); }
    VkDeviceSize allocatedBytes() const { return allocatedBytes_; }

private:
    std::vector<UniqueDeviceMemory> memory_;  // declared first: freed after the images
    std::vector<UniqueImage> images_;
    VkDeviceSize allocatedBytes_ = 0;
};

// Barriers (synchronization 1, so any Vulkan 1.3 device or host engine can use them).
void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkPipelineStageFlags srcStage,
                  VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess,
                  VkImageLayout oldLayout, VkImageLayout newLayout);
void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

}  // namespace ngi::vk
