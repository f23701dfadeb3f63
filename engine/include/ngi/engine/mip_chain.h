// ngi engine: the compute pipelines that build a geometry image's levels on the GPU, the
// middle step of the data flow restore -> mip chain -> draw (docs/DESIGN.md): the bilinear
// restore of the finer levels (mip_upsample.comp) when no network restores level 0 (or the
// bicubic restore of level 0, mip_cubic_restore.comp, for a chart the network does not), the
// nested subsamples (mip_downsample.comp), the geomorph targets (morph_targets.comp) and
// the per-quad diagonal choice (quad_diagonals.comp), and the seam weld after each restored
// level (seam_weld.comp, ngi/seam.h). GeometryImageSurface::recordBuild
// records them; the SuperResolution network is the other restore.
#pragma once

#include "ngi/engine/context.h"
#include "ngi/engine/resources.h"

#include <vulkan/vulkan.h>

namespace ngi::vk {

class MipChainPipelines {
public:
    // Creates the set layout (three storage images: a level, its geomorph targets, its quad
    // diagonals), the pipeline layout (gpu::MipPushConstants) and the five pipelines.
    // ngi::Error on failure; everything created so far is destroyed.
    explicit MipChainPipelines(const Context& context);

    VkDescriptorSetLayout setLayout() const { return setLayout_.get(); }
    VkPipelineLayout layout() const { return layout_.get(); }
    VkPipeline downsample() const { return downsample_.get(); }
    VkPipeline upsample() const { return upsample_.get(); }
    VkPipeline cubicRestore() const { return cubicRestore_.get(); }
    VkPipeline morphTargets() const { return morph_.get(); }
    VkPipeline quadDiagonals() const { return quadDiagonals_.get(); }
    // The seam weld: set 0 = {storage image (the level), storage buffer (uvec2 pairs)},
    // push constants gpu::SeamWeldPushConstants.
    VkDescriptorSetLayout weldSetLayout() const { return weldSetLayout_.get(); }
    VkPipelineLayout weldLayout() const { return weldLayout_.get(); }
    VkPipeline weld() const { return weld_.get(); }
    // The weld across the charts of a split component (seam_weld_group.comp): set 0 = {storage
    // image (a chart's level), storage buffer (uvec2 pairs), storage buffer (uvec4 value slots)},
    // push constants gpu::GroupWeldPushConstants.
    VkDescriptorSetLayout groupWeldSetLayout() const { return groupWeldSetLayout_.get(); }
    VkPipelineLayout groupWeldLayout() const { return groupWeldLayout_.get(); }
    VkPipeline groupWeld() const { return groupWeld_.get(); }

private:
    UniqueDescriptorSetLayout setLayout_, weldSetLayout_, groupWeldSetLayout_;
    UniquePipelineLayout layout_, weldLayout_, groupWeldLayout_;
    UniquePipeline downsample_, upsample_, cubicRestore_, morph_, quadDiagonals_, weld_, groupWeld_;
};

// A set layout of three bindings of `type` (a level, its geomorph targets, its quad
// diagonals) for `stages`; shared by the mip chain and the draw.
VkDescriptorSetLayout createLevelSetLayout(VkDevice device, VkDescriptorType type, VkShaderStageFlags stages);
// A pipeline layout of one set and one push-constant range of `size` bytes.
VkPipelineLayout createPipelineLayout(VkDevice device, VkDescriptorSetLayout set, VkShaderStageFlags stages,
                                      uint32_t size);

}  // namespace ngi::vk
