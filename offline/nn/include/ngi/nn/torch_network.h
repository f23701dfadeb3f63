// ngi nn: the super-resolution network as a libtorch module that executes the op list of a
// NetworkWeights (ngi/network_weights.h) layer by layer, so training, export, the C++
// reference forward and the engine's GLSL all run the same definition.
// Paper: "Neural Geometry Image-Based Representations with Optimal Transport", section 3.2.
#pragma once

#include "ngi/network_weights.h"

#include <torch/torch.h>

#include <cstdint>
#include <vector>

namespace ngi::nn {

// Gain of the residual output convolutions (see SuperResolutionNetImpl::gain_).
inline constexpr float kResidualGain = 1.0f / 1024.0f;  // a power of two: export/import are exact
// Gain of the 3x3 convolutions that read the stored positions (see gain_): they train as
// zero-sum kernels x this gain, so they see local differences (~1/128 of the [0,1] cube
// between neighbouring stored samples) at O(1) and are blind to the absolute position.
inline constexpr float kPositionInputGain = 128.0f;

class SuperResolutionNetImpl : public torch::nn::Module {
public:
    // Takes the op list of `network` and its parameters (copied). With `initialize` the
    // parameters are instead drawn from `seed`: He-uniform for convolutions followed by an
    // activation, fan-in uniform otherwise, zero biases; the convolutions that close a
    // residual branch are scaled down x0.1; the residual head (the sub-pixel convolution
    // before the shuffle on the way to the skip) x0.01 AND trains at kResidualGain; a square
    // full-resolution convolution after the shuffle starts at the identity (+ x0.01 noise).
    // The 3x3 convolutions of the stored positions train as zero-sum kernels x
    // kPositionInputGain (see zeroSum_); a loaded network keeps that projection only if its
    // kernels already sum to zero (one ngi-train wrote), any other runs exactly as stored.
    // So the untrained residual is ~1e-6 (the network starts at the skip's upsampling) and
    // the residual head learns directly, at the output's scale, like ESPCN's sub-pixel conv.
    // (Measured: with the gain on the 3->3 full-resolution conv instead, its inputs are
    // random features and 300 steps did not move the validation error.)
    SuperResolutionNetImpl(const NetworkWeights& network, bool initialize, uint64_t seed = 1);

    // positions, normals: N x 3 x H x W (H, W >= 2) -> N x 3 x ((H-1)f+1) x ((W-1)f+1).
    torch::Tensor forward(const torch::Tensor& positions, const torch::Tensor& normals);

    // Projects the weights that train under a constraint back onto it (zeroSum_): the
    // trainer calls this after every optimizer step (projected Adam); the constructor after
    // initializing. Loaded networks are used exactly as stored.
    void projectConstrainedWeights();

    // The op list with the current parameters (copied out of the module).
    NetworkWeights exportWeights() const;

    const NetworkWeights& layout() const { return layout_; }

private:
    NetworkWeights layout_;                     // op list; its parameters are not kept in sync
    std::vector<torch::Tensor> weight_, bias_;  // per layer (undefined for non-conv layers)
    // Per layer: the exported parameters are gain x the trained ones. The residual head
    // trains at kResidualGain: the residual they add is ~1e-4 of the [0,1]
    // position scale while Adam moves every raw weight by ~lr per step, so without the gain
    // each step's jitter (~lr x fan-in) is larger than the residual to be learnt.
    std::vector<float> gain_, biasGain_;  // weights, biases
    // Per layer: the kernel is kept at zero sum per (output, input) channel pair
    // (3x3 convolutions of the stored positions; projectConstrainedWeights). Why: the residual depends on the
    // local shape, not on where the surface sits in the cube; with raw positions the first
    // layer's features are ~99% absolute position and the shape signal (differences between
    // neighbours, ~1e-2, and their differences, ~1e-4) drowns (measured: the validation error
    // did not move off Catmull-Rom in 3500 steps).
    std::vector<bool> zeroSum_;
    torch::Tensor effectiveWeight(size_t layer) const;  // gain x trained weight: what forward and export use
};
TORCH_MODULE(SuperResolutionNet);

// The single ops, exposed for tests: exact libtorch counterparts of reference_forward.h.
torch::Tensor neighborhoodCrossAttention(const torch::Tensor& q, const torch::Tensor& k, const torch::Tensor& v,
                                         const NetworkLayer& layer);
torch::Tensor pixelShuffleCrop(const torch::Tensor& x, int64_t factor);
torch::Tensor bilinearUpsample(const torch::Tensor& coarse, int64_t factor);
torch::Tensor cubicUpsample(const torch::Tensor& coarse, int64_t factor);  // CubicSkip's upsampling
// HermiteSkip's upsampling: coarse positions and unit normals N x 3 x H x W.
torch::Tensor hermiteUpsample(const torch::Tensor& coarse, const torch::Tensor& normals, int64_t factor);

}  // namespace ngi::nn
