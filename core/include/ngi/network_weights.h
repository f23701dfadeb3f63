// ngi core: the super-resolution network's weights file (.ngiw), shared by the trainer
// (offline/nn, libtorch) and the engine (GLSL compute). No libtorch, no Vulkan here.
//
// The file describes the network as a plain op list over activation tensors plus the fp32
// parameters, so the engine builds one compute pipeline per layer without knowing how the
// network was designed (paper section 3.2 / "Implementation Details"; offline/nn/README.md
// documents the default architecture).
//
// Tensors. An activation tensor is a C x H x W fp32 feature map on a geometry-image sample
// grid. Its "grid factor" g says where it lives: with S samples per side at the input
// (stored) level, the tensor has (S - 1) * g + 1 samples per side, sample i at coarse
// coordinate i / g (geometry_image.h: samples lie ON the square's border). Tensor 0 is the
// stored position level (3 channels, [0,1]^3), tensor 1 the stored normal level (3 channels,
// unit vectors), both g = 1. Every layer writes one NEW tensor (single assignment), so
// validation is one forward sweep and the engine can alias buffers by liveness.
//
// Layers (exact semantics; the C++ reference forward in offline/nn is the executable spec):
//   Conv: out[o] = act(bias[o] + sum_{i,ky,kx} w[o][i][ky][kx] * in[i](y+ky-r, x+kx-r))
//         (+ residual[o] if inputs[1] is set; added AFTER the activation). k = 1 or 3,
//         r = k / 2; weights are PyTorch OIHW: w at weightOffset + ((o*I + i)*k + ky)*k + kx.
//         Padding Zero reads 0 outside the image, Replicate clamps the coordinate.
//   NeighborhoodCrossAttention (local attention, cost linear in pixels): inputs q, k, v
//         (C channels each, same grid), `heads` heads of d = C / heads channels; for each
//         pixel p and head h, over the window offsets o in [-r, r]^2 (r = kernelSize / 2)
//         whose p + o lies INSIDE the image (the others are masked out, not padded):
//           logit_o = attentionScale * sum_{c in head h} q[c](p) * k[c](p + o)
//           out[c](p) = sum_o softmax_o(logit) * v[c](p + o).
//   PixelShuffle: in has C * f^2 channels on grid g, out has C channels on grid g * f:
//         out[c](Y, X) = in[c*f*f + (Y % f)*f + (X % f)](Y / f, X / f) (PyTorch order), then
//         CROPPED to (S - 1) * g * f + 1 samples per side: fine sample f*y + i sits at coarse
//         coordinate y + i / f, so the first samples are exactly the nested fine grid and the
//         f - 1 trailing columns/rows (beyond the last coarse sample) are dropped.
//   BilinearSkip: inputs[0] coarse (C channels, grid g), inputs[1] fine (C channels, grid
//         g * f): out = bilinear(inputs[0]) + inputs[1], where fine sample X reads the coarse
//         samples X / f and X / f + 1 with weight (X % f) / f: exact interpolation (coarse
//         samples are reproduced), PyTorch interpolate(align_corners = true).
//   CubicSkip: as BilinearSkip with Catmull-Rom cubic convolution (Keys 1981, a = -1/2, the
//         third-order accurate one) instead: with x0 = X / f, t = (X % f) / f and the weights
//         w(t) = (-t^3/2 + t^2 - t/2, 3t^3/2 - 5t^2/2 + 1, -3t^3/2 + 2t^2 + t/2, t^3/2 - t^2/2)
//         on the coarse samples x0 - 1 .. x0 + 2, separably: rows first,
//         out = fine + sum_ky wy[ky] R(y0 - 1 + ky), R(y) = sum_kx wx[kx] c(y, x0 - 1 + kx).
//         Samples beyond the border are extrapolated linearly, c(-1) = 2 c(0) - c(1) and
//         c(i >= n) = 2 c(n-1) - c(n-2) (rows of R likewise), so linear functions are
//         reproduced up to the border (the seam), where clamping would bend them.
//   HermiteSkip: inputs[0] coarse positions (3 channels, grid g), inputs[1] fine (3 channels,
//         grid g * f), inputs[2] coarse unit normals (3 channels, grid g): out = fine + cubic
//         Hermite interpolation whose node tangents are the Catmull-Rom ones projected onto the
//         tangent plane of the stored normal (the normals are the surface's derivative
//         information, which positions alone only estimate). Rows first: for coarse row y and
//         fine column X, x0 = X / f, x1 = min(x0 + 1, w - 1), t = (X % f) / f,
//           m(y, x) = (c(y, x+1) - c(y, x-1)) / 2, c(y, 1) - c(y, 0) at x = 0,
//                     c(y, w-1) - c(y, w-2) at x = w - 1 (Catmull-Rom's linear extrapolation);
//           m'(y, x) = m - n (n . m), n = normal(y, x);
//           R(y, X) = h00(t) c(y, x0) + h10(t) m'(y, x0) + h01(t) c(y, x1) + h11(t) m'(y, x1),
//           h00 = 2t^3 - 3t^2 + 1, h10 = t^3 - 2t^2 + t, h01 = -2t^3 + 3t^2, h11 = t^3 - t^2;
//           N(y, X) = normalize(Catmull-Rom of the normals along x, as CubicSkip's rows)
//                     (n(y, x0) if that is 0): C1 like R, so the columns add no creases.
//         Then columns: the same along y on R(., X) with the normals N(., X). With every
//         normal orthogonal to its tangents this is exactly CubicSkip.
//
// File layout (little-endian):
//   magic "\x89NGW\r\n\x1a\n" (8 bytes), u32 formatVersion, u32 reserved (0),
//   u64 bodyBytes (= file size - 32), u32 bodyCrc32 (zlib crc32 of the body), u32 reserved (0)
//   body: u32 scaleFactor, u32 tensorCount, u32 outputTensor, u32 layerCount,
//         u64 parameterCount, string name, string metadata (u32 length + bytes each),
//         zero padding to a 4-byte boundary,
//         layerCount records of 16 u32/f32 fields (64 bytes):
//           kind, inputs[0], inputs[1], inputs[2], output, inChannels, outChannels,
//           kernelSize, padding, activation, activationSlope (f32), heads,
//           attentionScale (f32), factor, weightOffset, biasOffset
//         parameterCount f32 parameters.
// Format version history: 1 = this layout (HermiteSkip, kind 6, added without a version
// change: older readers reject it as an unknown layer kind).
//
// Resource limits. A weights file is untrusted input: every consumer runs its op list, so
// the validator (hence the reader, before any restore runs, and the writer) bounds what one
// restore can cost. Work and memory are counted per OUTPUT sample, i.e. independent of the
// input size: a tensor on grid g holds (g / f)^2 samples per output sample (f = the scale
// factor; exact in the limit of large inputs, which is where the cost is). The shipped
// assets/sr-x8.ngiw (NetworkWeights.ShippedNetworkIsWellWithinTheLimits prints its figures)
// is 18 layers, 192 channels at most, 89956 parameters, 1485 multiply-adds and 18.8
// activation values per output sample: 5x to 50x below every limit. At the largest limit a
// restore to 1025^2 is 8.6e9 multiply-adds (seconds, in the single-threaded C++ reference
// and on lavapipe alike) and at most 0.5 GB of activations; to 4097^2, 16x that.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace ngi {

