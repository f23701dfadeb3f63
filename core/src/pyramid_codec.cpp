// The nested-pyramid coder of one stored level: see ngi/pyramid_codec.h for the scheme and
// its sources (Sweldens 1996 lifting; Khodakovsky et al. 2000; the LZMA range coder;
// Cigolle et al. 2014 octahedral vectors; Duff et al. 2017 for the tangent frame).
#include "ngi/pyramid_codec.h"

#include "ngi/error.h"
#include "range_coder.h"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>

namespace ngi {
namespace {

using detail::BitModel;
using detail::RangeDecoder;
using detail::RangeEncoder;

constexpr uint8_t kCodecVersion = 1;
constexpr int kBuckets = 10;
constexpr int kMaxExponent = 18;  // |residual| < 2^18: 65535 / step + 1 for any step
constexpr uint32_t kMaxSize = 4097;

// The adaptive models of one context: zero flag, sign, Exp-Golomb exponent (unary) and the
// two top mantissa bits; lower mantissa bits are coded raw (they are close to uniform).
struct ResidualModels {
    BitModel zero, sign;
    BitModel prefix[kMaxExponent + 1];
    BitModel top[kMaxExponent + 1];
    BitModel second[kMaxExponent + 1][2];
};

void encodeResidual(RangeEncoder& rc, ResidualModels& m, int32_t q)
{
    rc.encode(m.zero, q != 0);
    if (q == 0) return;
    rc.encode(m.sign, q < 0);
    const uint32_t v = uint32_t(q < 0 ? -int64_t(q) : q);
    const int e = std::bit_width(v) - 1;
    for (int i = 0; i < e; ++i) rc.encode(m.prefix[i], 1);
    if (e < kMaxExponent) rc.encode(m.prefix[e], 0);
    if (e >= 1) {
        const int b1 = (v >> (e - 1)) & 1;
        rc.encode(m.top[e], b1);
        if (e >= 2) {
            rc.encode(m.second[e][b1], (v >> (e - 2)) & 1);
            if (e >= 3) rc.encodeBits(v & ((1u << (e - 2)) - 1), e - 2);
        }
    }
}

int32_t decodeResidual(RangeDecoder& rc, ResidualModels& m)
{
    if (!rc.decode(m.zero)) return 0;
    const bool negative = rc.decode(m.sign);
    int e = 0;
    while (e < kMaxExponent && rc.decode(m.prefix[e])) ++e;  // bounded: at most kMaxExponent bits
    uint32_t v = 1;
    if (e >= 1) {
        const int b1 = rc.decode(m.top[e]);
        v = (v << 1) | uint32_t(b1);
        if (e >= 2) {
            v = (v << 1) | uint32_t(rc.decode(m.second[e][b1]));
            if (e >= 3) v = (v << (e - 2)) | rc.decodeBits(e - 2);
        }
    }
    return negative ? -int32_t(v) : int32_t(v);
}

int bucketOf(uint32_t activity) { return std::min(kBuckets - 1, int(std::bit_width(activity))); }

// Rounds r / q to the nearest integer, halves away from zero (symmetric: |error| <= q / 2).
int32_t quantize(int32_t r, int32_t q)
{
    const int32_t half = q / 2;
    return r >= 0 ? (r + half) / q : -((-r + half) / q);
}

// Bits of a corner's quantized value round(65535 / q).
int cornerBits(int32_t q) { return std::bit_width(uint32_t((65535 + q / 2) / q)); }

uint16_t clamp16(int64_t v) { return uint16_t(std::clamp<int64_t>(v, 0, 65535)); }

// The 4-tap cubic midpoint (-a + 9b + 9c - d) / 16 of b and c, linear (b + c) / 2 when a or d
// is missing (hasOuter false). Integer arithmetic, identical in encoder and decoder.
int32_t midpoint(int32_t a, int32_t b, int32_t c, int32_t d, bool hasOuter)
{
    if (!hasOuter) return (b + c + 1) >> 1;
    return (9 * (b + c) - a - d + 8) >> 4;
}

// The levels of one stored level, shared by encoder and decoder so both predict
// identically. Encode reads `source` and writes encoder(); decode reads decoder(). The
// caller codes the levels in order, 0 (the corners) first, and may swap the encoder or
// decoder between levels (a flush: the models carry on, only the coder's state restarts).
template <bool Encode> class PositionCoder {
public:
    PositionCoder(uint32_t n, const uint16_t* source, std::span<const uint32_t> mates, uint32_t tangentScale,
                  std::vector<uint16_t> steps)
        : n_(n), source_(source), rec_(size_t(n) * n * 3, 0), mag_(size_t(n) * n * 3, 0), models_(3 * 3 * kBuckets),
          mates_(mates), firstOfClass_(mates.empty() ? 0 : size_t(n) * n, kNone), tangentScale_(tangentScale),
          steps_(std::move(steps))
    {}

    RangeEncoder& encoder() { return enc_; }
    RangeDecoder& decoder() { return dec_; }
    uint32_t levelCount() const { return uint32_t(steps_.size()); }
    const std::vector<uint16_t>& samples() const { return rec_; }
    std::vector<uint16_t> takeSamples() { return std::move(rec_); }

    // Codes level l: 0 is the four corners, raw (round(sample / step) in cornerBits bits);
    // level l > 0 the samples new at grid spacing (n - 1) >> l.
    void codeLevel(uint32_t l)
    {
        if (l == 0) {
            const int32_t q0 = steps_[0];
            for (uint32_t y : {0u, n_ - 1})
                for (uint32_t x : {0u, n_ - 1}) {
                    if (copiedFromMate(x, y)) continue;
                    for (int c = 0; c < 3; ++c) {
                        const size_t i = index(x, y) + c;
                        uint32_t qv;
                        if constexpr (Encode) {
                            qv = (uint32_t(source_[i]) + uint32_t(q0 / 2)) / uint32_t(q0);
                            enc_.encodeBits(qv, cornerBits(q0));
                        } else {
                            qv = dec_.decodeBits(cornerBits(q0));
                        }
                        rec_[i] = clamp16(int64_t(qv) * q0);
                    }
                }
            return;
        }
        const uint32_t s = (n_ - 1) >> l;  // this level's grid spacing in stored samples
        const int32_t k = steps_[l];
        // Pass 0: row midpoints (odd x, even y) from their row.
        for (uint32_t y = 0; y < n_; y += 2 * s)
            for (uint32_t x = s; x < n_; x += 2 * s) {
                int32_t p[3];
                for (int c = 0; c < 3; ++c) p[c] = along(x, y, s, true, c);
                code(x, y, s, 0, k, p);
            }
        // Pass 1: column midpoints (even x, odd y) from their column.
        for (uint32_t y = s; y < n_; y += 2 * s)
            for (uint32_t x = 0; x < n_; x += 2 * s) {
                int32_t p[3];
                for (int c = 0; c < 3; ++c) p[c] = along(x, y, s, false, c);
                code(x, y, s, 1, k, p);
            }
        // Pass 2: cell centres from the decoded midpoints of both directions.
        for (uint32_t y = s; y < n_; y += 2 * s)
            for (uint32_t x = s; x < n_; x += 2 * s) {
                int32_t p[3];
                for (int c = 0; c < 3; ++c) p[c] = (along(x, y, s, true, c) + along(x, y, s, false, c) + 1) >> 1;
                code(x, y, s, 2, k, p);
            }
    }

private:
    size_t index(uint32_t x, uint32_t y) const { return (size_t(y) * n_ + x) * 3; }

    // The midpoint prediction at (x, y) from the samples at +-s and +-3s along x (row) or y.
    int32_t along(uint32_t x, uint32_t y, uint32_t s, bool row, int c) const
    {
        const uint32_t t = row ? x : y;
        auto at = [&](int64_t u) -> int32_t {
            return rec_[row ? index(uint32_t(u), y) + c : index(x, uint32_t(u)) + c];
        };
        const bool outer = t >= 3 * s && t + 3 * s <= n_ - 1;
        return midpoint(outer ? at(int64_t(t) - 3 * s) : 0, at(int64_t(t) - s), at(int64_t(t) + s),
                        outer ? at(int64_t(t) + 3 * s) : 0, outer);
    }

    // A seam mate of an already decoded sample copies it (nothing is coded for it); else the
    // sample becomes its class's decoded member.
    bool copiedFromMate(uint32_t x, uint32_t y)
    {
        if (mates_.empty()) return false;
        uint32_t& first = firstOfClass_[mates_[size_t(y) * n_ + x]];
        if (first == kNone) {
            first = y * n_ + x;
            return false;
        }
        for (int c = 0; c < 3; ++c) rec_[index(x, y) + c] = rec_[size_t(first) * 3 + c];
        return true;
    }

    // The residual magnitudes already decoded around (x, y) at distance s, component c.
    uint32_t activity(uint32_t x, uint32_t y, uint32_t s, int c) const
    {
        uint32_t sum = 0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                if (dx == 0 && dy == 0) continue;
                const int64_t u = int64_t(x) + dx * int64_t(s), v = int64_t(y) + dy * int64_t(s);
                if (u < 0 || v < 0 || u >= n_ || v >= n_) continue;
                sum += mag_[index(uint32_t(u), uint32_t(v)) + c];
            }
        return sum;
    }

