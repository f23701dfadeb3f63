// ngi nn: training data and the training loop of the super-resolution network.
//
// Paper: "Neural Geometry Image-Based Representations with Optimal Transport", section 3.2
// ("Reconstruction Losses", "Implementation Details"): loss 0.5 L1 + 0.5 (1 - MS-SSIM),
// Adam with lr 5e-5, augmentation by 90-degree rotations and flips. Optionally (ngi-train
// --normal-l1 W) plus W x the point-to-plane L1, the error along the target's normal, which
// is what a surface distance sees (the paper's terms also charge sliding within the surface).
//
// Data: full-resolution geometry images as 16-bit RGB PNG pairs NAME_position.png (xyz in
// [0,1]) and NAME_normal.png (u16 = (n + 1) / 2 * 65535, the asset's NORM convention),
// written by `ngi-bake --export-full DIR` (NAME_positions.png / NAME_normals.png also read). The network input is the nested mip level
// scaleFactor times coarser (mip_pyramid.h); the target is the full image.
//
// Patches: a batch is B random square input windows of `patchSamples` coarse samples with
// their fine targets ((patchSamples - 1) f + 1 samples). The loss is taken on a fixed-size
// sub-window that keeps `contextSamples` coarse samples of context on each side, except on
// sides where the window touches the image border (the real seam): there the loss reaches
// the border, so the network learns the border behaviour of the full image, and elsewhere
// it sees the same context as in a full-image forward pass. Augmentation: one of the 8
// symmetries of the square per patch (transpose, vertical and horizontal flips), applied to
// input and target alike; they commute with nested subsampling (sizes 2^k + 1).
#pragma once

#include "ngi/geometry_image.h"
#include "ngi/network_weights.h"
#include "ngi/nn/ms_ssim.h"
#include "ngi/nn/torch_network.h"

#include <torch/torch.h>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace ngi::nn {

// One full-resolution training geometry image, as 3 x S x S float tensors.
struct TrainingImage {
    std::string name;
    torch::Tensor positions;                       // full resolution (the target)
    torch::Tensor normals;                         // full resolution unit normals (the point-to-plane term)
    torch::Tensor coarsePositions, coarseNormals;  // nested level scaleFactor times coarser (the input)
    // Optional: the input as a reader decodes it from an asset coded at each of
    // DecodedInputOptions::steps (one variant per step); a patch draws one at random.
    std::vector<torch::Tensor> decodedPositions, decodedNormals;
};

// Training on decoded inputs: the stored level quantized to u16, coded and
// decoded by the asset codec (ngi/pyramid_codec.h through applyAssetCoding, normals as the
// reader rebuilds them with 0 residual bits: the prediction from the decoded positions), so
// the network also removes coding noise. Empty steps: the plain nested level (no variants).
struct DecodedInputOptions {
    std::vector<uint32_t> steps;  // each in [1, kMaxPyramidStep], units of 1/65536 of the box
    uint32_t tangentScale = 0;    // the codec's tangent scale, in [0, kMaxTangentScale]
};

// The stored level `positions` (in [0,1]^3) / `normals` (unit) as a reader of an asset coded at
// `step` with `tangentScale` and no normal residual gets them: positions within step / 2 of
// their u16 quantization, normals predicted from those positions. ngi::Error on a size that is
// not 2^k + 1 or a step / tangent scale outside the codec's ranges.
std::pair<GeometryImage, GeometryImage> decodedStoredLevel(const GeometryImage& positions, const GeometryImage& normals,
                                                           uint32_t step, uint32_t tangentScale);

// Checks decoded-input options; ngi::Error naming the bad value.
void validateDecodedInputOptions(const DecodedInputOptions& options);

// Converts geometry images (full resolution, size 2^k + 1) into a training image, with one
// decoded input variant per decoded.steps entry.
TrainingImage makeTrainingImage(const std::string& name, const GeometryImage& positions, const GeometryImage& normals,
                                uint32_t scaleFactor, const DecodedInputOptions& decoded = {});

// Loads every NAME_position.png / NAME_normal.png pair in `directory` (sorted by name).
// ngi::Error naming the file on: a missing directory, no pairs, a positions file without
// its normals, unreadable/corrupt PNGs, not 16-bit RGB, not square 2^k + 1, sizes that
// differ within a pair, or a size too small for `scaleFactor`.
std::vector<TrainingImage> loadTrainingSet(const std::filesystem::path& directory, uint32_t scaleFactor,
                                           const DecodedInputOptions& decoded = {});

struct PatchOptions {
    uint32_t patchSamples = 37;   // coarse samples per input window side
    uint32_t contextSamples = 6;  // coarse context kept outside the loss window (interior sides)
    uint32_t batchSize = 8;
    float borderProbability = 0.2f;  // chance per axis to snap the window to each image border
};