inline constexpr uint32_t kNetworkWeightsVersion = 1;
inline constexpr uint32_t kNoTensor = 0xffffffffu;
inline constexpr uint32_t kPositionInputTensor = 0;
inline constexpr uint32_t kNormalInputTensor = 1;

inline constexpr uint32_t kMaxNetworkLayers = 256;                 // tensors: at most layers + 2
inline constexpr uint32_t kMaxNetworkChannels = 1024;              // channels of any tensor
inline constexpr uint64_t kMaxNetworkParameters = 1u << 22;        // 16 MiB of fp32
inline constexpr double kMaxMultiplyAddsPerOutputSample = 8192.0;  // convolutions + attention
inline constexpr double kMaxActivationsPerOutputSample = 128.0;    // fp32 values of all tensors together

enum class LayerKind : uint32_t {
    Conv = 1,
    NeighborhoodCrossAttention = 2,
    PixelShuffle = 3,
    BilinearSkip = 4,
    CubicSkip = 5,
    HermiteSkip = 6
};

// BilinearSkip, CubicSkip or HermiteSkip: out = upsample(inputs[0]) + inputs[1].
inline bool isSkip(LayerKind kind)
{
    return kind == LayerKind::BilinearSkip || kind == LayerKind::CubicSkip || kind == LayerKind::HermiteSkip;
}
enum class Activation : uint32_t { None = 0, ReLU = 1, LeakyReLU = 2 };
enum class Padding : uint32_t { Zero = 0, Replicate = 1 };

