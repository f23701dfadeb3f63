// ngi offline: bijectivity of the OT map (paper section 3.1 requires a bijective map
// psi^-1 o phi; the centroid map of Algorithm 1's power cells is not bijective in general).
// Boundary: orthogonal projection on the square's side, order kept. Interior: if anything is
// flipped, a fixed-border solve with Floater's mean value weights of the current layout,
// computed with unsigned angles so that every weight is positive (Floater 2003, "Mean value
// coordinates"; Floater 1997 for the embedding theorem).
#include "ngi/param/untangle.h"

#include "ngi/param/fixed_border_maps.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace ngi {

std::vector<glm::dvec2> makeBijectiveOnSquare(const DiskMesh& disk, const DiskTopology& topology,
                                              const std::array<size_t, 4>& cornerPositions, std::vector<glm::dvec2> uv,
                                              UntangleReport* report)
{
    static const glm::dvec2 kCorner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const auto& loop = disk.boundaryLoop;
    const size_t m = loop.size();
    UntangleReport local;
    for (glm::dvec2& x : uv) x = glm::clamp(x, glm::dvec2(0.0), glm::dvec2(1.0));

    for (int side = 0; side < 4; ++side) {
        const auto [begin, end] = sideRange(side, cornerPositions, m);
        const glm::dvec2 a = kCorner[side], direction = kCorner[(side + 1) % 4] - a;
        const size_t count = end - begin - 1;  // vertices strictly between the corners
        std::vector<double> t(count);
        for (size_t k = 0; k < count; ++k)
            t[k] = std::clamp(glm::dot(uv[loop[(begin + 1 + k) % m]] - a, direction), 0.0, 1.0);
        // Restore strict order along the side (forward, then backward from the far corner).
        const double gap = std::min(1e-7, 0.5 / double(count + 1));
        for (size_t k = 0; k < count; ++k) t[k] = std::max(t[k], (k == 0 ? 0.0 : t[k - 1]) + gap);
        for (size_t k = count; k-- > 0;) t[k] = std::min(t[k], (k + 1 == count ? 1.0 : t[k + 1]) - gap);
        for (size_t k = 0; k < count; ++k) uv[loop[(begin + 1 + k) % m]] = a + t[k] * direction;
        uv[loop[begin % m]] = a;
    }

    local.flippedBefore = countFlippedTriangles(disk, uv);
    local.flippedAfter = local.flippedBefore;
    if (local.flippedBefore > 0) {
        std::vector<glm::dvec2> boundaryUv(m);
        for (size_t k = 0; k < m; ++k) boundaryUv[k] = uv[loop[k]];
        const std::vector<DirectedWeight> weights = meanValueWeights(disk, uv);
        std::vector<glm::dvec2> relaxed;
        // Mean-value weights of a badly tangled layout span many orders of magnitude (1 / r for
        // near-zero edges): the solve can then put interior vertices within round-off of a side,
        // where they collapse onto it (cheese: 9 such triangles). Raising each row's small
        // weights to a growing fraction of its mean moves the solve towards Tutte's map, whose
        // vertices keep a distance from the border; the first floor without flips is kept.
        for (const double floor : {1e-3, 1e-2, 1e-1, 1.0}) {
            relaxed = solveFixedBorderMap(disk, topology, boundaryUv, weights, /*symmetric=*/false,
                                          /*clampNegative=*/true, nullptr, floor);
            // Each interior vertex solves to a convex combination of points of the square; the LU
            // solve's round-off (~1e-16) can still put a vertex just outside, which the OT site
            // check and the rasterizer reject: clamp that round-off away.
            for (glm::dvec2& x : relaxed) x = glm::clamp(x, glm::dvec2(0.0), glm::dvec2(1.0));
            local.weightFloor = floor;
            if (countFlippedTriangles(disk, relaxed) == 0) break;
        }
        for (size_t v = 0; v < uv.size(); ++v)
            if (topology.boundaryPosition[v] < 0)
                local.maxDisplacement = std::max(local.maxDisplacement, glm::length(relaxed[v] - uv[v]));
        uv.swap(relaxed);
        local.relaxed = true;
        local.flippedAfter = countFlippedTriangles(disk, uv);
    }
    if (report) *report = local;
    return uv;
}

}  // namespace ngi
