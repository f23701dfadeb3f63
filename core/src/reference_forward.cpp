// Plain C++ reference forward of the super-resolution network's op list (semantics in
// ngi/network_weights.h). Paper: "Neural Geometry Image-Based Representations with Optimal
// Transport", section 3.2; PixelShuffle after Shi et al. 2016 (ESPCN).
#include "ngi/nn/reference_forward.h"

#include "ngi/error.h"

#include <algorithm>
#include <optional>
#include <cmath>
#include <limits>

namespace ngi::nn {
namespace {

float activate(float x, Activation a, float slope)
{
    switch (a) {
    case Activation::ReLU: return x > 0.0f ? x : 0.0f;
    case Activation::LeakyReLU: return x < 0.0f ? slope * x : x;
    default: return x;
    }
}

bool sameShape(const FeatureMap& a, const FeatureMap& b)
{
    return a.channels == b.channels && a.height == b.height && a.width == b.width;
}

// out[y][x] += w * in[clamp/zero(y + dy)][clamp/zero(x + dx)] for one input plane.
void accumulateTap(float* out, const float* in, uint32_t h, uint32_t w, int dy, int dx, float weight, Padding padding)
{
    for (int y = 0; y < int(h); ++y) {
        int sy = y + dy;
        if (sy < 0 || sy >= int(h)) {
            if (padding == Padding::Zero) continue;
            sy = std::clamp(sy, 0, int(h) - 1);
        }
        const float* row = in + size_t(sy) * w;
        float* dst = out + size_t(y) * w;
        const int x0 = std::max(0, -dx), x1 = std::min(int(w), int(w) - dx);  // sx in range
        for (int x = 0; x < x0; ++x)
            if (padding == Padding::Replicate) dst[x] += weight * row[0];
        for (int x = x0; x < x1; ++x) dst[x] += weight * row[x + dx];
        for (int x = std::max(x1, x0); x < int(w); ++x)
            if (padding == Padding::Replicate) dst[x] += weight * row[w - 1];
    }
}

}  // namespace

FeatureMap featureMapFromGeometryImage(const GeometryImage& image)
{
    FeatureMap m(3, image.size, image.size);
    for (uint32_t y = 0; y < image.size; ++y)
        for (uint32_t x = 0; x < image.size; ++x)
            for (uint32_t c = 0; c < 3; ++c) m.at(c, y, x) = image.at(x, y)[c];
    return m;
}

GeometryImage geometryImageFromFeatureMap(const FeatureMap& map)
{
    if (map.channels != 3 || map.height != map.width) throw Error("feature map is not 3 x S x S");
    GeometryImage image(map.width);
    for (uint32_t y = 0; y < map.height; ++y)
        for (uint32_t x = 0; x < map.width; ++x)
            for (uint32_t c = 0; c < 3; ++c) image.at(x, y)[c] = map.at(c, y, x);
    return image;
}

FeatureMap conv2d(const FeatureMap& in, const NetworkLayer& l, std::span<const float> params,
                  const FeatureMap* residual)
{
    if (in.channels != l.inChannels) throw Error("conv2d: input channel count mismatch");
    const uint32_t k = l.kernelSize, r = k / 2, h = in.height, w = in.width;
    FeatureMap out(l.outChannels, h, w);
    const size_t plane = size_t(h) * w;
    for (uint32_t o = 0; o < l.outChannels; ++o) {
        float* dst = out.data.data() + o * plane;
        std::fill(dst, dst + plane, params[l.biasOffset + o]);
        for (uint32_t i = 0; i < l.inChannels; ++i)
            for (uint32_t ky = 0; ky < k; ++ky)
                for (uint32_t kx = 0; kx < k; ++kx) {
                    const float weight = params[l.weightOffset + ((size_t(o) * l.inChannels + i) * k + ky) * k + kx];
                    accumulateTap(dst, in.data.data() + i * plane, h, w, int(ky) - int(r), int(kx) - int(r), weight,
                                  l.padding);
                }
        for (size_t p = 0; p < plane; ++p) dst[p] = activate(dst[p], l.activation, l.activationSlope);
    }
    if (residual) {
        if (!sameShape(*residual, out)) throw Error("conv2d: residual shape mismatch");
        for (size_t p = 0; p < out.data.size(); ++p) out.data[p] += residual->data[p];
    }
    return out;
}

FeatureMap neighborhoodCrossAttention(const FeatureMap& q, const FeatureMap& k, const FeatureMap& v,
                                      const NetworkLayer& l)
{
    if (!sameShape(q, k) || !sameShape(q, v) || q.channels != l.inChannels || l.heads == 0 || q.channels % l.heads != 0)
        throw Error("neighborhoodCrossAttention: shape mismatch");
    const int h = int(q.height), w = int(q.width), r = int(l.kernelSize / 2), side = int(l.kernelSize);
    const uint32_t d = q.channels / l.heads;
    FeatureMap out(q.channels, q.height, q.width);
    std::vector<float> logits(size_t(side) * side);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            // The window clipped to the image: the masked offsets are never read. Which samples
            // are read depends on the position only, never on a value (a NaN or infinite logit
            // makes the output non-finite, which referenceForward reports, but reads nothing else).
            const int y0 = std::max(-r, -y), y1 = std::min(r, h - 1 - y);
            const int x0 = std::max(-r, -x), x1 = std::min(r, w - 1 - x);
            for (uint32_t head = 0; head < l.heads; ++head) {
                const uint32_t c0 = head * d;
                float maxLogit = -std::numeric_limits<float>::infinity();
                for (int dy = y0; dy <= y1; ++dy)
                    for (int dx = x0; dx <= x1; ++dx) {
                        float dot = 0.0f;
                        for (uint32_t c = c0; c < c0 + d; ++c) dot += q.at(c, y, x) * k.at(c, y + dy, x + dx);
                        const float logit = l.attentionScale * dot;
                        logits[size_t(dy + r) * side + (dx + r)] = logit;
                        // NaN propagates into the maximum (std::max would drop it).
                        maxLogit = std::isnan(logit) || logit > maxLogit ? logit : maxLogit;
                    }
                float sum = 0.0f;
                for (int dy = y0; dy <= y1; ++dy)
                    for (int dx = x0; dx <= x1; ++dx) {
                        float& e = logits[size_t(dy + r) * side + (dx + r)];
                        e = std::exp(e - maxLogit);  // NaN if a logit is NaN or +inf
                        sum += e;
                    }
                for (int dy = y0; dy <= y1; ++dy)
                    for (int dx = x0; dx <= x1; ++dx) {
                        const float weight = logits[size_t(dy + r) * side + (dx + r)] / sum;
                        for (uint32_t c = c0; c < c0 + d; ++c) out.at(c, y, x) += weight * v.at(c, y + dy, x + dx);
                    }
            }
        }
    return out;
}

