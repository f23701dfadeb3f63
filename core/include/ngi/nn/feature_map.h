// ngi core: the feature map, the one tensor type of the super-resolution network shared by the
// CPU reference forward (reference_forward.h), the engine's GLSL inference (SuperResolution
// run/readback) and the libtorch training code.
#pragma once

#include "ngi/geometry_image.h"

#include <cstdint>
#include <vector>

namespace ngi::nn {

// A C x H x W fp32 feature map, planar (CHW): value (c, y, x) at (c * height + y) * width + x.
struct FeatureMap {
    uint32_t channels = 0, height = 0, width = 0;
    std::vector<float> data;

    FeatureMap() = default;
    FeatureMap(uint32_t c, uint32_t h, uint32_t w) : channels(c), height(h), width(w), data(size_t(c) * h * w, 0.0f) {}
    float& at(uint32_t c, uint32_t y, uint32_t x) { return data[(size_t(c) * height + y) * width + x]; }
    float at(uint32_t c, uint32_t y, uint32_t x) const { return data[(size_t(c) * height + y) * width + x]; }
};

// A geometry image as a 3 x size x size feature map (channel = xyz), and back.
FeatureMap featureMapFromGeometryImage(const GeometryImage& image);
GeometryImage geometryImageFromFeatureMap(const FeatureMap& map);  // map must be 3 x S x S

}  // namespace ngi::nn
