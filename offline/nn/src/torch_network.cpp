// The super-resolution op list executed in libtorch (semantics in ngi/network_weights.h).
// Paper: "Neural Geometry Image-Based Representations with Optimal Transport", section 3.2;
// PixelShuffle: Shi et al. 2016 (ESPCN); residual blocks: He et al. 2016.
#include "ngi/nn/torch_network.h"

#include "ngi/nn/reference_forward.h"

#include "ngi/error.h"

#include <cmath>
#include <limits>

namespace ngi::nn {
namespace F = torch::nn::functional;

namespace {

torch::Tensor activate(const torch::Tensor& x, Activation a, float slope)
{
    switch (a) {
    case Activation::ReLU: return torch::relu(x);
    case Activation::LeakyReLU: return torch::leaky_relu(x, slope);
    default: return x;
    }
}

// How each convolution is initialized and trained (see SuperResolutionNetImpl::gain_).
enum class ConvRole { Trunk, ResidualClose, ResidualHead, FullResolution, PositionInput };

// Walking back from each skip's residual input: convolutions after the last PixelShuffle are
// full-resolution convs (initialized to the identity where square), the first convolution
// before it is the residual head (it computes the residual per sub-pixel; ESPCN's sub-pixel
// conv). Convolutions with a residual input close a residual branch.
std::vector<ConvRole> convRoles(const NetworkWeights& net)
{
    std::vector<ConvRole> role(net.layers.size(), ConvRole::Trunk);
    auto producer = [&](uint32_t tensor) -> int {
        for (size_t j = 0; j < net.layers.size(); ++j)
            if (net.layers[j].output == tensor) return int(j);
        return -1;
    };
    for (size_t i = 0; i < net.layers.size(); ++i)
        if (net.layers[i].kind == LayerKind::Conv && net.layers[i].inputs[1] != kNoTensor)
            role[i] = ConvRole::ResidualClose;
    for (size_t i = 0; i < net.layers.size(); ++i)
        if (net.layers[i].kind == LayerKind::Conv && net.layers[i].kernelSize > 1 &&
            net.layers[i].inputs[0] == kPositionInputTensor)
            role[i] = ConvRole::PositionInput;
    for (size_t i = 0; i < net.layers.size(); ++i) {
        if (!isSkip(net.layers[i].kind)) continue;
        bool shuffled = false;
        for (int j = producer(net.layers[i].inputs[1]); j >= 0; j = producer(net.layers[size_t(j)].inputs[0])) {
            const NetworkLayer& l = net.layers[size_t(j)];
            if (l.kind == LayerKind::PixelShuffle) {
                shuffled = true;
                continue;
            }
            if (l.kind != LayerKind::Conv) break;
            if (shuffled || j == 0 || producer(l.inputs[0]) < 0) {
                role[size_t(j)] = ConvRole::ResidualHead;
                break;
            }
            role[size_t(j)] = ConvRole::FullResolution;
        }
    }
    return role;
}

// True if every (output, input) kernel of the convolution sums to zero up to fp32 rounding
// of its terms: the layer was trained with the zero-sum projection (a network from
// ngi-train), so resuming keeps it; any other network is executed exactly as stored.
bool kernelsSumToZero(const NetworkWeights& net, const NetworkLayer& l)
{
    const size_t taps = size_t(l.kernelSize) * l.kernelSize;
    for (size_t k = 0; k < size_t(l.outChannels) * l.inChannels; ++k) {
        double sum = 0.0, magnitude = 0.0;
        for (size_t t = 0; t < taps; ++t) {
            const double w = net.parameters[l.weightOffset + k * taps + t];
            sum += w;
            magnitude += std::abs(w);
        }
        if (std::abs(sum) > 1e-6 * magnitude + 1e-30) return false;
    }
    return true;
}

}  // namespace

SuperResolutionNetImpl::SuperResolutionNetImpl(const NetworkWeights& network, bool initialize, uint64_t seed)
    : layout_(network)
{
    validateNetwork(network, network.name.empty() ? "network" : network.name);
    weight_.resize(network.layers.size());
    bias_.resize(network.layers.size());
    gain_.assign(network.layers.size(), 1.0f);
    biasGain_.assign(network.layers.size(), 1.0f);
    zeroSum_.assign(network.layers.size(), false);
    const std::vector<ConvRole> role = convRoles(network);
    for (size_t i = 0; i < network.layers.size(); ++i) {
        if (role[i] == ConvRole::PositionInput) {
            gain_[i] = kPositionInputGain;
            zeroSum_[i] = initialize || kernelsSumToZero(network, network.layers[i]);
        }
        if (role[i] == ConvRole::ResidualHead) gain_[i] = biasGain_[i] = kResidualGain;
        // A full-resolution conv's bias adds straight to the output: it trains at the gain too
        // (its weights multiply the tiny residual and stay at gain 1, near the identity).
        if (role[i] == ConvRole::FullResolution) biasGain_[i] = kResidualGain;
    }
    torch::Generator gen = at::detail::createCPUGenerator(seed);
    for (size_t i = 0; i < network.layers.size(); ++i) {
        const NetworkLayer& l = network.layers[i];
        if (l.kind != LayerKind::Conv) continue;
        const int64_t k = l.kernelSize;
        torch::Tensor w, b;
        if (initialize) {
            const double fanIn = double(l.inChannels) * k * k;
            const double gain = l.activation == Activation::None
                ? 1.0 / 3.0
                : 2.0 / (1.0 + double(l.activationSlope) * l.activationSlope);
            const double scale = role[i] == ConvRole::ResidualClose ? 0.1
                : role[i] == ConvRole::ResidualHead                 ? 0.01  // and x gain_ when used
                : role[i] == ConvRole::FullResolution               ? 0.01
                                                                    : 1.0;
            const double bound = std::sqrt(3.0 * gain / fanIn) * scale;
            w = torch::rand({l.outChannels, l.inChannels, k, k}, gen, torch::kFloat32) * (2.0 * bound) - bound;
            if (role[i] == ConvRole::FullResolution && l.inChannels == l.outChannels)
                for (int64_t c = 0; c < l.outChannels; ++c) w[c][c][k / 2][k / 2] += 1.0f;  // ~identity
            b = torch::zeros({l.outChannels}, torch::kFloat32);
        } else {
            w = torch::from_blob(const_cast<float*>(network.parameters.data() + l.weightOffset),
                                 {l.outChannels, l.inChannels, k, k}, torch::kFloat32)
                    .clone();
            b = torch::from_blob(const_cast<float*>(network.parameters.data() + l.biasOffset), {l.outChannels},
                                 torch::kFloat32)
                    .clone();
            w = w / gain_[i], b = b / biasGain_[i];  // powers of two: exact
        }
        weight_[i] = register_parameter("w" + std::to_string(i), w);
        bias_[i] = register_parameter("b" + std::to_string(i), b);
    }
    if (initialize) projectConstrainedWeights();
}

torch::Tensor SuperResolutionNetImpl::forward(const torch::Tensor& positions, const torch::Tensor& normals)
{
    if (positions.dim() != 4 || positions.size(1) != 3 || positions.sizes() != normals.sizes() ||
        positions.size(2) < 2 || positions.size(3) < 2)
        throw Error("super-resolution network: inputs must be N x 3 x H x W with H, W >= 2 and equal shapes");
    std::vector<torch::Tensor> t(layout_.tensorCount);
    t[kPositionInputTensor] = positions;
    t[kNormalInputTensor] = normals;
    for (size_t i = 0; i < layout_.layers.size(); ++i) {
        const NetworkLayer& l = layout_.layers[i];
        const torch::Tensor& x = t[l.inputs[0]];
        switch (l.kind) {
        case LayerKind::Conv: {
            torch::Tensor y;
            const torch::Tensor w = effectiveWeight(i);
            const torch::Tensor b = biasGain_[i] != 1.0f ? bias_[i] * biasGain_[i] : bias_[i];
            if (l.kernelSize == 3 && l.padding == Padding::Replicate)
                y = torch::conv2d(F::pad(x, F::PadFuncOptions({1, 1, 1, 1}).mode(torch::kReplicate)), w, b);
            else
                y = torch::conv2d(x, w, b, 1, int64_t(l.kernelSize / 2));
            y = activate(y, l.activation, l.activationSlope);
            if (l.inputs[1] != kNoTensor) y = y + t[l.inputs[1]];
            t[l.output] = y;
            break;
        }
        case LayerKind::NeighborhoodCrossAttention:
            t[l.output] = neighborhoodCrossAttention(x, t[l.inputs[1]], t[l.inputs[2]], l);
            break;
        case LayerKind::PixelShuffle: t[l.output] = pixelShuffleCrop(x, l.factor); break;
        case LayerKind::BilinearSkip: t[l.output] = bilinearUpsample(x, l.factor) + t[l.inputs[1]]; break;
        case LayerKind::CubicSkip: t[l.output] = cubicUpsample(x, l.factor) + t[l.inputs[1]]; break;
        case LayerKind::HermiteSkip: t[l.output] = hermiteUpsample(x, t[l.inputs[2]], l.factor) + t[l.inputs[1]]; break;
        }
    }
    return t[layout_.outputTensor];
}

torch::Tensor SuperResolutionNetImpl::effectiveWeight(size_t layer) const
{
    return gain_[layer] != 1.0f ? weight_[layer] * gain_[layer] : weight_[layer];
}

void SuperResolutionNetImpl::projectConstrainedWeights()
{
    torch::NoGradGuard noGrad;
    for (size_t i = 0; i < weight_.size(); ++i)
        if (zeroSum_[i]) weight_[i].sub_(weight_[i].mean({2, 3}, true));
}

NetworkWeights SuperResolutionNetImpl::exportWeights() const
{
    NetworkWeights out = layout_;
    for (size_t i = 0; i < layout_.layers.size(); ++i) {
        if (!weight_[i].defined()) continue;
        const NetworkLayer& l = layout_.layers[i];
        const torch::Tensor w = effectiveWeight(i).detach().contiguous().to(torch::kCPU);
        const torch::Tensor b = (bias_[i].detach() * biasGain_[i]).contiguous().to(torch::kCPU);
        std::copy(w.data_ptr<float>(), w.data_ptr<float>() + w.numel(), out.parameters.begin() + l.weightOffset);
        std::copy(b.data_ptr<float>(), b.data_ptr<float>() + b.numel(), out.parameters.begin() + l.biasOffset);
    }
    return out;
}

// Local (neighbourhood) cross-attention: every pixel's query attends to the window x window
// keys around it; cost O(pixels * window^2 * channels), linear in pixels. Out-of-image
// neighbours are masked (-inf logits), matching reference_forward.cpp. Written as one
// shifted view per window offset (10x faster on CPU than an unfold of keys and values).
torch::Tensor neighborhoodCrossAttention(const torch::Tensor& q, const torch::Tensor& k, const torch::Tensor& v,
                                         const NetworkLayer& l)
{
    const int64_t n = q.size(0), c = q.size(1), h = q.size(2), w = q.size(3);
    const int64_t r = l.kernelSize / 2, heads = l.heads, d = c / heads;
    const auto pad = F::PadFuncOptions({r, r, r, r});
    const torch::Tensor keys = F::pad(k, pad), values = F::pad(v, pad);
    const torch::Tensor inside = F::pad(torch::ones({1, 1, h, w}, q.options()), pad);
    auto shifted = [&](const torch::Tensor& x, int64_t dy, int64_t dx) {
        return x.narrow(2, r + dy, h).narrow(3, r + dx, w);
    };
    const torch::Tensor queries = q.reshape({n, heads, d, h, w});
    std::vector<torch::Tensor> logits, masks;
    for (int64_t dy = -r; dy <= r; ++dy)
        for (int64_t dx = -r; dx <= r; ++dx) {
            logits.push_back((queries * shifted(keys, dy, dx).reshape({n, heads, d, h, w})).sum(2));
            masks.push_back(shifted(inside, dy, dx));
        }
    const torch::Tensor outside = torch::stack(masks, 2) == 0;  // 1 x 1 x taps x h x w
    const torch::Tensor weights = torch::softmax((torch::stack(logits, 2) * double(l.attentionScale))
                                                     .masked_fill(outside, -std::numeric_limits<float>::infinity()),
                                                 2);  // n x heads x taps x h x w
    torch::Tensor out;
    int64_t tap = 0;
    for (int64_t dy = -r; dy <= r; ++dy)
        for (int64_t dx = -r; dx <= r; ++dx, ++tap) {
            const torch::Tensor term =
                weights.select(2, tap).unsqueeze(2) * shifted(values, dy, dx).reshape({n, heads, d, h, w});
            out = out.defined() ? out + term : term;
        }
    return out.reshape({n, c, h, w});
}

// PixelShuffle (PyTorch channel order) then crop: fine sample f*y + i sits at coarse
// coordinate y + i/f, so the first (H-1)f+1 rows/columns are the nested fine grid and the
// f-1 trailing ones (beyond the last coarse sample) are dropped.
torch::Tensor pixelShuffleCrop(const torch::Tensor& x, int64_t f)
{
    const int64_t h = x.size(2), w = x.size(3);
    return torch::pixel_shuffle(x, f).narrow(2, 0, (h - 1) * f + 1).narrow(3, 0, (w - 1) * f + 1);
}

// Exact interpolation on the sample grid: fine sample X sits at coarse coordinate X / f,
// which is align_corners = true with output size (H-1)f+1.
torch::Tensor bilinearUpsample(const torch::Tensor& coarse, int64_t f)
{
    const int64_t h = coarse.size(2), w = coarse.size(3);
    return F::interpolate(coarse,
                          F::InterpolateFuncOptions()
                              .size(std::vector<int64_t>{(h - 1) * f + 1, (w - 1) * f + 1})
                              .mode(torch::kBilinear)
                              .align_corners(true));
}

// Catmull-Rom along the last axis: the coarse row is padded by linear extrapolation (1 before,
// 2 after; network_weights.h), a 4-tap convolution per phase i (weights catmullRomWeights(i/f))
// gives f outputs per coarse sample, interleaved and cropped to (W-1)f+1.
torch::Tensor cubicUpsampleLastAxis(const torch::Tensor& x, int64_t f)
{
    const int64_t n = x.size(0), c = x.size(1), h = x.size(2), w = x.size(3);
    std::vector<float> taps;
    for (int64_t i = 0; i < f; ++i) {
        const std::array<float, 4> wt = catmullRomWeights(float(i) / float(f));
        taps.insert(taps.end(), wt.begin(), wt.end());
    }
    const torch::Tensor kernel = torch::from_blob(taps.data(), {f, 1, 1, 4}, torch::kFloat32).clone();
    const torch::Tensor flat = x.reshape({n * c, 1, h, w});
    const torch::Tensor before = 2.0 * flat.narrow(3, 0, 1) - flat.narrow(3, 1, 1);
    const torch::Tensor after = 2.0 * flat.narrow(3, w - 1, 1) - flat.narrow(3, w - 2, 1);
    const torch::Tensor padded = torch::cat({before, flat, after, after}, 3);
    const torch::Tensor phases = torch::conv2d(padded, kernel.to(x.device()));  // (n c) x f x h x w
    return phases.permute({0, 2, 3, 1}).reshape({n, c, h, w * f}).narrow(3, 0, (w - 1) * f + 1);
}

torch::Tensor cubicUpsample(const torch::Tensor& coarse, int64_t f)
{
    const torch::Tensor rows = cubicUpsampleLastAxis(coarse, f);                         // along X
    return cubicUpsampleLastAxis(rows.transpose(2, 3), f).transpose(2, 3).contiguous();  // along Y
}

namespace {

// HermiteSkip's node tangents along the last axis: Catmull-Rom's (one-sided at the ends)
// minus their component along the unit normals (channel dimension 1).
torch::Tensor projectedTangents(const torch::Tensor& p, const torch::Tensor& normals)
{
    const int64_t w = p.size(-1);
    const torch::Tensor m =
        torch::cat({p.narrow(-1, 1, 1) - p.narrow(-1, 0, 1), 0.5 * (p.narrow(-1, 2, w - 2) - p.narrow(-1, 0, w - 2)),
                    p.narrow(-1, w - 1, 1) - p.narrow(-1, w - 2, 1)},
                   -1);
    return m - normals * (normals * m).sum(1, true);
}

// Interleaves f phases (each ... x (w-1)) into (w-1)f samples and appends the last node.
torch::Tensor interleave(const std::vector<torch::Tensor>& phases, const torch::Tensor& last)
{
    const torch::Tensor s = torch::stack(phases, -1);
    std::vector<int64_t> sizes = phases[0].sizes().vec();
    sizes.back() *= int64_t(phases.size());
    return torch::cat({s.reshape(sizes), last}, -1);
}

// One axis (the last) of HermiteSkip: positions p and normals n (N x 3 x H x W) -> the
// Hermite samples and the interpolated, renormalized normals, both N x 3 x H x ((W-1)f+1).
std::pair<torch::Tensor, torch::Tensor> hermiteLastAxis(const torch::Tensor& p, const torch::Tensor& n, int64_t f)
{
    if (p.size(-1) < 2) throw Error("hermiteUpsample: needs at least 2 samples per axis");
    const int64_t w = p.size(-1);
    const torch::Tensor m = projectedTangents(p, n);
    const torch::Tensor p0 = p.narrow(-1, 0, w - 1), p1 = p.narrow(-1, 1, w - 1);
    const torch::Tensor m0 = m.narrow(-1, 0, w - 1), m1 = m.narrow(-1, 1, w - 1);
    const torch::Tensor n0 = n.narrow(-1, 0, w - 1);
    std::vector<torch::Tensor> values;
    for (int64_t i = 0; i < f; ++i) {
        const std::array<float, 4> h = hermiteWeights(float(i) / float(f));
        values.push_back(h[0] * p0 + h[1] * m0 + h[2] * p1 + h[3] * m1);
    }
    // Row normals: Catmull-Rom of the normals, renormalized (the left node's normal if 0).
    const torch::Tensor v = cubicUpsampleLastAxis(n, f);
    const torch::Tensor len = v.norm(2, 1, true);
    const torch::Tensor left = interleave(std::vector<torch::Tensor>(size_t(f), n0), n.narrow(-1, w - 1, 1));
    return {interleave(values, p.narrow(-1, w - 1, 1)), torch::where(len > 0, v / len.clamp_min(1e-30), left)};
}

}  // namespace

torch::Tensor hermiteUpsample(const torch::Tensor& coarse, const torch::Tensor& normals, int64_t f)
{
    if (coarse.dim() != 4 || coarse.size(1) != 3 || coarse.sizes() != normals.sizes())
        throw Error("hermiteUpsample: positions and normals must be N x 3 x H x W of one shape");
    const auto [rows, rowNormals] = hermiteLastAxis(coarse, normals, f);  // along X
    return hermiteLastAxis(rows.transpose(2, 3), rowNormals.transpose(2, 3), f).first.transpose(2, 3).contiguous();
}

}  // namespace ngi::nn