// A batch: inputs N x 3 x P x P, targets N x 3 x T x T (the loss window), and where each
// loss window sits in the network output ((P-1)f+1 per side).
struct PatchBatch {
    torch::Tensor positions, normals, target;
    torch::Tensor targetNormals;                     // the target's unit normals, cropped like `target`
    std::vector<std::array<int64_t, 2>> lossOrigin;  // (row, column) in the output
    int64_t lossSize = 0;
};

// Side of the loss window for `options` at `scaleFactor`; ngi::Error if it is < 1.
int64_t lossWindowSize(const PatchOptions& options, uint32_t scaleFactor);

// Draws a batch (random image, window and symmetry per patch; with decoded variants, a random
// variant per patch, drawn after the window). ngi::Error if a coarse image
// is smaller than patchSamples.
PatchBatch samplePatches(const std::vector<TrainingImage>& images, uint32_t scaleFactor, const PatchOptions& options,
                         std::mt19937_64& rng);

struct LossTerms {
    torch::Tensor total;  // 0.5 L1 + 0.5 (1 - MS-SSIM) + normalL1Weight x point-to-plane L1, differentiable
    double l1 = 0.0, msSsim = 0.0, pointToPlaneL1 = 0.0;
};

// Mean |<restored - target, targetNormal>| over the samples of B x 3 x H x W tensors: the
// error along the surface normal, the part of a position error that moves the surface (and so
// the Chamfer distance, DESIGN.md "Metrics"). The paper's L1 and MS-SSIM also charge errors
// along the surface, which only slide samples within it.
torch::Tensor pointToPlaneL1(const torch::Tensor& restored, const torch::Tensor& target,
                             const torch::Tensor& targetNormals);

// The training loss of `net` on `batch` (output cropped to each patch's loss window): the
// paper's 0.5 L1 + 0.5 (1 - MS-SSIM), plus normalL1Weight x pointToPlaneL1 (0: the paper's).
LossTerms trainingLoss(SuperResolutionNet& net, const PatchBatch& batch, const MsSsimOptions& msSsimOptions,
                       double normalL1Weight = 0.0);

// The loss is multiplied by this before backpropagation (the reported loss is not). Position
// errors are ~1e-4 of the [0,1] scale, so raw gradients of the trunk are ~1e-10 to 1e-12:
// below Adam's epsilon (1e-8), where Adam stops normalizing and the trunk does not train.
// Scaling the loss is the same as Adam with epsilon / kOptimizerLossScale; the minimizer is
// unchanged.
inline constexpr double kOptimizerLossScale = 1e4;

struct TrainOptions {
    uint64_t steps = 20000;
    double learningRate = 5e-5;
    uint64_t seed = 1;
    PatchOptions patches;
    MsSsimOptions msSsim;
    // Weight of the point-to-plane L1 term added to the paper's loss (trainingLoss); 0: the
    // paper's loss alone.
    double normalL1Weight = 0.0;
    std::filesystem::path checkpointDirectory;  // empty: no checkpoints
    uint64_t checkpointEvery = 500;
    bool resume = false;  // continue from checkpointDirectory's checkpoint
    // Validation hook (e.g. Chamfer distance of a development mesh once ngi-eval exists):
    // called every validateEvery steps with the current weights; its value is reported.
    std::function<double(const NetworkWeights&)> validate;
    uint64_t validateEvery = 1000;
};

struct TrainProgress {
    uint64_t step = 0, totalSteps = 0, firstStep = 0;
    double loss = 0.0, l1 = 0.0, msSsim = 0.0;
    double seconds = 0.0;              // wall time since this run started
    double validation = std::nan("");  // last validation value (NaN: none yet)
};

// Trains `net` (which must hold its initial or resumed weights) with Adam. Calls
// `progress` after every step (the caller prints). Writes checkpoints atomically:
// DIR/checkpoint.ngiw (weights, metadata {"step": N}) and DIR/checkpoint.optim.pt. With
// options.resume, `net` must have been created from readCheckpoint() and the optimizer
// state and step are restored. Returns the last progress.
TrainProgress train(SuperResolutionNet& net, const std::vector<TrainingImage>& images, const TrainOptions& options,
                    const std::function<void(const TrainProgress&)>& progress);

// Whole-image restore error of `net` against bilinear and bicubic upsampling, per image: mean and
// max absolute difference to the full image, in the normalized [0,1] position scale.
// (A stand-in validation until ngi-eval's Chamfer distance is available.)
struct RestoreError {
    std::string name;
    double networkL1 = 0.0, bilinearL1 = 0.0, networkMax = 0.0, bilinearMax = 0.0;
    double bicubicL1 = 0.0, bicubicMax = 0.0;  // Catmull-Rom (CubicSkip's upsampling) of the same level
    double hermiteL1 = 0.0, hermiteMax = 0.0;  // HermiteSkip's upsampling (stored normals) of the same level
};
std::vector<RestoreError> evaluateRestore(SuperResolutionNet& net, const std::vector<TrainingImage>& images);

// The checkpoint's weights and the step it was written at; ngi::Error naming the file if it
// is missing or corrupt.
NetworkWeights readCheckpoint(const std::filesystem::path& directory, uint64_t& step);

}  // namespace ngi::nn
