// ngi engine: each chart's base colour (ngi/asset.h AssetChart::baseColor) as a sampled GPU
// image with its mip chain, for the adaptive draw's fragment stage. The chart's square is its
// own texture atlas: texel (x, y) of an S-texel image is the surface at grid uv (x, y) / (S - 1),
// so the shader samples at (uv (S - 1) + 0.5) / S. The mip chain is box-filtered in linear
// light on the CPU (sRGB images: the sampler filters in linear light too); sampling clamps to
// the edge, so nothing outside the chart bleeds in.
#pragma once

#include "ngi/asset.h"
#include "ngi/engine/context.h"
#include "ngi/engine/resources.h"

#include <vector>

namespace ngi::vk {

class ChartColorImages {
public:
    // Uploads every chart's base colour (VK_FORMAT_R8G8B8A8_SRGB, full mip chain) and one 1 x 1
    // image of ngi's default grey for charts without one (a real colour image has at least
    // 2 x 2 texels, so a shader can tell them apart); waits for the upload. ngi::Error on failure.
    ChartColorImages(const Context& context, const Asset& asset);

    // The view to sample for chart c (its own image, or the default grey).
    VkImageView view(size_t chart) const;
    // Trilinear, clamped to the edge.
    VkSampler sampler() const { return sampler_.get(); }
    // True when some chart has its own base colour.
    bool any() const { return any_; }
    // Whether chart c's colour has an alpha below 1 somewhere: its draw needs the alpha test
    // (NGI_SPEC_CUT_OUT in ngi_shared.h). cutsOut() alone: whether some chart's does.
    bool cutsOut(size_t chart) const { return cutsOut_[chart]; }
    bool cutsOut() const;
    // Device memory of the images, in bytes.
    VkDeviceSize bytes() const;

private:
    std::vector<UniqueImage> images_;  // [0]: the default grey; then one per coloured chart
    std::vector<size_t> imageOfChart_;
    std::vector<bool> cutsOut_;  // per chart
    UniqueSampler sampler_;
    bool any_ = false;
};

// The mip chain of an n x n sRGB RGBA8 image as Vulkan sizes it (level i: max(1, n >> i) per
// side, down to 1 x 1), each level the 2 x 2 box of the one before in linear light (the last
// row or column of an odd size folded into its neighbour's box). Level 0 is `rgba` itself.
std::vector<std::vector<uint8_t>> colorMipChain(const std::vector<uint8_t>& rgba, uint32_t n);

}  // namespace ngi::vk
