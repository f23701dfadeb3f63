// ngi engine (internal): what the files of SuperResolution share: the tensor layout on the
// GPU (C4 planes), the workspace of one input size (tensors aliased by liveness, descriptor
// sets) and small helpers. super_resolution.cpp: weights repacking and recording;
// sr_workspace.cpp: tensor allocation; sr_profile.cpp: timestamps per op; sr_host.cpp: the
// host paths for tests and tools.
#pragma once

#include "ngi/engine/super_resolution.h"
#include "sr_kernels.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include <array>
#include <cstring>
#include <string>
#include <vector>

namespace ngi::vk {

constexpr VkDeviceSize kWindowBytes = NGI_SR_UBO_VEC4S * 16;  // one conv dispatch's weights
constexpr VkFormat kTensorFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

inline uint32_t groupsOf(uint32_t channels) { return (channels + 3) / 4; }

// The engine's conv kernel shape (ngi-bench-sr --micro on lavapipe, 129^2, 2 loaded cores):
// 4 pixels per invocation; 2 output groups per invocation while the unrolled body stays
// small (input groups x taps <= 36: 16 -> 192 3x3 7.7 GFLOP/s vs 6.1 with 1 group, 3 -> 32
// 6.5 vs 5.4), else 1 (32 -> 32 3x3: 11.0 GFLOP/s, 11.4 with 2 groups at 3x the compile
// time, 6.6 with 4 x 2: the larger body spills registers).
inline SrConvShape resolveShape(SrConvShape s, uint32_t inGroups, uint32_t kernel)
{
    if (s.groupsPerInvocation == 0) s.groupsPerInvocation = inGroups * kernel * kernel <= 36 ? 2 : 1;
    if (s.pixelsPerInvocation == 0) s.pixelsPerInvocation = 4;
    if (s.groupsPerInvocation > 8 || s.pixelsPerInvocation > 16) throw Error("super-resolution: conv shape too large");
    return s;
}

struct TensorDims {
    uint32_t channels = 0, width = 0, height = 0;
    VkDeviceSize bytes() const { return VkDeviceSize(groupsOf(channels)) * width * height * 16; }
};

// Host CHW -> C4 planes (zero lanes past the channel count) and back.
inline void packTensor(const nn::FeatureMap& t, float* dst)
{
    const size_t plane = size_t(t.width) * t.height;
    std::memset(dst, 0, groupsOf(t.channels) * plane * 16);
    for (uint32_t c = 0; c < t.channels; ++c)
        for (size_t p = 0; p < plane; ++p) dst[((c / 4) * plane + p) * 4 + c % 4] = t.data[c * plane + p];
}

inline nn::FeatureMap unpackTensor(const float* src, const TensorDims& d)
{
    nn::FeatureMap t(d.channels, d.height, d.width);
    const size_t plane = size_t(d.width) * d.height;
    t.data.resize(d.channels * plane);
    for (uint32_t c = 0; c < d.channels; ++c)
        for (size_t p = 0; p < plane; ++p) t.data[c * plane + p] = src[((c / 4) * plane + p) * 4 + c % 4];
    return t;
}

inline void computeToComputeBarrier(VkCommandBuffer cmd)
{
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

inline std::string kindName(const NetworkLayer& l)
{
    switch (l.kind) {
    case LayerKind::Conv: return l.kernelSize == 3 ? "conv3x3" : "conv1x1";
    case LayerKind::NeighborhoodCrossAttention: return "attention";
    case LayerKind::PixelShuffle: return "pixel_shuffle";
    case LayerKind::BilinearSkip: return "bilinear_skip";
    case LayerKind::CubicSkip: return "cubic_skip";
    case LayerKind::HermiteSkip: return "hermite_skip";
    }
    return "?";
}

// The error of a restore with `bad` non-finite samples of `total`, naming the network.
inline std::string nonFiniteMessage(const std::string& label, uint64_t bad, uint64_t total)
{
    return label + ": the restore produced non-finite values (" + std::to_string(bad) + " of " + std::to_string(total) +
        " restored samples)";
}

struct SuperResolution::Workspace {
    const Context* context = nullptr;
    uint32_t width = 0, height = 0;   // input (stored level) size
    std::vector<TensorDims> dims;     // per tensor
    std::vector<Buffer> buffers;      // aliased by liveness
    std::vector<uint32_t> bufferOf;   // per tensor
    std::vector<VkBufferView> views;  // per tensor
    VkDescriptorPool pool = VK_NULL_HANDLE;
    std::vector<VkDescriptorSet> layerSets;  // per layer (tensors only: the same for every restore)
    VkDeviceSize bytes = 0;

    SrTensorView tensor(uint32_t id) const { return {views[id], dims[id].channels, dims[id].width, dims[id].height}; }

    ~Workspace()
    {
        if (!context) return;
        if (pool) vkDestroyDescriptorPool(context->device, pool, nullptr);
        for (VkBufferView v : views)
            if (v) vkDestroyBufferView(context->device, v, nullptr);
        for (Buffer& b : buffers) destroyBuffer(*context, b);
    }
};

// Writes the tensor bindings of `set`: inputs in[0..2] (kNoTensor: unbound), output `out`
// (kNoTensor: none) and the weights window.
void writeTensorSet(VkDevice device, VkDescriptorSet set, const std::vector<VkBufferView>& views,
                    std::array<uint32_t, 3> in, uint32_t out, const VkDescriptorBufferInfo& weights);

// What one record() binds that the next one must not overwrite while this one is pending:
// the descriptor sets holding its images (input passes: stored level -> tensor 0, 1; output
// pass: output tensor + stored level -> full level) and its count of non-finite samples.
struct SuperResolution::Restore {
    const Context* context = nullptr;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    VkDescriptorSet inputSets[2]{};
    VkDescriptorSet outputSet = VK_NULL_HANDLE;
    Buffer check;          // host-visible uint, zeroed by the host before the record
    uint64_t samples = 0;  // samples this restore writes

    ~Restore()
    {
        if (!context) return;
        if (pool) vkDestroyDescriptorPool(context->device, pool, nullptr);
        destroyBuffer(*context, check);
    }
};

}  // namespace ngi::vk
