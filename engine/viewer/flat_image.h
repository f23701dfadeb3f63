// ngi-view: the geometry image itself, shown flat as a 2D picture (view mode "geometry
// image"). One mip level is read back from the surface once, turned into RGBA8 (positions
// as RGB, or octahedral normals decoded to n * 0.5 + 0.5) and drawn as a textured rectangle
// with nearest sampling, so each sample of the level is one visible square.
#pragma once

#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"
#include "ngi/engine/surface.h"

#include <vulkan/vulkan.h>

#include <cstdint>

namespace ngi::view {

enum class FlatChannel : uint32_t { Positions = 0, Normals = 1 };

class FlatImageView {
public:
    // Pipeline for the renderer's formats (draws inside the same dynamic rendering pass).
    explicit FlatImageView(const vk::Renderer& renderer);
    ~FlatImageView();
    FlatImageView(const FlatImageView&) = delete;
    FlatImageView& operator=(const FlatImageView&) = delete;

    // Makes the picture show `level` of `surface` (reads it back and uploads it when it is
    // not what is shown already; waits for the GPU, call between frames). `generation`
    // identifies the surface (changes when another asset is opened).
    void show(const vk::GeometryImageSurface& surface, uint64_t generation, uint32_t level, FlatChannel channel);

    // Draws the picture as a square centred in the region x >= leftMargin of the viewport.
    void record(VkCommandBuffer cmd, VkExtent2D extent, float leftMargin) const;

    uint32_t size() const { return texture_->width; }
    VkDeviceSize gpuBytes() const { return texture_->bytes; }

private:
    const vk::Renderer& renderer_;
    // Owners, destroyed in reverse order (a constructor that throws frees what it made).
    vk::UniqueDescriptorSetLayout setLayout_;
    vk::UniquePipelineLayout layout_;
    vk::UniquePipeline pipeline_;
    vk::UniqueSampler sampler_;
    vk::UniqueDescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;  // freed with pool_
    vk::UniqueImage texture_;
    uint64_t shownGeneration_ = ~0ull;
    uint32_t shownLevel_ = ~0u;
    FlatChannel shownChannel_ = FlatChannel::Positions;
};

}  // namespace ngi::view
