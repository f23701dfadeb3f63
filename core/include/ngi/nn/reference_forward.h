// ngi nn: plain C++ reference forward pass of a network weights file (no libtorch, no
// Vulkan). It is the executable specification of the ops in ngi/network_weights.h: the
// GLSL kernels are tested against these functions, and these against libtorch.
// Single-threaded, fp32 accumulation, straightforward loops (clarity over speed).
#pragma once

#include "ngi/geometry_image.h"
#include "ngi/nn/feature_map.h"
#include "ngi/network_weights.h"

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace ngi::nn {

// Conv layer (kind Conv): `residual` may be null; it must be set iff layer.inputs[1] is.
FeatureMap conv2d(const FeatureMap& input, const NetworkLayer& layer, std::span<const float> parameters,
                  const FeatureMap* residual);

// NeighborhoodCrossAttention layer: q, k, v of equal shape. Reads only the window offsets
// inside the image, whatever the values; a NaN or overflowing logit gives non-finite outputs.
FeatureMap neighborhoodCrossAttention(const FeatureMap& q, const FeatureMap& k, const FeatureMap& v,
                                      const NetworkLayer& layer);

// PixelShuffle by `factor` followed by the crop to (H - 1) * factor + 1 rows and
// (W - 1) * factor + 1 columns.
FeatureMap pixelShuffleCrop(const FeatureMap& input, uint32_t factor);

// Exact bilinear upsampling of `coarse` by `factor` plus `fine` (which must be
// C x ((H-1)*factor+1) x ((W-1)*factor+1)).
FeatureMap bilinearSkip(const FeatureMap& coarse, const FeatureMap& fine, uint32_t factor);

// Catmull-Rom cubic upsampling of `coarse` by `factor` plus `fine` (CubicSkip, see
// ngi/network_weights.h); same shapes as bilinearSkip.
FeatureMap cubicSkip(const FeatureMap& coarse, const FeatureMap& fine, uint32_t factor);

// Normal-projected cubic Hermite upsampling of `coarse` (3 channels) by `factor` plus `fine`
// (HermiteSkip, see ngi/network_weights.h); `normals` are unit vectors on the coarse grid.
FeatureMap hermiteSkip(const FeatureMap& coarse, const FeatureMap& normals, const FeatureMap& fine, uint32_t factor);

// The cubic Hermite basis at fraction t in [0, 1): weights of p0, m0, p1, m1 (HermiteSkip).
std::array<float, 4> hermiteWeights(float t);

// The Catmull-Rom weights of the coarse samples x0 - 1 .. x0 + 2 at fraction t in [0, 1).
std::array<float, 4> catmullRomWeights(float t);

// The whole network on one input: positions and normals 3 x H x W (H, W >= 2, rectangles
// allowed). Returns the output tensor (3 x ((H-1)*f+1) x ((W-1)*f+1)). ngi::Error on an
// invalid network (validateNetwork, resource limits included) or mismatched inputs, and
// "LABEL: the restore produced non-finite values (layer N)" (LABEL = networkLabel) as soon
// as a layer's output holds a NaN or an infinity: every tensor is checked, not only the
// output, since a ReLU can turn a NaN into 0.
// `residualGain` (AssetChart::residualGain, in [0, 1]) blends the output toward the Catmull-Rom
// cubic c of the output skip layer's coarse input (its CubicSkip with a zero residual, i.e.
// bicubic upsampling of the stored positions): output = c + gain (network - c). 1 leaves every
// value bitwise as the network computes it; 0 gives c exactly. A gain other than 1 needs the
// output written by a skip layer (outputSkipLayer), else ngi::Error. For a CubicSkip output this
// is skip + gain x residual; for the shipped network's HermiteSkip the gain-0 end is the bicubic,
// not its Hermite skip: measured, the Hermite skip itself is what loses to bicubic on
// piecewise-flat meshes, so only a cubic endpoint makes the restore never worse than
// bicubic in image RMS.
FeatureMap referenceForward(const NetworkWeights& network, const FeatureMap& positions, const FeatureMap& normals,
                            float residualGain = 1.0f);

// The layer that writes the network's output when it is a skip (BilinearSkip, CubicSkip,
// HermiteSkip), else nullopt: the layer whose coarse input the gain's cubic endpoint upsamples.
std::optional<size_t> outputSkipLayer(const NetworkWeights& network);

// The blend's two endpoints: cubic = the Catmull-Rom upsampling of the output skip's coarse
// input, network = the output (referenceForward at gain 1, bitwise). referenceForward(net, p,
// n, g) = cubic + g (network - cubic). ngi::Error as referenceForward, and when the output is
// not written by a skip.
struct RestoreEndpoints {
    FeatureMap cubic, network;
};
RestoreEndpoints referenceForwardEndpoints(const NetworkWeights& network, const FeatureMap& positions,
                                           const FeatureMap& normals);

}  // namespace ngi::nn
