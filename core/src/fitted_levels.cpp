// Coarse levels fitted to the full surface (fitted_levels.h): linear least squares over the
// level's vertex positions with the parameterization fixed, Hoppe et al. 1993, "Mesh
// Optimization", section 4.2, solved by conjugate gradients (Hestenes and Stiefel 1952).
#include "ngi/fitted_levels.h"

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <thread>

namespace ngi {
namespace {

// The three corners (indices into an n x n level) and barycentric weights of the level's
// triangle holding local point (fx, fy) of quad (qx, qy), alternating diagonals: a-c when
// qx + qy is even, else b-d (a = (0, 0), b = (1, 0), c = (1, 1), d = (0, 1)).
struct Corners {
    std::array<size_t, 3> index;
    std::array<float, 3> weight;
};

Corners cornersAt(uint32_t n, uint32_t qx, uint32_t qy, float fx, float fy)
{
    const size_t a = size_t(qy) * n + qx, b = a + 1, c = a + n + 1, d = a + n;
    if (((qx + qy) & 1) == 0) {
        if (fx >= fy) return {{a, b, c}, {1.0f - fx, fx - fy, fy}};
        return {{a, c, d}, {1.0f - fy, fx, fy - fx}};
    }
    if (fx + fy <= 1.0f) return {{a, b, d}, {1.0f - fx - fy, fx, fy}};
    return {{b, c, d}, {1.0f - fy, fx + fy - 1.0f, 1.0f - fx}};
}

// The data of one level's fit: samples of level 0 every `step` samples, `perQuad` per quad side.
struct FitData {
    const GeometryImage& full;
    uint32_t n, step, perQuad, side;  // level size; data spacing in full samples; data per quad side; data per side

