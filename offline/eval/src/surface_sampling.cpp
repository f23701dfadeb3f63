// ngi offline eval: the normalization frame and the area-uniform surface sampling of
// docs/DESIGN.md "Metrics" (frame: reference bbox centre, longest side 1; 200k samples per
// surface, uniform by area, fixed seed).
#include "ngi/eval/surface_distance.h"

#include "ngi/error.h"
#include "surface_checks.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace ngi {
namespace detail {

void checkSurface(const TriangleMesh& mesh, const std::string& what)
{
    if (mesh.triangles.empty()) throw Error(what + ": has no triangles");
    const size_t n = mesh.positions.size();
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3& tri = mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
            if (tri[k] >= n)
                throw Error(what + ": triangle " + std::to_string(t) + " uses vertex " + std::to_string(tri[k]) +
                            " but the mesh has " + std::to_string(n) + " vertices");
            const glm::dvec3& p = mesh.positions[tri[k]];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw Error(what + ": vertex " + std::to_string(tri[k]) + " has a non-finite coordinate");
        }
    }
}

}  // namespace detail

ReferenceFrame referenceFrame(const TriangleMesh& reference)
{
    detail::checkSurface(reference, "reference mesh");
    // The bounding box of the surface: the vertices used by triangles (stray unused vertices
    // are not part of the surface and must not move the frame).
    glm::dvec3 lo(std::numeric_limits<double>::infinity());
    glm::dvec3 hi(-std::numeric_limits<double>::infinity());
    for (const glm::uvec3& tri : reference.triangles)
        for (int k = 0; k < 3; ++k) {
            lo = glm::min(lo, reference.positions[tri[k]]);
            hi = glm::max(hi, reference.positions[tri[k]]);
        }
    const glm::dvec3 side = hi - lo;
    const double longest = std::max({side.x, side.y, side.z});
    if (!(longest > 0.0) || !std::isfinite(longest)) throw Error("reference mesh: its bounding box has zero size");
    ReferenceFrame frame;
    frame.centre = 0.5 * (lo + hi);
    frame.scale = 1.0 / longest;
    return frame;
}

std::vector<glm::dvec3> sampleSurface(const TriangleMesh& mesh, uint32_t count, uint64_t seed)
{
    std::vector<glm::dvec3> positions;
    positions.reserve(count);
    for (const SurfaceSample& s : sampleSurfacePoints(mesh, count, seed)) positions.push_back(s.position);
    return positions;
}

std::vector<SurfaceSample> sampleSurfacePoints(const TriangleMesh& mesh, uint32_t count, uint64_t seed)
{
    detail::checkSurface(mesh, "mesh");
    // Cumulative areas (twice the area; the factor cancels) for the triangle choice.
    std::vector<double> cumulative(mesh.triangles.size());
    double total = 0.0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3& tri = mesh.triangles[t];
        const glm::dvec3 a = mesh.positions[tri.x];
        total += glm::length(glm::cross(mesh.positions[tri.y] - a, mesh.positions[tri.z] - a));
        cumulative[t] = total;
    }
    if (!(total > 0.0) || !std::isfinite(total)) throw Error("mesh: its surface has zero (or non-finite) area");

    std::mt19937_64 rng(seed);
    // 53 random bits -> a double in [0, 1); mt19937_64's sequence is fixed by the standard.
    auto uniform = [&rng] { return double(rng() >> 11) * 0x1.0p-53; };

    std::vector<SurfaceSample> samples(count);
    for (uint32_t i = 0; i < count; ++i) {
        const double target = uniform() * total;
        // First triangle whose cumulative area exceeds the target: never a zero-area one.
        size_t t = size_t(std::upper_bound(cumulative.begin(), cumulative.end(), target) - cumulative.begin());
        t = std::min(t, cumulative.size() - 1);
        while (t > 0 && cumulative[t] == cumulative[t - 1])  // only if target rounded to the end
            --t;
        const glm::uvec3& tri = mesh.triangles[t];
        // Uniform point in a triangle: sqrt-warped barycentrics (Turk 1990).
        const double s = std::sqrt(uniform());
        const double r = uniform();
        const double wa = 1.0 - s, wb = s * (1.0 - r), wc = s * r;
        samples[i].position = wa * mesh.positions[tri.x] + wb * mesh.positions[tri.y] + wc * mesh.positions[tri.z];
        samples[i].triangle = uint32_t(t);
        samples[i].barycentric = {wa, wb, wc};
    }
    return samples;
}

}  // namespace ngi
