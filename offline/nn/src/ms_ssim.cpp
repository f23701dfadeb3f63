// Multi-scale SSIM. Paper: Wang, Simoncelli, Bovik 2003, "Multiscale structural similarity
// for image quality assessment"; conventions in ngi/nn/ms_ssim.h.
#include "ngi/nn/ms_ssim.h"

#include "ngi/error.h"

#include <cmath>

namespace ngi::nn {
namespace {

torch::Tensor gaussianWindow(int size, double sigma, const torch::TensorOptions& options)
{
    std::vector<double> g(static_cast<size_t>(size));
    double sum = 0.0;
    for (int i = 0; i < size; ++i) {
        const double t = i - (size - 1) / 2.0;
        g[size_t(i)] = std::exp(-t * t / (2.0 * sigma * sigma));
        sum += g[size_t(i)];
    }
    for (double& v : g) v /= sum;
    return torch::from_blob(g.data(), {size}, torch::kFloat64).clone().to(options);
}

// Separable "valid" Gaussian filter of every channel.
torch::Tensor blur(const torch::Tensor& x, const torch::Tensor& window)
{
    const int64_t c = x.size(1), n = window.size(0);
    const torch::Tensor horizontal = window.view({1, 1, 1, n}).expand({c, 1, 1, n});
    const torch::Tensor vertical = window.view({1, 1, n, 1}).expand({c, 1, n, 1});
    namespace F = torch::nn::functional;
    const auto grouped = F::Conv2dFuncOptions().groups(c);
    return F::conv2d(F::conv2d(x, horizontal, grouped), vertical, grouped);
}

}  // namespace

int64_t msSsimMinimumSize(const MsSsimOptions& o)
{
    return int64_t(o.windowSize) << (o.weights.empty() ? 0 : o.weights.size() - 1);
}

torch::Tensor msSsim(const torch::Tensor& xIn, const torch::Tensor& yIn, const MsSsimOptions& o)
{
    if (xIn.dim() != 4 || xIn.sizes() != yIn.sizes())
        throw Error("MS-SSIM: inputs must be N x C x H x W of equal shape");
    if (o.weights.empty() || o.windowSize < 1) throw Error("MS-SSIM: needs at least one scale and a window");
    if (std::min(xIn.size(2), xIn.size(3)) < msSsimMinimumSize(o))
        throw Error("MS-SSIM: images of " + std::to_string(xIn.size(2)) + "x" + std::to_string(xIn.size(3)) +
                    " are smaller than " + std::to_string(msSsimMinimumSize(o)) + " for " +
                    std::to_string(o.weights.size()) + " scales");
    const double c1 = std::pow(o.k1 * o.dataRange, 2.0), c2 = std::pow(o.k2 * o.dataRange, 2.0);
    const torch::Tensor window = gaussianWindow(o.windowSize, o.sigma, xIn.options());
    torch::Tensor x = xIn, y = yIn;
    torch::Tensor result;
    for (size_t j = 0; j < o.weights.size(); ++j) {
        if (j > 0) {
            x = torch::avg_pool2d(x, 2);
            y = torch::avg_pool2d(y, 2);
        }
        // Second moments of values shifted by a per-image, per-channel constant (the mean of
        // both images): mathematically identical, but E[x^2] - mu^2 no longer cancels in
        // fp32 for smooth geometry images whose local variances are ~1e-6 of x^2.
        const torch::Tensor shift = (0.5 * (x.mean({2, 3}, true) + y.mean({2, 3}, true))).detach();
        const torch::Tensor xs = x - shift, ys = y - shift;
        const torch::Tensor muXs = blur(xs, window), muYs = blur(ys, window);
        const torch::Tensor sxx = blur(xs * xs, window) - muXs * muXs;
        const torch::Tensor syy = blur(ys * ys, window) - muYs * muYs;
        const torch::Tensor sxy = blur(xs * ys, window) - muXs * muYs;
        torch::Tensor map = (2.0 * sxy + c2) / (sxx + syy + c2);
        if (j + 1 == o.weights.size()) {
            const torch::Tensor muX = muXs + shift, muY = muYs + shift;
            map = map * (2.0 * muX * muY + c1) / (muX * muX + muY * muY + c1);
        }
        const torch::Tensor term = map.mean({2, 3}).clamp_min(1e-6).pow(o.weights[j]);  // N x C
        result = result.defined() ? result * term : term;
    }
    return result.mean();
}

}  // namespace ngi::nn
