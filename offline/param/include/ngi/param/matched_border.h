// ngi offline: the matched boundary parameterization that makes a chart's seams watertight
// at every level of detail (Gu, Gortler, Hoppe 2002, "Geometry Images", section 4).
//
// After the square map, every cut path appears twice on the disk's boundary, once per side,
// and the two sides usually get different lengths on the square's border, so their border
// samples hit different surface points and the drawn mesh cracks. This stage re-places the
// boundary: the cut nodes (where the mate structure of the boundary changes) land on
// multiples of 2^K samples, the corners on the square's corners, the two sides of every
// cut path get the same length, and the vertices inside a path get the same fraction on
// both sides. Then mate border samples are the same surface point at every level 0..K of
// the nested pyramid. The interior follows the moved border through the mean-value weights
// of the current layout (Floater 2003): unchanged where the border did not move, bijective
// because the weights are positive and the border convex. Then the interior is transported
// once more (semi-discrete OT from that map, border fixed) when that preserves area better.
#pragma once

#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/disk_topology.h"
#include "ngi/param/parameterize.h"
#include "ngi/seam.h"

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace ngi {

struct MatchedBorderReport {
    size_t cutPaths = 0;           // mate segment pairs on the border
    size_t openSegments = 0;       // segments of the input's own boundary loops
    uint32_t level = 0;            // coarsest watertight level K chosen
    uint32_t levelLimit = 0;       // the coarsest level asked for
    double lengthChange = 0.0;     // sum over border segments of |new - old length|, fraction of the perimeter
    double mismatch = 0.0;         // the same for the two sides' natural mismatch alone (the cost of any matching)
    double maxBorderMove = 0.0;    // largest move of a boundary vertex along the border (uv units)
    double maxInteriorMove = 0.0;  // largest move of an interior vertex (uv units)
    size_t flippedTriangles = 0;   // after the interior solve (0 when matched)
    double areaDistortionMeanBefore = 0.0;  // of the mean-value map with the matched border
    bool retransported = false;             // the interior was transported again (better area) with the border fixed
    int transportIterations = 0;            // Newton iterations of those transports
    int transportRounds = 0;                // rounds kept
    // Every round tried (kept or not): the map's mean area distortion after it (the value
    // before the first is areaDistortionMeanBefore) and its wall time, so the cost of each
    // round is visible beside what it gained.
    std::vector<double> roundAreaDistortionMean, roundSeconds;
    bool movedCorners = false;  // the map's corners made equal lengths impossible: new corners chosen
    bool matched = false;       // false: the map was left as it was (reason in `problem`)
    std::string problem;
};

struct MatchedBorder {
    std::vector<glm::dvec2> uv;         // the new map (the old one when !report.matched)
    std::array<uint32_t, 4> corners{};  // disk vertices on the square's corners (may differ from the map's)
    ChartSeams seams;                   // matched = report.matched
    MatchedBorderReport report;
};

// Matches the border of `map` (a bijective map of `disk` onto the square, boundary on the
// border, corners on the corners) for a chart of `resolution` cells (power of two). K is
// the coarsest level <= levelLimit whose rounding of the border lengths costs at most
// `maxExtraLengthChange` of the perimeter beyond the matching at full resolution. If no
// level works, or the interior solve would flip a triangle, returns the map unchanged with
// matched = false and the reason (the chart then draws without a seam guarantee).
MatchedBorder matchBorder(const DiskMesh& disk, const SquareMap& map, uint32_t resolution, uint32_t levelLimit,
                          double maxExtraLengthChange = 0.05, unsigned threads = 2);

// The fractions of a border run's vertices 0..n (phi.size() = n + 1: their natural fractions,
// increasing) through `pins` (vertex, fraction; (0, 0) and (n, 1) among them): between pins a
// blend of phi and index spacing, so no boundary edge collapses. Empty when the pins are not
// increasing in both. Shared by matchBorder and matchBorders.
std::vector<double> pinnedFractions(const std::vector<double>& phi, std::vector<std::pair<size_t, double>> pins);

// The point of the square's border at perimeter parameter t in [0, 4R] (samples, counter-
// clockwise from the corner (0, 0), as seam.h's perimeter index).
glm::dvec2 perimeterUv(double t, uint32_t resolution);

// The interior after the border of `map` moved to `boundaryUv` (per position of
// disk.boundaryLoop): the mean-value weights of the map (Floater 2003), raised towards Tutte's
// where they fold, then one transport round of the interior when report.lengthChange is large
// and it preserves area better. Fills the report's interior fields; false (uv unusable) when a
// triangle stays flipped (report.flippedTriangles). Shared by matchBorder and matchBorders.
bool solveMatchedInterior(const DiskMesh& disk, const DiskTopology& topology, const SquareMap& map,
                          const std::vector<glm::dvec2>& boundaryUv, unsigned threads, MatchedBorderReport& report,
                          std::vector<glm::dvec2>& uv);

}  // namespace ngi