    template <class F> void forEach(F&& f) const
    {
        for (uint32_t j = 0; j < side; ++j) {
            const uint32_t qy = std::min(j / perQuad, n - 2);
            const float fy = float(j - qy * perQuad) / float(perQuad);
            for (uint32_t i = 0; i < side; ++i) {
                const uint32_t qx = std::min(i / perQuad, n - 2);
                const float fx = float(i - qx * perQuad) / float(perQuad);
                f(full.at(i * step, j * step), cornersAt(n, qx, qy, fx, fy));
            }
        }
    }
};

bool interior(uint32_t n, size_t i)
{
    const uint32_t x = uint32_t(i % n), y = uint32_t(i / n);
    return x > 0 && y > 0 && x + 1 < n && y + 1 < n;
}

// Weighted linear least squares over the interior samples of `level` (border fixed), by
// conjugate gradients from its current values: minimizes sum_s weight_s |p_s - A_s x|^2.
void solveWeighted(const FitData& data, const std::vector<float>& weight, std::vector<glm::vec3>& x,
                   uint32_t iterations)
{
    const uint32_t n = data.n;
    const size_t count = size_t(n) * n;
    // Normal equations A^T W A x = A^T W p: r = A^T W (p - A x), zero on the border.
    std::vector<glm::dvec3> r(count, glm::dvec3(0.0));
    size_t s = 0;
    data.forEach([&](const glm::vec3& p, const Corners& c) {
        glm::vec3 residual = p;
        for (int v = 0; v < 3; ++v) residual -= c.weight[v] * x[c.index[v]];
        const double w = weight[s++];
        for (int v = 0; v < 3; ++v) r[c.index[v]] += w * double(c.weight[v]) * glm::dvec3(residual);
    });
    for (size_t i = 0; i < count; ++i)
        if (!interior(n, i)) r[i] = glm::dvec3(0.0);
    std::vector<glm::dvec3> dir = r, q(count);
    auto dot = [&](const std::vector<glm::dvec3>& u, const std::vector<glm::dvec3>& v) {
        glm::dvec3 sum(0.0);
        for (size_t i = 0; i < count; ++i) sum += u[i] * v[i];
        return sum;
    };
    glm::dvec3 rr = dot(r, r);
    for (uint32_t it = 0; it < iterations; ++it) {
        std::fill(q.begin(), q.end(), glm::dvec3(0.0));
        s = 0;
        data.forEach([&](const glm::vec3&, const Corners& c) {
            glm::dvec3 value(0.0);
            for (int v = 0; v < 3; ++v) value += double(c.weight[v]) * dir[c.index[v]];
            value *= double(weight[s++]);
            for (int v = 0; v < 3; ++v) q[c.index[v]] += double(c.weight[v]) * value;
        });
        for (size_t i = 0; i < count; ++i)
            if (!interior(n, i)) q[i] = glm::dvec3(0.0);
        const glm::dvec3 dq = dot(dir, q);
        glm::dvec3 alpha(0.0), beta(0.0);
        for (int a = 0; a < 3; ++a) alpha[a] = dq[a] > 0.0 ? rr[a] / dq[a] : 0.0;
        for (size_t i = 0; i < count; ++i) {
            x[i] += glm::vec3(alpha * dir[i]);
            r[i] -= alpha * q[i];
        }
        const glm::dvec3 next = dot(r, r);
        for (int a = 0; a < 3; ++a) beta[a] = rr[a] > 0.0 ? next[a] / rr[a] : 0.0;
        rr = next;
        for (size_t i = 0; i < count; ++i) dir[i] = r[i] + beta * dir[i];
    }
}

// Fits level k: least squares, then Lawson's reweighting (weights times the residual, the
// classic iteration from least squares towards the minimax fit, Lawson 1961) for `rounds`
// rounds, since the tile bounds measure the largest distance.
void fitLevel(const GeometryImage& full, GeometryImage& level, uint32_t k, uint32_t iterations, uint32_t rounds)
{
    const uint32_t n = level.size;
    if (n < 3) return;
    const uint32_t d = k >= 2 ? k - 2 : 0;
    const FitData data{full, n, 1u << d, 1u << (k - d), (full.size - 1) / (1u << d) + 1};
    std::vector<float> weight(size_t(data.side) * data.side, 1.0f);
    for (uint32_t round = 0; round <= rounds; ++round) {
        // Later rounds start from the previous fit, close to their own: a third of the iterations.
        solveWeighted(data, weight, level.texels, round == 0 ? iterations : std::max(1u, iterations / 3));
        if (round == rounds) break;
        // Lawson: w <- w |r| / mean(w |r|); a sample on the fit keeps a small weight.
        std::vector<float> residual(weight.size());
        size_t s = 0;
        double sum = 0.0;
        data.forEach([&](const glm::vec3& p, const Corners& c) {
            glm::vec3 at(0.0f);
            for (int v = 0; v < 3; ++v) at += c.weight[v] * level.texels[c.index[v]];
            residual[s] = weight[s] * glm::length(p - at);
            sum += residual[s++];
        });
        const double mean = sum / double(weight.size());
        if (!(mean > 0.0)) break;
        for (size_t i = 0; i < weight.size(); ++i) weight[i] = float(std::max(double(residual[i]) / mean, 1e-3));
    }
}

}  // namespace

void fitCoarseLevels(SurfacePyramid& pyramid, uint32_t iterations, uint32_t rounds)
{
    if (pyramid.levelCount() < 2) return;
    const GeometryImage& full = pyramid.positions[0];
    // Every level is fitted to level 0 alone: the levels are independent, one thread each up to
    // the cores there are (levels 1 and 2 read all of level 0 and take most of the time).
    std::atomic<uint32_t> next{1};
    std::exception_ptr failure;
    std::mutex failureMutex;
    auto work = [&] {
        for (uint32_t k = next++; k < pyramid.levelCount(); k = next++) {
            try {
                fitLevel(full, pyramid.positions[k], k, iterations, rounds);
            } catch (...) {
                const std::lock_guard<std::mutex> lock(failureMutex);
                if (!failure) failure = std::current_exception();
            }
        }
    };
    const uint32_t threads = std::min(pyramid.levelCount() - 1, std::max(1u, std::thread::hardware_concurrency()));
    std::vector<std::thread> pool;
    for (uint32_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
}

std::pair<glm::vec3, glm::vec3> coarserSurfaceAt(const GeometryImage& coarserPositions,
                                                 const GeometryImage& coarserNormals, uint32_t x, uint32_t y)
{
    const uint32_t n = coarserPositions.size;
    const uint32_t qx = std::min(x >> 1, n - 2), qy = std::min(y >> 1, n - 2);
    const Corners c = cornersAt(n, qx, qy, float(x - 2 * qx) * 0.5f, float(y - 2 * qy) * 0.5f);
    glm::vec3 p(0.0f), normal(0.0f);
    for (int v = 0; v < 3; ++v) {
        p += c.weight[v] * coarserPositions.texels[c.index[v]];
        normal += c.weight[v] * coarserNormals.texels[c.index[v]];
    }
    const float length = glm::length(normal);
    return {p, length > 0.0f ? normal / length : glm::vec3(0.0f, 0.0f, 1.0f)};
}

}  // namespace ngi
