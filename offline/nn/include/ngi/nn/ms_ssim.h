// ngi nn: multi-scale structural similarity, the structural half of the training loss.
//
// Paper: Wang, Simoncelli, Bovik 2003, "Multiscale structural similarity for image quality
// assessment" (the NGI paper's Eq. for L_struct). At scales j = 1..M (each a 2x2
// average-pool of the previous, odd trailing rows/columns dropped) with an 11-tap Gaussian
// window (sigma 1.5), no padding ("valid" filtering):
//   l(x,y) = (2 mu_x mu_y + C1) / (mu_x^2 + mu_y^2 + C1),
//   cs(x,y) = (2 sigma_xy + C2) / (sigma_x^2 + sigma_y^2 + C2), C1 = (k1 L)^2, C2 = (k2 L)^2,
//   MS-SSIM = mean_image(l cs)_M^{w_M} * prod_{j<M} mean_image(cs)_j^{w_j},
// per image and channel, then averaged over images and channels. Weights (0.0448, 0.2856,
// 0.3001, 0.2363, 0.1333) as in the paper, not renormalized. The per-scale means are
// clamped to >= 1e-6 before the power (negative structure correlations would give NaN).
// The image must be at least windowSize * 2^(M-1) samples per side.
#pragma once

#include <torch/torch.h>

#include <vector>

namespace ngi::nn {

struct MsSsimOptions {
    int windowSize = 11;
    double sigma = 1.5;
    double dataRange = 1.0;  // L: positions are normalized to [0,1]
    double k1 = 0.01, k2 = 0.03;
    std::vector<double> weights{0.0448, 0.2856, 0.3001, 0.2363, 0.1333};  // one per scale
};

// MS-SSIM of two N x C x H x W tensors (differentiable); a scalar tensor. ngi::Error on
// mismatched shapes or images too small for the number of scales.
torch::Tensor msSsim(const torch::Tensor& x, const torch::Tensor& y, const MsSsimOptions& options = {});

// Smallest side msSsim accepts for `options`.
int64_t msSsimMinimumSize(const MsSsimOptions& options);

}  // namespace ngi::nn
