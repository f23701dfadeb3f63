// ngi nn: the super-resolution network's architecture as a plain op list.
//
// Paper: "Neural Geometry Image-Based Representations with Optimal Transport", section 3.2
// and "Implementation Details": a position branch and a normal branch of convolutions,
// cross-attention fusing normal features into the position stream, residual blocks
// (He et al. 2016), PixelShuffle upsampling (Shi et al. 2016, ESPCN), a final convolution,
// and a skip connection from the bilinearly upsampled input (the network learns the
// residual). The op list (ngi/network_weights.h) is the single definition: the libtorch
// module, the C++ reference forward and the engine's GLSL all execute the same list.
//
// Default network (x8, 129 -> 1025 samples), all heavy work at the STORED resolution:
//   position branch  conv3x3 3->F, act; (branchConvs-1) x conv3x3 F->F, act      -> P
//   normal branch    conv3x3 3->F, act; (branchConvs-1) x conv3x3 F->F, act      -> N
//   cross-attention  q = conv1x1(P), k = conv1x1(N), v = conv1x1(N) (no act);
//                    a = NeighborhoodCrossAttention(q, k, v): each pixel attends to the
//                    window x window neighbourhood of normal features (local attention,
//                    cost linear in pixels; heads of F/heads channels, scale 1/sqrt(d));
//                    X = conv1x1(a) + P
//   trunk            resBlocks x { X = conv3x3(act(conv3x3(X))) + X }
//   sub-pixel        u = act(conv1x1 F->U (X)); s = conv3x3 U -> 3*f^2 (u)
//                    PixelShuffle(f) + crop -> 3 channels at full resolution
//                    (x32, x64: 3 f^2 would pass kMaxNetworkChannels, so two stages:
//                    u' = act(conv3x3 U -> U*(f/8)^2 (u)), PixelShuffle(f/8) + crop, then
//                    s = conv3x3 U -> 3*8^2 (u') at f/8 times the stored resolution,
//                    PixelShuffle(8) + crop)
//   final conv       r = conv3x3 3->3 at full resolution (the only full-res conv: thin)
//   skip             out = upsample_x f(input positions) + r, upsample = normal-projected
//                    cubic Hermite (HermiteSkip, default: it reads the stored normals too),
//                    Catmull-Rom cubic (CubicSkip) or bilinear (the paper's skip). The
//                    residual the network must learn is what the skip misses. Catmull-Rom
//                    alone is far closer than bilinear, which a bilinear-skip network spends
//                    its first steps relearning; Hermite with the stored normals' tangent
//                    planes is closer still along the normal (docs/networks.md), a product of
//                    normals and positions that convolutions + LeakyReLU do not learn from
//                    the patch gradients in thousands of steps (measured: they tie Catmull-Rom).
// 3x3 convolutions use replicate (clamp-to-edge) padding: the image border is the cut
// seam, whose samples continue outwards rather than dropping to 0.
#pragma once

#include "ngi/network_weights.h"

#include <cstdint>
#include <string>

namespace ngi::nn {

// Factor of the last sub-pixel stage of a two-stage upsampling (x32, x64).
inline constexpr uint32_t kLastStageFactor = 8;

struct SuperResolutionConfig {
    uint32_t scaleFactor = 8;  // 8: stored 128 -> 1024; 2-64 valid (one model each)
    uint32_t features = 32;    // F: channels of both branches and the trunk
    uint32_t branchConvs = 2;  // 3x3 convolutions per input branch
    uint32_t attentionHeads = 4;
    uint32_t attentionWindow = 3;  // neighbourhood side (odd)
    uint32_t resBlocks = 2;
    uint32_t upsampleFeatures = 16;  // U: channels entering the sub-pixel convolution
    Activation activation = Activation::LeakyReLU;
    float activationSlope = 0.1f;
    LayerKind skip = LayerKind::HermiteSkip;  // HermiteSkip (default), CubicSkip or BilinearSkip
};

// The op list of `config` with parameters sized and zero-filled (the trainer initializes
// them). Throws ngi::Error if the config is invalid (zero sizes, heads not dividing F,
// even window, scale factor not a power of two in [2, 64]).
NetworkWeights buildSuperResolutionNetwork(const SuperResolutionConfig& config, const std::string& name);

// Transfer learning across scale factors: copies `donor`'s trained parameters into `network`
// (the same op list up to the scale factor, e.g. an x2 network started from the shipped x4).
// Every Conv with the donor's shape at the same layer index is copied. The sub-pixel
// convolution (the Conv feeding a PixelShuffle) of factor f, where the donor's factor F is a
// multiple of f, takes the donor's output channels at the fine offsets both grids share:
// channel c*f*f + i*f + j <- c*F*F + (i*F/f)*F + j*F/f, i.e. the residual the donor predicts at
// those sub-sample positions (a level finer than the donor's input has proportionally smaller
// residuals, which training rescales quickly). Other layers keep `network`'s parameters.
// Returns the number of Conv layers copied. Throws ngi::Error if the layer lists differ in
// length or in any layer's kind, or a mismatched Conv is not such a sub-pixel convolution.
size_t transferParameters(NetworkWeights& network, const NetworkWeights& donor);

// One line describing a config (for metadata and logs), e.g. "x8 F32 branch2 heads4 ...".
std::string describe(const SuperResolutionConfig& config);

}  // namespace ngi::nn