    using Vec = std::array<int64_t, 3>;
    static constexpr int64_t kUnit = 16384;  // fixed-point unit of the frame vectors

    Vec sample(uint32_t x, uint32_t y) const
    {
        const size_t i = index(x, y);
        return {rec_[i], rec_[i + 1], rec_[i + 2]};
    }
    static Vec sub(const Vec& a, const Vec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
    static Vec add(const Vec& a, const Vec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
    static Vec cross(const Vec& a, const Vec& b)
    {
        return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    }
    static int64_t dot(const Vec& a, const Vec& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
    // a scaled to length kUnit, rounded; false for a zero vector. Integers throughout except one
    // correctly rounded sqrt and division per component, so encoder and decoder agree exactly.
    static bool normalized(Vec a, Vec& out)
    {
        while (std::max({std::abs(a[0]), std::abs(a[1]), std::abs(a[2])}) >= (int64_t(1) << 20))
            for (int64_t& v : a) v /= 2;
        const int64_t squared = dot(a, a);
        if (squared == 0) return false;
        const double length = std::sqrt(double(squared));
        for (int c = 0; c < 3; ++c) out[c] = std::llround(double(a[c]) * double(kUnit) / length);
        return true;
    }
    static int64_t roundDiv(int64_t a, int64_t b) { return a >= 0 ? (a + b / 2) / b : -((-a + b / 2) / b); }

    // The residual frame at (x, y): the surface normal from decoded neighbours (the two grid
    // directions' differences, across the coarser grid where the pass has no decoded
    // neighbour in that direction), then two tangents. False where it is degenerate.
    bool frameAt(uint32_t x, uint32_t y, uint32_t s, int pass, Vec (&f)[3]) const
    {
        const uint32_t last = n_ - 1;
        Vec u{}, v{};
        if (pass != 1) u = sub(sample(x + s, y), sample(x - s, y));
        if (pass != 0) v = sub(sample(x, y + s), sample(x, y - s));
        if (pass == 0)
            for (uint32_t xa : {x - s, x + s})
                v = add(v, sub(sample(xa, y + 2 * s <= last ? y + 2 * s : y), sample(xa, y >= 2 * s ? y - 2 * s : y)));
        if (pass == 1)
            for (uint32_t ya : {y - s, y + s})
                u = add(u, sub(sample(x + 2 * s <= last ? x + 2 * s : x, ya), sample(x >= 2 * s ? x - 2 * s : x, ya)));
        if (!normalized(cross(u, v), f[0])) return false;
        int axis = 0;
        for (int c = 1; c < 3; ++c)
            if (std::abs(f[0][c]) < std::abs(f[0][axis])) axis = c;
        Vec e{0, 0, 0};
        e[axis] = 1;
        if (!normalized(cross(f[0], e), f[1])) return false;
        const Vec t2 = cross(f[0], f[1]);
        f[2] = {t2[0] / kUnit, t2[1] / kUnit, t2[2] / kUnit};
        return true;
    }

    void code(uint32_t x, uint32_t y, uint32_t s, int pass, int32_t step, const int32_t* prediction)
    {
        const size_t i = index(x, y);
        if (copiedFromMate(x, y)) return;
        Vec frame[3];
        if (tangentScale_ && frameAt(x, y, s, pass, frame)) {
            codeInFrame(x, y, s, pass, step, prediction, frame);
            return;
        }
        uint32_t earlier = 0;
        for (int c = 0; c < 3; ++c) {
            const uint32_t a = activity(x, y, s, c) + 2 * earlier;
            ResidualModels& m = models_[size_t((pass * 3 + c) * kBuckets + bucketOf(a))];
            const int32_t p = std::clamp(prediction[c], 0, 65535);
            int32_t q;
            if constexpr (Encode) {
                q = quantize(int32_t(source_[i + c]) - p, step);
                encodeResidual(enc_, m, q);
            } else {
                q = decodeResidual(dec_, m);
            }
            rec_[i + c] = clamp16(int64_t(p) + int64_t(q) * step);
            const uint32_t magnitude = uint32_t(std::min<int64_t>(q < 0 ? -int64_t(q) : q, 255));
            mag_[i + c] = uint8_t(magnitude);
            earlier += magnitude;
        }
    }

    // The residual as its normal and two tangent components (normal step `step`, tangent
    // steps tangentScale times larger: a sample moved within the surface barely changes it).
    void codeInFrame(uint32_t x, uint32_t y, uint32_t s, int pass, int32_t step, const int32_t* prediction,
                     const Vec (&f)[3])
    {
        const size_t i = index(x, y);
        Vec p, r{};
        for (int c = 0; c < 3; ++c) p[c] = std::clamp(prediction[c], 0, 65535);
        if constexpr (Encode)
            for (int c = 0; c < 3; ++c) r[c] = int64_t(source_[i + c]) - p[c];
        Vec d{0, 0, 0};
        uint32_t earlier = 0;
        for (int j = 0; j < 3; ++j) {
            const int64_t q = int64_t(step) * (j ? tangentScale_ : 1);
            const uint32_t a = activity(x, y, s, j) + 2 * earlier;
            ResidualModels& m = models_[size_t((pass * 3 + j) * kBuckets + bucketOf(a))];
            int32_t k;
            if constexpr (Encode) {
                k = int32_t(std::clamp<int64_t>(roundDiv(dot(r, f[j]), q * kUnit), -(1 << 18), 1 << 18));
                encodeResidual(enc_, m, k);
            } else {
                k = decodeResidual(dec_, m);
            }
            for (int c = 0; c < 3; ++c) d[c] += int64_t(k) * q * f[j][c];
            const uint32_t magnitude = uint32_t(std::min<int64_t>(std::abs(int64_t(k)), 255));
            mag_[i + j] = uint8_t(magnitude);
            earlier += magnitude;
        }
        for (int c = 0; c < 3; ++c) rec_[i + c] = clamp16(p[c] + roundDiv(d[c], kUnit));
    }

    uint32_t n_;
    const uint16_t* source_;
    RangeEncoder enc_;
    RangeDecoder dec_;
    std::vector<uint16_t> rec_;
    std::vector<uint8_t> mag_;
    std::vector<ResidualModels> models_;
    static constexpr uint32_t kNone = ~0u;
    std::span<const uint32_t> mates_;
    std::vector<uint32_t> firstOfClass_;
    uint32_t tangentScale_;
    std::vector<uint16_t> steps_;
};

void checkMates(std::span<const uint32_t> mates, uint32_t size, const std::string& where)
{
    if (mates.empty()) return;
    const size_t count = size_t(size) * size;
    if (mates.size() != count)
        throw Error(where + ": the seam mate table does not match a " + std::to_string(size) + "^2 level");
    for (uint32_t m : mates)
        if (m >= count) throw Error(where + ": a seam mate id is outside the level");
}

void checkSize(uint32_t size, const std::string& where)
{
    if (size < 2 || size > kMaxSize || !std::has_single_bit(size - 1))
        throw Error(where + ": " + std::to_string(size) + " samples per side is not 2^k + 1 in [2, " +
                    std::to_string(kMaxSize) + "]");
}

// Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (JCGT 6(1)): t1, t2 with n.
void tangentFrame(const glm::vec3& n, glm::vec3& t1, glm::vec3& t2)
{
    const float sign = std::copysign(1.0f, n.z);
    const float a = -1.0f / (sign + n.z);
    const float b = n.x * n.y * a;
    t1 = glm::vec3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    t2 = glm::vec3(b, sign + n.y * n.y * a, -n.y);
}

glm::vec2 octahedral(glm::vec3 v)
{
    v /= std::abs(v.x) + std::abs(v.y) + std::abs(v.z);
    if (v.z >= 0.0f) return {v.x, v.y};
    return {(1.0f - std::abs(v.y)) * (v.x >= 0.0f ? 1.0f : -1.0f),
            (1.0f - std::abs(v.x)) * (v.y >= 0.0f ? 1.0f : -1.0f)};
}

glm::vec3 fromOctahedral(glm::vec2 e)
{
    glm::vec3 v(e.x, e.y, 1.0f - std::abs(e.x) - std::abs(e.y));
    if (v.z < 0.0f) {
        v.x = (1.0f - std::abs(e.y)) * (e.x >= 0.0f ? 1.0f : -1.0f);
        v.y = (1.0f - std::abs(e.x)) * (e.y >= 0.0f ? 1.0f : -1.0f);
    }
    return glm::normalize(v);
}

glm::vec3 normalAt(std::span<const uint16_t> n16, size_t i)
{
    const glm::vec3 v(n16[i] / 65535.0f * 2.0f - 1.0f, n16[i + 1] / 65535.0f * 2.0f - 1.0f,
                      n16[i + 2] / 65535.0f * 2.0f - 1.0f);
    const float l = glm::length(v);
    return l > 1e-6f ? v / l : glm::vec3(0.0f, 0.0f, 1.0f);
}

uint16_t normal16(float v) { return uint16_t(std::lround(std::clamp(v * 0.5f + 0.5f, 0.0f, 1.0f) * 65535.0f)); }

std::vector<glm::vec3> predictedNormals(std::span<const uint16_t> p, uint32_t n)
{
    std::vector<glm::vec3> out(size_t(n) * n);
    auto at = [&](uint32_t x, uint32_t y) {
        const size_t i = (size_t(y) * n + x) * 3;
        return glm::vec3(float(p[i]), float(p[i + 1]), float(p[i + 2]));
    };
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const glm::vec3 du = at(std::min(x + 1, n - 1), y) - at(x > 0 ? x - 1 : 0, y);
            const glm::vec3 dv = at(x, std::min(y + 1, n - 1)) - at(x, y > 0 ? y - 1 : 0);
            const glm::vec3 c = glm::cross(du, dv);
            const float l = glm::length(c);
            out[size_t(y) * n + x] = l > 0.0f ? c / l : glm::vec3(0.0f, 0.0f, 1.0f);
        }
    return out;
}

}  // namespace

uint32_t pyramidLevelCount(uint32_t size)
{
    checkSize(size, "pyramid codec");
    return uint32_t(std::countr_zero(size - 1)) + 1;
}

namespace {

constexpr uint8_t kLevelsCodecVersion = 2;  // flushed at every level (encodePyramidLevels)

// The steps of every level, checked; what both payload forms start with.
std::vector<uint16_t> levelSteps(std::span<const uint16_t> samples, uint32_t size, const PyramidCodecOptions& options)
{
    const uint32_t levels = pyramidLevelCount(size);
    if (samples.size() != size_t(size) * size * 3)
        throw Error("pyramid codec: " + std::to_string(samples.size()) + " samples do not make a " +
                    std::to_string(size) + "^2 RGB level");
    std::vector<uint16_t> steps(levels, uint16_t(std::min<uint32_t>(options.step, 65535)));
    if (!options.levelSteps.empty()) {
        if (options.levelSteps.size() != levels)
            throw Error("pyramid codec: " + std::to_string(options.levelSteps.size()) + " per-level steps for " +
                        std::to_string(levels) + " levels");
        steps = options.levelSteps;
    }
    for (uint16_t q : steps)
        if (q < 1 || q > kMaxPyramidStep)
            throw Error("pyramid codec: step " + std::to_string(q) + " is outside [1, " +
                        std::to_string(kMaxPyramidStep) + "]");
    checkMates(options.mates, size, "pyramid codec");
    if (options.tangentScale > kMaxTangentScale)
        throw Error("pyramid codec: tangent step scale " + std::to_string(options.tangentScale) + " is above " +
                    std::to_string(kMaxTangentScale));
    return steps;
}

std::vector<uint8_t> payloadHeader(uint8_t version, const std::vector<uint16_t>& steps, uint32_t tangentScale)
{
    std::vector<uint8_t> out = {version, uint8_t(steps.size()), uint8_t(tangentScale)};
    for (uint16_t q : steps) out.push_back(uint8_t(q & 0xff)), out.push_back(uint8_t(q >> 8));
    return out;
}

struct PayloadHeader {
    std::vector<uint16_t> steps;
    uint32_t tangentScale = 0;
};

// Parses a header of `version` for a size x size level; `fail` throws.
template <class Fail>
PayloadHeader parseHeader(std::span<const uint8_t> payload, uint8_t version, uint32_t size, Fail fail)
{
    const uint32_t levels = pyramidLevelCount(size);
    if (payload.size() < 3) fail("the payload is truncated (no header)");
    if (payload[0] != version) fail("unknown codec version " + std::to_string(payload[0]));
    if (payload[1] != levels)
        fail("the payload codes " + std::to_string(payload[1]) + " levels, a " + std::to_string(size) +
             "^2 level has " + std::to_string(levels));
    PayloadHeader h;
    h.tangentScale = payload[2];
    if (h.tangentScale > kMaxTangentScale)
        fail("tangent step scale " + std::to_string(h.tangentScale) + " is above " + std::to_string(kMaxTangentScale));
    if (payload.size() < 3 + 2 * size_t(levels)) fail("the payload is truncated (step table)");
    h.steps.resize(levels);
    for (uint32_t l = 0; l < levels; ++l) {
        h.steps[l] = uint16_t(payload[3 + 2 * l] | payload[4 + 2 * l] << 8);
        if (h.steps[l] < 1 || h.steps[l] > kMaxPyramidStep)
            fail("step " + std::to_string(h.steps[l]) + " is outside [1, " + std::to_string(kMaxPyramidStep) + "]");
    }
    return h;
}

}  // namespace

std::vector<uint8_t> encodePyramidPositions(std::span<const uint16_t> samples, uint32_t size,
                                            const PyramidCodecOptions& options)
{
    const std::vector<uint16_t> steps = levelSteps(samples, size, options);
    PositionCoder<true> coder(size, samples.data(), options.mates, options.tangentScale, steps);
    std::vector<size_t> ends;
    for (uint32_t l = 0; l < coder.levelCount(); ++l) {
        coder.codeLevel(l);
        ends.push_back(coder.encoder().size());
    }
    if (options.levelBytes) {
        options.levelBytes->clear();
        for (size_t l = 0; l < ends.size(); ++l) options.levelBytes->push_back(ends[l] - (l ? ends[l - 1] : 0));
    }
    std::vector<uint8_t> out = payloadHeader(kCodecVersion, steps, options.tangentScale);
    const std::vector<uint8_t> stream = coder.encoder().finish();
    out.insert(out.end(), stream.begin(), stream.end());
    return out;
}

std::vector<uint16_t> decodePyramidPositions(std::span<const uint8_t> payload, uint32_t size, const std::string& name,
                                             std::span<const uint32_t> mates)
{
    checkSize(size, name);
    checkMates(mates, size, name);
    auto fail = [&](const std::string& problem) { throw Error(name + ": pyramid-coded positions: " + problem); };
    const PayloadHeader h = parseHeader(payload, kCodecVersion, size, fail);
    const size_t headerBytes = 3 + 2 * h.steps.size();
    PositionCoder<false> coder(size, nullptr, mates, h.tangentScale, h.steps);
    coder.decoder() = RangeDecoder(payload.subspan(headerBytes));
    for (uint32_t l = 0; l < coder.levelCount(); ++l) coder.codeLevel(l);
    if (coder.decoder().overrun() > 0) fail("the stream is truncated");
    if (coder.decoder().unread() > 0)
        fail(std::to_string(coder.decoder().unread()) + " bytes follow the end of the stream");
    return coder.takeSamples();
}

PyramidPayloadInfo pyramidPayloadInfo(std::span<const uint8_t> payload)
{
    PyramidPayloadInfo info;
    if (payload.size() < 3 || (payload[0] != kCodecVersion && payload[0] != kLevelsCodecVersion) || payload[1] == 0)
        return info;
    const size_t finest = 3 + 2 * (size_t(payload[1]) - 1);
    if (payload.size() < finest + 2) return info;
    info.finestStep = uint32_t(payload[finest] | payload[finest + 1] << 8);
    info.tangentScale = payload[2];
    for (size_t l = 0; l < payload[1]; ++l)
        info.steps.push_back(uint16_t(payload[3 + 2 * l] | payload[4 + 2 * l] << 8));
    return info;
}

std::vector<uint16_t> gradedLevelSteps(uint32_t finestStep, uint32_t levelCount, double grade)
{
    if (!std::isfinite(grade) || grade < 1.0)
        throw Error("pyramid codec: step grade " + std::to_string(grade) + " is not a number >= 1");
    if (finestStep < 1 || finestStep > kMaxPyramidStep)
        throw Error("pyramid codec: step " + std::to_string(finestStep) + " is outside [1, " +
                    std::to_string(kMaxPyramidStep) + "]");
    // The divisor by repeated multiplication, not std::pow: basic IEEE operations round the same
    // on every platform, so every writer grades alike and stepGradeOf recognises the file.
    std::vector<uint16_t> steps(levelCount);
    double divisor = 1.0;
    for (uint32_t l = levelCount; l-- > 0; divisor *= grade)
        steps[l] = uint16_t(std::clamp(std::round(double(finestStep) / divisor), 1.0, double(kMaxPyramidStep)));
    return steps;
}

double stepGradeOf(std::span<const uint16_t> steps)
{
    if (steps.empty()) return 0.0;
    for (const double grade : kPyramidStepGrades) {
        const std::vector<uint16_t> made =
            gradedLevelSteps(std::clamp<uint32_t>(steps.back(), 1, kMaxPyramidStep), uint32_t(steps.size()), grade);
        if (std::equal(made.begin(), made.end(), steps.begin(), steps.end())) return grade;
    }
    return 0.0;
}

size_t pyramidLevelsHeaderBytes(uint32_t size) { return 3 + 2 * size_t(pyramidLevelCount(size)); }

PyramidLevels encodePyramidLevels(std::span<const uint16_t> samples, uint32_t size, const PyramidCodecOptions& options)
{
    const std::vector<uint16_t> steps = levelSteps(samples, size, options);
    PositionCoder<true> coder(size, samples.data(), options.mates, options.tangentScale, steps);
    PyramidLevels out;
    out.header = payloadHeader(kLevelsCodecVersion, steps, options.tangentScale);
    for (uint32_t l = 0; l < coder.levelCount(); ++l) {
        coder.codeLevel(l);
        out.levels.push_back(coder.encoder().finish());
        coder.encoder() = RangeEncoder();  // the next level's stream starts afresh; the models go on
    }
    if (options.levelBytes) {
        options.levelBytes->clear();
        for (const auto& level : out.levels) options.levelBytes->push_back(level.size());
    }
    return out;
}

struct PyramidLevelDecoder::State {
    PositionCoder<false> coder;
    uint32_t decoded = 0;
    bool failed = false;
};

PyramidLevelDecoder::PyramidLevelDecoder(std::span<const uint8_t> header, uint32_t size, std::string name,
                                         std::span<const uint32_t> mates)
    : name_(std::move(name)), size_(size)
{
    checkSize(size, name_);
    checkMates(mates, size, name_);
    auto fail = [&](const std::string& problem) { throw Error(name_ + ": pyramid-coded positions: " + problem); };
    PayloadHeader h = parseHeader(header, kLevelsCodecVersion, size, fail);
    if (header.size() != 3 + 2 * h.steps.size())
        fail("the header holds " + std::to_string(header.size()) + " bytes, not " +
             std::to_string(3 + 2 * h.steps.size()));
    steps_ = h.steps;
    tangentScale_ = h.tangentScale;
    state_ =
        std::make_unique<State>(State{PositionCoder<false>(size, nullptr, mates, h.tangentScale, std::move(h.steps))});
}

PyramidLevelDecoder::~PyramidLevelDecoder() = default;
PyramidLevelDecoder::PyramidLevelDecoder(PyramidLevelDecoder&&) noexcept = default;

uint32_t PyramidLevelDecoder::levelCount() const { return uint32_t(steps_.size()); }
uint32_t PyramidLevelDecoder::levelsDecoded() const { return state_->decoded; }

size_t PyramidLevelDecoder::decodeLevel(std::span<const uint8_t> bytes)
{
    State& st = *state_;
    const uint32_t l = st.decoded;
    auto fail = [&](const std::string& problem) {
        st.failed = true;
        throw Error(name_ + ": pyramid-coded positions, level " + std::to_string(l) + ": " + problem);
    };
    if (st.failed) fail("an earlier level failed to decode");
    if (l >= levelCount()) fail("every level is already decoded");
    st.coder.decoder() = RangeDecoder(bytes);
    st.coder.codeLevel(l);
    if (st.coder.decoder().overrun() > 0)
        fail("the stream runs past the " + std::to_string(bytes.size()) + " bytes given");
    ++st.decoded;
    return st.coder.decoder().consumed();
}

uint32_t PyramidLevelDecoder::decodedSize() const
{
    const uint32_t d = state_->decoded;
    return d == 0 ? 0 : ((size_ - 1) >> (levelCount() - d)) + 1;
}

std::vector<uint16_t> PyramidLevelDecoder::decodedLevel() const
{
    const uint32_t d = state_->decoded;
    if (d == 0) throw Error(name_ + ": pyramid-coded positions: no level is decoded yet");
    const uint32_t shift = levelCount() - d, n = decodedSize();
    const std::vector<uint16_t>& rec = state_->coder.samples();
    std::vector<uint16_t> out;
    out.reserve(size_t(n) * n * 3);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x)
            for (int c = 0; c < 3; ++c)
                out.push_back(rec[((size_t(y) << shift) * size_ + (size_t(x) << shift)) * 3 + c]);
    return out;
}

std::vector<uint16_t> decodePyramidLevels(const PyramidLevels& levels, uint32_t size, const std::string& name,
                                          std::span<const uint32_t> mates)
{
    PyramidLevelDecoder decoder(levels.header, size, name, mates);
    if (levels.levels.size() > decoder.levelCount())
        throw Error(name + ": pyramid-coded positions: " + std::to_string(levels.levels.size()) +
                    " level streams for " + std::to_string(decoder.levelCount()) + " levels");
    for (const std::vector<uint8_t>& stream : levels.levels) {
        const size_t used = decoder.decodeLevel(stream);
        if (used != stream.size())
            throw Error(name + ": pyramid-coded positions, level " + std::to_string(decoder.levelsDecoded() - 1) +
                        ": " + std::to_string(stream.size() - used) + " bytes follow the end of its stream");
    }
    return decoder.decodedLevel();
}

namespace {

// Shared traversal of the normal residuals (raster order; contexts by component and the
// magnitudes of the left and upper residuals).
template <bool Encode>
std::vector<uint16_t> codeNormals(std::span<const uint16_t> positions, std::span<const uint16_t> normals, uint32_t n,
                                  uint32_t bits, bool flip, RangeEncoder* enc, RangeDecoder* dec,
                                  std::span<const uint32_t> mates)
{
    constexpr uint32_t kNone = ~0u;
    std::vector<uint32_t> firstOfClass(mates.empty() ? 0 : size_t(n) * n, kNone);
    std::vector<glm::vec3> predicted = predictedNormals(positions, n);
    std::vector<uint16_t> out(predicted.size() * 3);
    std::vector<uint8_t> mag(predicted.size() * 2, 0);
    std::vector<ResidualModels> models(2 * kBuckets);
    const float step = bits ? 2.0f / float(1u << bits) : 0.0f;
    const int32_t limit = bits ? int32_t(1u << (bits - 1)) : 0;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const size_t s = size_t(y) * n + x;
            if (!mates.empty()) {
                uint32_t& first = firstOfClass[mates[s]];
                if (first != kNone) {
                    for (int c = 0; c < 3; ++c) out[s * 3 + c] = out[size_t(first) * 3 + c];
                    continue;
                }
                first = uint32_t(s);
            }
            const glm::vec3 p = flip ? -predicted[s] : predicted[s];
            glm::vec3 result = p;
            if (bits) {
                glm::vec3 t1, t2;
                tangentFrame(p, t1, t2);
                glm::vec2 e(0.0f);
                int32_t q[2] = {0, 0};
                if constexpr (Encode) {
                    const glm::vec3 v = normalAt(normals, s * 3);
                    e = octahedral(glm::vec3(glm::dot(v, t1), glm::dot(v, t2), glm::dot(v, p)));
                }
                for (int c = 0; c < 2; ++c) {
                    const uint32_t a =
                        (x ? mag[(s - 1) * 2 + c] : 0u) + (y ? mag[(s - n) * 2 + c] : 0u) + (c ? mag[s * 2] : 0u);
                    ResidualModels& m = models[size_t(c * kBuckets + bucketOf(a))];
                    if constexpr (Encode) {
                        q[c] = std::clamp(int32_t(std::lround(e[c] / step)), -limit, limit);
                        encodeResidual(*enc, m, q[c]);
                    } else {
                        q[c] = std::clamp(decodeResidual(*dec, m), -limit, limit);
                    }
                    mag[s * 2 + c] = uint8_t(std::min<int32_t>(std::abs(q[c]), 255));
                }
                const glm::vec3 l = fromOctahedral(glm::vec2(float(q[0]) * step, float(q[1]) * step));
                result = l.x * t1 + l.y * t2 + l.z * p;
            }
            for (int c = 0; c < 3; ++c) out[s * 3 + c] = normal16(result[c]);
        }
    return out;
}

}  // namespace