FeatureMap pixelShuffleCrop(const FeatureMap& in, uint32_t f)
{
    if (f == 0 || in.channels % (f * f) != 0 || in.height < 1 || in.width < 1)
        throw Error("pixelShuffleCrop: channels are not a multiple of factor^2");
    // Fine sample f*y + i sits at coarse coordinate y + i/f: the first (H-1)*f+1 rows of the
    // shuffled H*f rows are the nested fine grid; the f-1 rows beyond the last coarse
    // sample (and likewise columns) are cropped.
    FeatureMap out(in.channels / (f * f), (in.height - 1) * f + 1, (in.width - 1) * f + 1);
    for (uint32_t c = 0; c < out.channels; ++c)
        for (uint32_t Y = 0; Y < out.height; ++Y)
            for (uint32_t X = 0; X < out.width; ++X)
                out.at(c, Y, X) = in.at(c * f * f + (Y % f) * f + (X % f), Y / f, X / f);
    return out;
}

std::array<float, 4> catmullRomWeights(float t)
{
    const float t2 = t * t, t3 = t2 * t;
    return {-0.5f * t3 + t2 - 0.5f * t, 1.5f * t3 - 2.5f * t2 + 1.0f, -1.5f * t3 + 2.0f * t2 + 0.5f * t,
            0.5f * t3 - 0.5f * t2};
}

std::array<float, 4> hermiteWeights(float t)
{
    const float t2 = t * t, t3 = t2 * t;
    return {2.0f * t3 - 3.0f * t2 + 1.0f, t3 - 2.0f * t2 + t, -2.0f * t3 + 3.0f * t2, t3 - t2};
}

