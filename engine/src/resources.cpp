// Buffers, images and barriers.
#include "ngi/engine/resources.h"

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include <algorithm>
#include <initializer_list>

namespace ngi::vk {

namespace {

// createBuffer with the first of `preferences` that one of the buffer's memory types offers.
Buffer createBufferPreferring(const Context& c, VkDeviceSize size, VkBufferUsageFlags usage,
                              std::initializer_list<VkMemoryPropertyFlags> preferences)
{
    UniqueBuffer b(c, Buffer{});  // frees what was made if a step below throws
    b->size = size;
    VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    info.size = size;
    info.usage = usage;
    info.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    NGI_VK_CHECK(vkCreateBuffer(c.device, &info, nullptr, &b->buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(c.device, b->buffer, &req);
    VkMemoryPropertyFlags memory = *preferences.begin();
    for (VkMemoryPropertyFlags p : preferences) {
        memory = p;
        bool offered = false;
        for (uint32_t t = 0; t < c.memoryProperties.memoryTypeCount; ++t)
            offered |= (req.memoryTypeBits & (1u << t)) && (c.memoryProperties.memoryTypes[t].propertyFlags & p) == p;
        if (offered) break;
    }
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = c.memoryType(req.memoryTypeBits, memory);
    NGI_VK_CHECK(vkAllocateMemory(c.device, &alloc, nullptr, &b->memory));
    NGI_VK_CHECK(vkBindBufferMemory(c.device, b->buffer, b->memory, 0));
    if (memory & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
        NGI_VK_CHECK(vkMapMemory(c.device, b->memory, 0, size, 0, &b->mapped));
    return b.release();
}

}  // namespace

Buffer createBuffer(const Context& c, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags memory)
{
    return createBufferPreferring(c, size, usage, {memory});
}

Buffer createHostWrittenBuffer(const Context& c, VkDeviceSize size, VkBufferUsageFlags usage)
{
    constexpr VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    return createBufferPreferring(c, size, usage, {host | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, host});
}

void destroyBuffer(const Context& c, Buffer& b)
{
    if (b.mapped) vkUnmapMemory(c.device, b.memory);
    if (b.buffer) vkDestroyBuffer(c.device, b.buffer, nullptr);
    if (b.memory) vkFreeMemory(c.device, b.memory, nullptr);
    b = Buffer{};
}

Image createImage(const Context& c, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                  VkImageAspectFlags aspect, VkSampleCountFlagBits samples, uint32_t mipLevels)
{
    UniqueImage img(c, Image{});  // frees what was made if a step below throws
    img->format = format;
    img->width = width;
    img->height = height;
    VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    info.imageType = VK_IMAGE_TYPE_2D;
    info.format = format;
    info.extent = {width, height, 1};
    info.mipLevels = mipLevels;
    info.arrayLayers = 1;
    info.samples = samples;
    info.tiling = VK_IMAGE_TILING_OPTIMAL;
    info.usage = usage;
    info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    NGI_VK_CHECK(vkCreateImage(c.device, &info, nullptr, &img->image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(c.device, img->image, &req);
    VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    alloc.allocationSize = req.size;
    alloc.memoryTypeIndex = c.memoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    NGI_VK_CHECK(vkAllocateMemory(c.device, &alloc, nullptr, &img->memory));
    img->bytes = req.size;
    NGI_VK_CHECK(vkBindImageMemory(c.device, img->image, img->memory, 0));
    VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    view.image = img->image;
    view.viewType = VK_IMAGE_VIEW_TYPE_2D;
    view.format = format;
    view.subresourceRange = {aspect, 0, mipLevels, 0, 1};
    NGI_VK_CHECK(vkCreateImageView(c.device, &view, nullptr, &img->view));
    return img.release();
}

void destroyImage(const Context& c, Image& img)
{
    if (img.view) vkDestroyImageView(c.device, img.view, nullptr);
    if (img.image) vkDestroyImage(c.device, img.image, nullptr);
    if (img.memory) vkFreeMemory(c.device, img.memory, nullptr);
    img = Image{};
}

ImagePool::ImagePool(const Context& c, std::span<const ImageDesc> descs)
{
    // The images first (their requirements decide the layout), then the allocations.
    std::vector<VkMemoryRequirements> reqs(descs.size());
    for (size_t i = 0; i < descs.size(); ++i) {
        images_.emplace_back(c, Image{});
        Image& img = *images_.back().operator->();
        img.format = descs[i].format;
        img.width = descs[i].width;
        img.height = descs[i].height;
        VkImageCreateInfo info{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
        info.imageType = VK_IMAGE_TYPE_2D;
        info.format = descs[i].format;
        info.extent = {descs[i].width, descs[i].height, 1};
        info.mipLevels = 1;
        info.arrayLayers = 1;
        info.samples = VK_SAMPLE_COUNT_1_BIT;
        info.tiling = VK_IMAGE_TILING_OPTIMAL;
        info.usage = descs[i].usage;
        info.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        NGI_VK_CHECK(vkCreateImage(c.device, &info, nullptr, &img.image));
        vkGetImageMemoryRequirements(c.device, img.image, &reqs[i]);
        img.bytes = reqs[i].size;
    }
    // Vulkan 1.1's limit on one allocation (at least 1 GiB on every device).
    VkPhysicalDeviceMaintenance3Properties maintenance3{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props.pNext = &maintenance3;
    vkGetPhysicalDeviceProperties2(c.physicalDevice, &props);
    const VkDeviceSize maxBytes = std::max<VkDeviceSize>(maintenance3.maxMemoryAllocationSize, 1u << 30);

    // Greedy groups in order: an image joins the open group when they share a device-local
    // memory type and the group stays within maxBytes (all optimal-tiling images: no
    // bufferImageGranularity constraint between them).
    std::vector<bool> placed(descs.size(), false);
    for (size_t first = 0; first < descs.size(); ++first) {
        if (placed[first]) continue;
        const uint32_t type = c.memoryType(reqs[first].memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        std::vector<std::pair<size_t, VkDeviceSize>> members;  // image, offset
        VkDeviceSize end = 0;
        for (size_t i = first; i < descs.size(); ++i) {
            if (placed[i] || !(reqs[i].memoryTypeBits & (1u << type))) continue;
            const VkDeviceSize offset = (end + reqs[i].alignment - 1) / reqs[i].alignment * reqs[i].alignment;
            if (!members.empty() && offset + reqs[i].size > maxBytes) continue;
            members.push_back({i, offset});
            end = offset + reqs[i].size;
            placed[i] = true;
        }
        VkMemoryAllocateInfo alloc{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        alloc.allocationSize = end;
        alloc.memoryTypeIndex = type;
        memory_.emplace_back(c.device);
        NGI_VK_CHECK(vkAllocateMemory(c.device, &alloc, nullptr, memory_.back().out()));
        allocatedBytes_ += end;
        for (const auto& [i, offset] : members)
            NGI_VK_CHECK(vkBindImageMemory(c.device, images_[i]->image, memory_.back().get(), offset));
    }
    for (size_t i = 0; i < descs.size(); ++i) {
        Image& img = *images_[i].operator->();
        VkImageViewCreateInfo view{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
        view.image = img.image;
        view.viewType = VK_IMAGE_VIEW_TYPE_2D;
        view.format = img.format;
        view.subresourceRange = {descs[i].aspect, 0, 1, 0, 1};
        NGI_VK_CHECK(vkCreateImageView(c.device, &view, nullptr, &img.view));
    }
}

UniqueBuffer::UniqueBuffer(const Context& c, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags memory)
    : context_(&c), buffer_(createBuffer(c, size, usage, memory))
{}

UniqueBuffer& UniqueBuffer::operator=(UniqueBuffer&& other) noexcept
{
    if (this != &other) {
        reset();
        context_ = other.context_;
        buffer_ = std::exchange(other.buffer_, Buffer{});
    }
    return *this;
}

void UniqueBuffer::reset() noexcept
{
    if (context_) destroyBuffer(*context_, buffer_);
}

UniqueImage::UniqueImage(const Context& c, uint32_t width, uint32_t height, VkFormat format, VkImageUsageFlags usage,
                         VkImageAspectFlags aspect, VkSampleCountFlagBits samples)
    : context_(&c), image_(createImage(c, width, height, format, usage, aspect, samples))
{}

UniqueImage& UniqueImage::operator=(UniqueImage&& other) noexcept
{
    if (this != &other) {
        reset();
        context_ = other.context_;
        image_ = std::exchange(other.image_, Image{});
    }
    return *this;
}

void UniqueImage::reset() noexcept
{
    if (context_) destroyImage(*context_, image_);
}

void imageBarrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkPipelineStageFlags srcStage,
                  VkAccessFlags srcAccess, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess,
                  VkImageLayout oldLayout, VkImageLayout newLayout)
{
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    b.oldLayout = oldLayout;
    b.newLayout = newLayout;
    b.srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

void memoryBarrier(VkCommandBuffer cmd, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess)
{
    VkMemoryBarrier b{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    vkCmdPipelineBarrier(cmd, srcStage, dstStage, 0, 1, &b, 0, nullptr, 0, nullptr);
}

}  // namespace ngi::vk