std::vector<uint16_t> normalsFromPositions(std::span<const uint16_t> positions, uint32_t size, bool flip,
                                           std::span<const uint32_t> mates)
{
    checkSize(size, "normals from positions");
    checkMates(mates, size, "normals from positions");
    if (positions.size() != size_t(size) * size * 3)
        throw Error("normals from positions: the sample count does not match the size");
    return codeNormals<false>(positions, {}, size, 0, flip, nullptr, nullptr, mates);
}

std::vector<uint8_t> encodePredictedNormals(std::span<const uint16_t> decodedPositions,
                                            std::span<const uint16_t> normals, uint32_t size, uint32_t bits,
                                            std::span<const uint32_t> mates)
{
    checkSize(size, "normal coder");
    checkMates(mates, size, "normal coder");
    const size_t count = size_t(size) * size * 3;
    if (decodedPositions.size() != count || normals.size() != count)
        throw Error("normal coder: the sample counts do not match a " + std::to_string(size) + "^2 level");
    if (bits > 16) throw Error("normal coder: " + std::to_string(bits) + " residual bits is above 16");
    // Orientation: the side most input normals lie on.
    const std::vector<glm::vec3> predicted = predictedNormals(decodedPositions, size);
    double agree = 0.0;
    for (size_t s = 0; s < predicted.size(); ++s) agree += glm::dot(predicted[s], normalAt(normals, s * 3));
    const bool flip = agree < 0.0;
    std::vector<uint8_t> out = {kCodecVersion, uint8_t(flip ? 1 : 0), uint8_t(bits)};
    if (bits == 0) return out;  // the decoder recomputes the prediction
    RangeEncoder enc;
    codeNormals<true>(decodedPositions, normals, size, bits, flip, &enc, nullptr, mates);
    const std::vector<uint8_t> stream = enc.finish();
    out.insert(out.end(), stream.begin(), stream.end());
    return out;
}

