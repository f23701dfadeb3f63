// Test helper: a host engine's descriptor set of one uniform block (binding 0), as a host
// binds it at SurfacePipeline::firstHostSet next to ngi's sets: its layout, a host-visible
// buffer holding the block and the set written to it, each held by its owner.
#pragma once

#include "ngi/engine/context.h"
#include "ngi/engine/resources.h"
#include "ngi/engine/vk_check.h"

#include <vulkan/vulkan.h>

#include <cstring>
#include <span>

namespace ngi::test {

struct HostUniformSet {
    // One uniform block holding a copy of `bytes` (not empty), visible to `stages`. ngi::Error
    // on a Vulkan failure.
    HostUniformSet(const vk::Context& c, std::span<const std::byte> bytes, VkShaderStageFlags stages)
        : layout(c.device), pool(c.device)
    {
        const VkDescriptorSetLayoutBinding binding{0, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, stages, nullptr};
        VkDescriptorSetLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        layoutInfo.bindingCount = 1;
        layoutInfo.pBindings = &binding;
        NGI_VK_CHECK(vkCreateDescriptorSetLayout(c.device, &layoutInfo, nullptr, layout.out()));
        layoutHandle = layout.get();
        block = vk::UniqueBuffer(c, bytes.size(), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                 VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        std::memcpy(block->mapped, bytes.data(), bytes.size());
        const VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1};
        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.maxSets = 1;
        poolInfo.poolSizeCount = 1;
        poolInfo.pPoolSizes = &poolSize;
        NGI_VK_CHECK(vkCreateDescriptorPool(c.device, &poolInfo, nullptr, pool.out()));
        VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        alloc.descriptorPool = pool.get();
        alloc.descriptorSetCount = 1;
        alloc.pSetLayouts = &layoutHandle;
        NGI_VK_CHECK(vkAllocateDescriptorSets(c.device, &alloc, &set));
        const VkDescriptorBufferInfo bufferInfo{block->buffer, 0, bytes.size()};
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = set;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
        w.pBufferInfo = &bufferInfo;
        vkUpdateDescriptorSets(c.device, 1, &w, 0, nullptr);
    }
    HostUniformSet(const HostUniformSet&) = delete;
    HostUniformSet& operator=(const HostUniformSet&) = delete;

    // The layouts a pipeline's hostSetLayouts take: {&layoutHandle, 1}.
    std::span<const VkDescriptorSetLayout> layouts() const { return {&layoutHandle, 1}; }

    vk::UniqueDescriptorSetLayout layout;
    VkDescriptorSetLayout layoutHandle = VK_NULL_HANDLE;  // layout.get(), addressable
    vk::UniqueBuffer block;
    vk::UniqueDescriptorPool pool;
    VkDescriptorSet set = VK_NULL_HANDLE;  // freed with the pool
};

}  // namespace ngi::test
