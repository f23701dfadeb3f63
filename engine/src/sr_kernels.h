// ngi engine (internal): the compute pipelines of the super-resolution ops, one small unit
// per op kind (STYLE.md: pipeline creation + one record call + one .comp). Shapes travel as
// push constants (SrPushConstants); what fixes array sizes or unrolls loops (kernel size,
// groups per invocation, heads, window) as specialization constants, one pipeline each,
// all created when the network loads.
#pragma once

#include "ngi/engine/super_resolution.h"
#include "ngi_shared.h"

#include <vulkan/vulkan.h>

#include <array>
#include <compare>
#include <map>
#include <vector>

namespace ngi::vk {

enum class SrShader : uint32_t { Conv, Attention, PixelShuffle, BilinearSkip, Input, Output };

// One pipeline: the shader and its specialization constants (ids 0 .. 4).
struct SrPipelineKey {
    SrShader shader = SrShader::Conv;
    std::array<uint32_t, 5> constants{};
    auto operator<=>(const SrPipelineKey&) const = default;
};

// A tensor of the current workspace as the kernels see it.
struct SrTensorView {
    VkBufferView view = VK_NULL_HANDLE;  // rgba32f texel view (uniform + storage texel buffer)
    uint32_t channels = 0, width = 0, height = 0;
    uint32_t groups() const { return (channels + 3) / 4; }
};

struct SuperResolution::Kernels {
    Kernels(const Context& context);
    ~Kernels();
    Kernels(const Kernels&) = delete;
    Kernels& operator=(const Kernels&) = delete;

    // Compiles the pipelines of `keys` not yet created (through `cache` when not null),
    // on up to min(hardware threads, 4) threads: a driver like lavapipe compiles each
    // pipeline on the calling thread. ngi::Error if one fails.
    void create(const std::vector<SrPipelineKey>& keys, VkPipelineCache cache);
    // A pipeline created by create(); ngi::Error if it was not.
    VkPipeline pipeline(const SrPipelineKey& key) const;
    size_t pipelineCount() const { return pipelines_.size(); }

    // Records one dispatch of `shader` over `groupsX x groupsY x groupsZ` workgroups with
    // `set` bound (the weights window at `weightsOffset`) and `push`.
    void dispatch(VkCommandBuffer cmd, VkPipeline pipeline, VkDescriptorSet set, uint32_t weightsOffset,
                  const gpu::SrPushConstants& push, uint32_t groupsX, uint32_t groupsY, uint32_t groupsZ) const;

    const Context& context;
    VkDescriptorSetLayout setLayout = VK_NULL_HANDLE;
    VkPipelineLayout layout = VK_NULL_HANDLE;

private:
    std::map<SrPipelineKey, VkPipeline> pipelines_;
};

// Workgroups to cover n items with `local` items per workgroup.
inline uint32_t srGroups(uint32_t n, uint32_t local) { return (n + local - 1) / local; }

}  // namespace ngi::vk