FeatureMap cubicSkip(const FeatureMap& coarse, const FeatureMap& fine, uint32_t f)
{
    if (f == 0 || fine.channels != coarse.channels || fine.height != (coarse.height - 1) * f + 1 ||
        fine.width != (coarse.width - 1) * f + 1)
        throw Error("cubicSkip: fine map is not the coarse map's grid times the factor");
    FeatureMap out = fine;
    const int64_t w = coarse.width, h = coarse.height;
    for (uint32_t c = 0; c < out.channels; ++c) {
        // Sample (y, x) of the coarse map, extrapolated linearly beyond the border in x.
        auto sample = [&](int64_t y, int64_t x) {
            if (x < 0) return 2.0f * coarse.at(c, uint32_t(y), 0) - coarse.at(c, uint32_t(y), 1);
            if (x >= w)
                return 2.0f * coarse.at(c, uint32_t(y), uint32_t(w - 1)) - coarse.at(c, uint32_t(y), uint32_t(w - 2));
            return coarse.at(c, uint32_t(y), uint32_t(x));
        };
        for (uint32_t Y = 0; Y < out.height; ++Y) {
            const int64_t y0 = Y / f;
            const std::array<float, 4> wy = catmullRomWeights(float(Y % f) / float(f));
            for (uint32_t X = 0; X < out.width; ++X) {
                const int64_t x0 = X / f;
                const std::array<float, 4> wx = catmullRomWeights(float(X % f) / float(f));
                auto row = [&](int64_t y) {
                    float r = 0.0f;
                    for (int kx = 0; kx < 4; ++kx) r += wx[size_t(kx)] * sample(y, x0 - 1 + kx);
                    return r;
                };
                float sum = 0.0f;
                for (int ky = 0; ky < 4; ++ky) {
                    const int64_t y = y0 - 1 + ky;
                    const float r = y < 0 ? 2.0f * row(0) - row(1) : y >= h ? 2.0f * row(h - 1) - row(h - 2) : row(y);
                    sum += wy[size_t(ky)] * r;
                }
                out.at(c, Y, X) += sum;
            }
        }
    }
    return out;
}

