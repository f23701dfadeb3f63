// ngi engine: the super-resolution workspace of one input size: tensors aliased by their
// liveness over the op list, their texel-buffer views and the descriptor sets per layer.
#include "sr_internal.h"

#include "ngi/engine/super_resolution.h"
#include "sr_kernels.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include <algorithm>
#include <cmath>
#include <cstring>

namespace ngi::vk {

void writeTensorSet(VkDevice device, VkDescriptorSet set, const std::vector<VkBufferView>& views,
                    std::array<uint32_t, 3> in, uint32_t out, const VkDescriptorBufferInfo& weights)
{
    std::vector<VkWriteDescriptorSet> writes;
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.descriptorCount = 1;
    for (uint32_t k = 0; k < 3; ++k)
        if (in[k] != kNoTensor) {
            w.dstBinding = NGI_SR_BINDING_IN0 + k;
            w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
            w.pTexelBufferView = &views[in[k]];
            writes.push_back(w);
        }
    if (out != kNoTensor) {
        w.dstBinding = NGI_SR_BINDING_OUT;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
        w.pTexelBufferView = &views[out];
        writes.push_back(w);
    }
    w.dstBinding = NGI_SR_BINDING_WEIGHTS;
    w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
    w.pTexelBufferView = nullptr;
    w.pBufferInfo = &weights;
    writes.push_back(w);
    vkUpdateDescriptorSets(device, uint32_t(writes.size()), writes.data(), 0, nullptr);
}

SuperResolution::Workspace& SuperResolution::prepare(uint32_t width, uint32_t height)
{
    for (auto& w : workspaces_)
        if (w->width == width && w->height == height) return *w;
    auto ws = std::make_unique<Workspace>();
    ws->context = &context_;
    ws->width = width;
    ws->height = height;
    const uint32_t tensorCount = uint32_t(shapes_.size());
    ws->dims.resize(tensorCount);
    for (uint32_t t = 0; t < tensorCount; ++t) {
        if (!explicitDims_.empty()) {
            ws->dims[t] = {explicitDims_[t][0], explicitDims_[t][1], explicitDims_[t][2]};
        } else {
            const uint32_t g = shapes_[t].gridFactor;
            ws->dims[t] = {shapes_[t].channels, (width - 1) * g + 1, (height - 1) * g + 1};
        }
    }
    const uint32_t maxTexels = context_.properties.limits.maxTexelBufferElements;
    for (uint32_t t = 0; t < tensorCount; ++t)
        if (ws->dims[t].bytes() / 16 > maxTexels)
            throw Error(label() + ": tensor " + std::to_string(t) + " (" + std::to_string(ws->dims[t].channels) +
                        " channels, " + std::to_string(ws->dims[t].width) + "x" + std::to_string(ws->dims[t].height) +
                        ") exceeds this device's texel buffer limit (" + std::to_string(maxTexels) + " texels)");

    // Liveness: a tensor is live from the layer that writes it (inputs: before layer 0) to
    // its last reader (the output tensor: to the end).
    const int layerCount = int(network_.layers.size());
    std::vector<int> lastUse(tensorCount, -1), firstDef(tensorCount, -1);
    for (int li = 0; li < layerCount; ++li) {
        const NetworkLayer& l = network_.layers[li];
        for (uint32_t in : l.inputs)
            if (in != kNoTensor) lastUse[in] = li;
        firstDef[l.output] = li;
    }
    lastUse[network_.outputTensor] = layerCount;
    // Slots first (a free slot that grows least, then the smallest), buffers sized after.
    ws->bufferOf.assign(tensorCount, UINT32_MAX);
    std::vector<VkDeviceSize> slotBytes;
    std::vector<int> slotFreeAfter;  // per slot: last use of the tensor it holds
    auto place = [&](uint32_t t, int def) {
        const VkDeviceSize need = ws->dims[t].bytes();
        uint32_t best = UINT32_MAX;
        VkDeviceSize bestGrowth = 0;
        for (uint32_t b = 0; b < slotBytes.size(); ++b) {
            if (slotFreeAfter[b] >= def) continue;
            const VkDeviceSize growth = need > slotBytes[b] ? need - slotBytes[b] : 0;
            if (best == UINT32_MAX || growth < bestGrowth || (growth == bestGrowth && slotBytes[b] < slotBytes[best])) {
                best = b;
                bestGrowth = growth;
            }
        }
        if (best == UINT32_MAX || bestGrowth >= need) {  // growing would cost as much as a new slot
            best = uint32_t(slotBytes.size());
            slotBytes.push_back(0);
            slotFreeAfter.push_back(0);
        }
        slotBytes[best] = std::max(slotBytes[best], need);
        slotFreeAfter[best] = std::max(lastUse[t], def);
        ws->bufferOf[t] = best;
    };
    for (uint32_t t = 0; t < hostInputs_; ++t) place(t, -1);
    for (int li = 0; li < layerCount; ++li) {
        if (li > 0 && fusedSkip_[li - 1]) continue;  // placed with its conv
        // A conv with a fused skip writes the skip's output (its own output never exists).
        place(fusedSkip_[li] ? network_.layers[li + 1].output : network_.layers[li].output, li);
    }
    for (VkDeviceSize bytes : slotBytes) {
        ws->buffers.push_back(createBuffer(context_, bytes,
                                           VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                                               VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                                               VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT));
        ws->bytes += bytes;
    }
    ws->views.assign(tensorCount, VK_NULL_HANDLE);
    for (uint32_t t = 0; t < tensorCount; ++t) {
        if (ws->bufferOf[t] == UINT32_MAX) continue;
        VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
        info.buffer = ws->buffers[ws->bufferOf[t]].buffer;
        info.format = kTensorFormat;
        info.range = ws->dims[t].bytes();
        NGI_VK_CHECK(vkCreateBufferView(context_.device, &info, nullptr, &ws->views[t]));
    }

    // One descriptor set per layer (the input and output passes bind images: per restore).
    const uint32_t setCount = uint32_t(layerCount);
    const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 3 * setCount},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, setCount},
                                          {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, setCount}};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = setCount;
    poolInfo.poolSizeCount = uint32_t(std::size(sizes));
    poolInfo.pPoolSizes = sizes;
    NGI_VK_CHECK(vkCreateDescriptorPool(context_.device, &poolInfo, nullptr, &ws->pool));
    std::vector<VkDescriptorSetLayout> layouts(setCount, kernels_->setLayout);
    ws->layerSets.resize(setCount);
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = ws->pool;
    alloc.descriptorSetCount = setCount;
    alloc.pSetLayouts = layouts.data();
    NGI_VK_CHECK(vkAllocateDescriptorSets(context_.device, &alloc, ws->layerSets.data()));

    const VkDescriptorBufferInfo weightsInfo{weights_.buffer, 0, kWindowBytes};
    for (int li = 0; li < layerCount; ++li) {
        const NetworkLayer& l = network_.layers[li];
        if (li > 0 && fusedSkip_[li - 1]) continue;
        // Statically used but unread bindings (a conv's residual when it has none) hold the input.
        std::array<uint32_t, 3> in = l.inputs;
        if (fusedSkip_[li]) in[2] = network_.layers[li + 1].inputs[0];
        for (uint32_t& t : in)
            if (t == kNoTensor) t = l.inputs[0];
        writeTensorSet(context_.device, ws->layerSets[li], ws->views, in,
                       fusedSkip_[li] ? network_.layers[li + 1].output : l.output, weightsInfo);
    }
    workspaces_.push_back(std::move(ws));
    return *workspaces_.back();
}

}  // namespace ngi::vk