// One op of the network. Fields a kind does not use are 0 (or kNoTensor for inputs).
struct NetworkLayer {
    LayerKind kind = LayerKind::Conv;
    std::array<uint32_t, 3> inputs{kNoTensor, kNoTensor, kNoTensor};  // see the header comment
    uint32_t output = kNoTensor;
    uint32_t inChannels = 0, outChannels = 0;
    uint32_t kernelSize = 0;          // Conv: 1 or 3; attention: window side (odd)
    Padding padding = Padding::Zero;  // Conv
    Activation activation = Activation::None;
    float activationSlope = 0.0f;  // LeakyReLU: y = x < 0 ? slope * x : x
    uint32_t heads = 0;            // attention
    float attentionScale = 0.0f;   // attention: logits = scale * q.k
    uint32_t factor = 0;           // PixelShuffle, BilinearSkip, CubicSkip
    uint32_t weightOffset = 0;     // Conv: first weight in NetworkWeights::parameters
    uint32_t biasOffset = 0;       // Conv: first bias in NetworkWeights::parameters

    bool operator==(const NetworkLayer&) const = default;
};

// The network: op list + parameters. `scaleFactor` is the upsampling of the whole network
// (8 for 128 -> 1024); the output tensor has 3 channels (positions) on grid scaleFactor.
// `source` says where the network came from, for error messages only: the readers set it to
// the path (or the name they were given, e.g. "the asset's WGHT chunk"); it is not
// serialized and not part of the network's identity (operator== and networkHash ignore it).
struct NetworkWeights {
    std::string name;      // network id (the asset's networkId)
    std::string metadata;  // free-form JSON text (architecture, training state)
    uint32_t scaleFactor = 8;
    uint32_t tensorCount = 2;
    uint32_t outputTensor = kNoTensor;
    std::vector<NetworkLayer> layers;
    std::vector<float> parameters;
    std::string source;

    // Every field but `source` (keep in sync when adding one).
    bool operator==(const NetworkWeights& o) const
    {
        return name == o.name && metadata == o.metadata && scaleFactor == o.scaleFactor &&
            tensorCount == o.tensorCount && outputTensor == o.outputTensor && layers == o.layers &&
            parameters == o.parameters;
    }
};

// What error messages call `network`: its source, else "network 'NAME'", else "network".
std::string networkLabel(const NetworkWeights& network);

// Shape of an activation tensor: channels and grid factor (see the header comment).
struct TensorShape {
    uint32_t channels = 0;
    uint32_t gridFactor = 0;  // 0 = not (yet) defined
};

// Checks every rule above (single assignment, channel and grid consistency, parameter
// ranges in bounds, finite scalars, output = 3 channels on grid scaleFactor, the resource
// limits) and returns the shape of every tensor. Throws ngi::Error "WHERE: problem" naming
// the layer, or the limit and the network's figure.
std::vector<TensorShape> validateNetwork(const NetworkWeights& network, const std::string& where);

// The figures the resource limits bound (see the header comment).
struct NetworkFigures {
    uint32_t layers = 0;
    uint32_t maxChannels = 0;  // of any tensor
    uint64_t parameters = 0;
    double multiplyAddsPerOutputSample = 0.0;  // convolutions and attention, as networkMultiplyAdds
    double activationsPerOutputSample = 0.0;   // every tensor, inputs included
};

// The figures of a network that passes validateNetwork's structural rules (`shapes` is its
// result); no limit is checked here.
NetworkFigures networkFigures(const NetworkWeights& network, const std::vector<TensorShape>& shapes);

// Serializes (after validateNetwork). Throws ngi::Error on an invalid network.
std::vector<uint8_t> serializeNetworkWeights(const NetworkWeights& network);

// Parses and validates. `name` is used in error messages (normally the path) and becomes the
// network's `source`. Rejects bad magic, unknown version, truncation, CRC mismatch,
// inconsistent networks and networks beyond the resource limits with one ngi::Error
// "NAME: problem". Never reads out of bounds, whatever the input; checks the layer and
// parameter counts against the limits before allocating them.
NetworkWeights parseNetworkWeights(std::span<const uint8_t> bytes, const std::string& name);

// Reads and parses a file; errors name the path, which becomes the network's `source`.
NetworkWeights readNetworkWeights(const std::filesystem::path& path);

// Writes atomically (writeFileAtomic): the destination is never half-written.
void writeNetworkWeights(const NetworkWeights& network, const std::filesystem::path& path);

// FNV-1a 64 of the serialized file: the identity an asset records as networkHash.
uint64_t networkHash(const NetworkWeights& network);

// Multiply-adds of one forward pass on an input of `storedSamples` per side (S x S),
// counting convolutions and attention (2 FLOPs per multiply-add); the data movement ops
// (shuffle, bilinear) are not counted.
uint64_t networkMultiplyAdds(const NetworkWeights& network, uint32_t storedSamples);

}  // namespace ngi