std::vector<uint16_t> decodePredictedNormals(std::span<const uint8_t> payload,
                                             std::span<const uint16_t> decodedPositions, uint32_t size,
                                             const std::string& name, std::span<const uint32_t> mates)
{
    checkSize(size, name);
    checkMates(mates, size, name);
    auto fail = [&](const std::string& problem) { throw Error(name + ": predicted normals: " + problem); };
    if (decodedPositions.size() != size_t(size) * size * 3) fail("the positions do not match the size");
    if (payload.size() < 3) fail("the payload is truncated (no header)");
    if (payload[0] != kCodecVersion) fail("unknown codec version " + std::to_string(payload[0]));
    if (payload[1] > 1) fail("unknown flags " + std::to_string(payload[1]));
    const uint32_t bits = payload[2];
    if (bits > 16) fail(std::to_string(bits) + " residual bits is above 16");
    const bool flip = payload[1] & 1;
    if (bits == 0) {
        if (payload.size() != 3) fail("a prediction-only payload has extra bytes");
        return codeNormals<false>(decodedPositions, {}, size, 0, flip, nullptr, nullptr, mates);
    }
    RangeDecoder dec(payload.subspan(3));
    std::vector<uint16_t> out = codeNormals<false>(decodedPositions, {}, size, bits, flip, nullptr, &dec, mates);
    if (dec.overrun() > 0) fail("the stream is truncated");
    if (dec.unread() > 0) fail(std::to_string(dec.unread()) + " bytes follow the end of the stream");
    return out;
}

}  // namespace ngi