namespace {

using Vec3 = std::array<float, 3>;

float dot3(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// One axis of HermiteSkip: a line of n samples p with normals nrm, upsampled by f at fine
// index X. Tangents are Catmull-Rom's (one-sided at the ends) minus their normal part.
Vec3 hermiteAt(const std::vector<Vec3>& p, const std::vector<Vec3>& nrm, uint32_t f, uint32_t X)
{
    const size_t n = p.size(), i0 = X / f, i1 = std::min(i0 + 1, n - 1);
    auto tangent = [&](size_t i) {
        Vec3 m;
        for (int c = 0; c < 3; ++c)
            m[size_t(c)] = i == 0 ? p[1][size_t(c)] - p[0][size_t(c)]
                : i == n - 1      ? p[n - 1][size_t(c)] - p[n - 2][size_t(c)]
                                  : 0.5f * (p[i + 1][size_t(c)] - p[i - 1][size_t(c)]);
        const float along = dot3(nrm[i], m);
        for (int c = 0; c < 3; ++c) m[size_t(c)] -= nrm[i][size_t(c)] * along;
        return m;
    };
    const Vec3 m0 = tangent(i0), m1 = tangent(i1);
    const std::array<float, 4> h = hermiteWeights(float(X % f) / float(f));
    Vec3 out;
    for (size_t c = 0; c < 3; ++c) out[c] = h[0] * p[i0][c] + h[1] * m0[c] + h[2] * p[i1][c] + h[3] * m1[c];
    return out;
}

// The row normal: Catmull-Rom of the normals (linear extrapolation beyond the ends, as
// CubicSkip), renormalized; C1 like the rows themselves.
Vec3 cubicNormal(const std::vector<Vec3>& nrm, uint32_t f, uint32_t X)
{
    const int64_t n = int64_t(nrm.size()), i0 = X / f;
    const std::array<float, 4> wt = catmullRomWeights(float(X % f) / float(f));
    Vec3 v{0.0f, 0.0f, 0.0f};
    for (int k = 0; k < 4; ++k) {
        const int64_t i = i0 - 1 + k;
        for (size_t c = 0; c < 3; ++c) {
            const float s = i < 0 ? 2.0f * nrm[0][c] - nrm[1][c]
                : i >= n          ? 2.0f * nrm[size_t(n - 1)][c] - nrm[size_t(n - 2)][c]
                                  : nrm[size_t(i)][c];
            v[c] += wt[size_t(k)] * s;
        }
    }
    const float len = std::sqrt(dot3(v, v));
    if (!(len > 0.0f)) return nrm[size_t(i0)];
    for (float& c : v) c /= len;
    return v;
}

}  // namespace

FeatureMap hermiteSkip(const FeatureMap& coarse, const FeatureMap& normals, const FeatureMap& fine, uint32_t f)
{
    if (f == 0 || coarse.channels != 3 || fine.channels != 3 || !sameShape(coarse, normals) ||
        fine.height != (coarse.height - 1) * f + 1 || fine.width != (coarse.width - 1) * f + 1 || coarse.width < 2 ||
        coarse.height < 2)
        throw Error("hermiteSkip: needs 3-channel coarse positions and normals of one shape (>= 2 x 2) and a fine map "
                    "on the coarse grid times the factor");
    FeatureMap out = fine;
    const uint32_t h = coarse.height, w = coarse.width;
    // Rows first: R(y, X) and the row normals N(y, X), stored per fine column.
    std::vector<std::vector<Vec3>> rows(out.width, std::vector<Vec3>(h)), rowNormals(out.width, std::vector<Vec3>(h));
    std::vector<Vec3> p(w), nrm(w);
    for (uint32_t y = 0; y < h; ++y) {
        for (uint32_t x = 0; x < w; ++x)
            for (uint32_t c = 0; c < 3; ++c) p[x][c] = coarse.at(c, y, x), nrm[x][c] = normals.at(c, y, x);
        for (uint32_t X = 0; X < out.width; ++X) {
            rows[X][y] = hermiteAt(p, nrm, f, X);
            rowNormals[X][y] = cubicNormal(nrm, f, X);
        }
    }
    for (uint32_t X = 0; X < out.width; ++X)
        for (uint32_t Y = 0; Y < out.height; ++Y) {
            const Vec3 v = hermiteAt(rows[X], rowNormals[X], f, Y);
            for (uint32_t c = 0; c < 3; ++c) out.at(c, Y, X) += v[c];
        }
    return out;
}

FeatureMap bilinearSkip(const FeatureMap& coarse, const FeatureMap& fine, uint32_t f)
{
    if (f == 0 || fine.channels != coarse.channels || fine.height != (coarse.height - 1) * f + 1 ||
        fine.width != (coarse.width - 1) * f + 1)
        throw Error("bilinearSkip: fine map is not the coarse map's grid times the factor");
    FeatureMap out = fine;
    // Same arithmetic as PyTorch interpolate(align_corners=true): source = X * (1/f) in fp32.
    const float step = 1.0f / float(f);
    for (uint32_t c = 0; c < out.channels; ++c)
        for (uint32_t Y = 0; Y < out.height; ++Y) {
            const uint32_t y0 = Y / f, y1 = std::min(y0 + 1, coarse.height - 1);
            const float ty = float(Y) * step - float(y0);
            for (uint32_t X = 0; X < out.width; ++X) {
                const uint32_t x0 = X / f, x1 = std::min(x0 + 1, coarse.width - 1);
                const float tx = float(X) * step - float(x0);
                const float top = coarse.at(c, y0, x0) * (1.0f - tx) + coarse.at(c, y0, x1) * tx;
                const float bottom = coarse.at(c, y1, x0) * (1.0f - tx) + coarse.at(c, y1, x1) * tx;
                out.at(c, Y, X) += top * (1.0f - ty) + bottom * ty;
            }
        }
    return out;
}

std::optional<size_t> outputSkipLayer(const NetworkWeights& net)
{
    for (size_t li = 0; li < net.layers.size(); ++li)
        if (net.layers[li].output == net.outputTensor)
            return isSkip(net.layers[li].kind) ? std::optional(li) : std::nullopt;
    return std::nullopt;
}

namespace {

// The forward pass; with a gain other than 1 (or `split`), the output is blended toward the
// Catmull-Rom cubic c of the output skip's coarse input: c + gain (network - c). A gain of 1
// leaves the output untouched (bitwise the network's).
FeatureMap forward(const NetworkWeights& net, const FeatureMap& positions, const FeatureMap& normals, float gain,
                   RestoreEndpoints* split)
{
    const std::string label = networkLabel(net);
    validateNetwork(net, label);
    if (positions.channels != 3 || !sameShape(positions, normals) || positions.height < 2 || positions.width < 2)
        throw Error("referenceForward: inputs must be 3 x H x W position and normal maps of equal size, H, W >= 2");
    const std::optional<size_t> outputSkip = outputSkipLayer(net);
    if ((gain != 1.0f || split) && !outputSkip)
        throw Error(label +
                    ": a residual gain needs the network's output written by a skip layer (BilinearSkip, "
                    "CubicSkip or HermiteSkip)");
    if (!(gain >= 0.0f && gain <= 1.0f))
        throw Error(label + ": residual gain " + std::to_string(gain) + " is not in [0, 1]");
    std::vector<FeatureMap> tensors(net.tensorCount);
    tensors[kPositionInputTensor] = positions;
    tensors[kNormalInputTensor] = normals;
    FeatureMap cubic;  // the blend's gain-0 endpoint
    for (size_t li = 0; li < net.layers.size(); ++li) {
        const NetworkLayer& l = net.layers[li];
        const FeatureMap& a = tensors[l.inputs[0]];
        switch (l.kind) {
        case LayerKind::Conv:
            tensors[l.output] =
                conv2d(a, l, net.parameters, l.inputs[1] != kNoTensor ? &tensors[l.inputs[1]] : nullptr);
            break;
        case LayerKind::NeighborhoodCrossAttention:
            tensors[l.output] = neighborhoodCrossAttention(a, tensors[l.inputs[1]], tensors[l.inputs[2]], l);
            break;
        case LayerKind::PixelShuffle: tensors[l.output] = pixelShuffleCrop(a, l.factor); break;
        case LayerKind::BilinearSkip: tensors[l.output] = bilinearSkip(a, tensors[l.inputs[1]], l.factor); break;
        case LayerKind::CubicSkip: tensors[l.output] = cubicSkip(a, tensors[l.inputs[1]], l.factor); break;
        case LayerKind::HermiteSkip:
            tensors[l.output] = hermiteSkip(a, tensors[l.inputs[2]], tensors[l.inputs[1]], l.factor);
            break;
        }
        if (outputSkip && li == *outputSkip && (gain != 1.0f || split)) {
            const FeatureMap& fine = tensors[l.inputs[1]];
            cubic = cubicSkip(a, FeatureMap(fine.channels, fine.height, fine.width), l.factor);
        }
        // Finite but extreme parameters (a huge slope, weights near FLT_MAX) overflow: the
        // first layer that makes a NaN or an infinity ends the restore, never its output.
        const std::vector<float>& values = tensors[l.output].data;
        if (!std::all_of(values.begin(), values.end(), [](float v) { return std::isfinite(v); }))
            throw Error(label + ": the restore produced non-finite values (layer " + std::to_string(li) + ")");
    }
    FeatureMap out = tensors[net.outputTensor];
    if (split) *split = {cubic, out};
    if (gain != 1.0f)
        for (size_t i = 0; i < out.data.size(); ++i) out.data[i] = cubic.data[i] + gain * (out.data[i] - cubic.data[i]);
    return out;
}

}  // namespace

FeatureMap referenceForward(const NetworkWeights& net, const FeatureMap& positions, const FeatureMap& normals,
                            float residualGain)
{
    return forward(net, positions, normals, residualGain, nullptr);
}

RestoreEndpoints referenceForwardEndpoints(const NetworkWeights& net, const FeatureMap& positions,
                                           const FeatureMap& normals)
{
    RestoreEndpoints split;
    forward(net, positions, normals, 1.0f, &split);
    return split;
}

}  // namespace ngi::nn
