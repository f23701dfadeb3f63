// ngi offline: the matched border of a GROUP of charts that share curves (one surface split
// into several charts; docs/cross-chart-seams.md section 3).
//
// matchBorder (matched_border.h) makes the two sides of every cut path of ONE chart sample the
// same surface points at every level 0..K (Gu, Gortler, Hoppe 2002, section 4). Here the same
// holds for every curve two charts share: both sides get the same integer length (units of
// 2^K samples, solveGroupLengths), their ends land on multiples of 2^K in both charts, and the
// vertices along the curve get the same fractions on both sides, so border sample a + i of one
// chart and b + length - i of the other are one surface point at every level <= K. Cut paths
// within a chart are matched as matchBorder does, in the same length system. Corner 0 of each
// chart stays where its map put it; corners 1-3 go to the vertex nearest c R after the lengths
// are solved (a pin in the fractions of the curve it lies on, shared with the other side).
// Each chart's interior then follows its moved border (solveMatchedInterior).
#pragma once

#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/matched_border.h"
#include "ngi/param/parameterize.h"
#include "ngi/seam.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ngi {

inline constexpr uint32_t kNoGroupVertex = ~0u;

// One chart of the group: its disk, its square map, its resolution (a power of two) and, per
// vertex of disk.mesh, the vertex of the group's shared numbering it is (the surface before it
// was split and cut; kNoGroupVertex for vertices the cut added). A boundary edge of one chart
// whose two group vertices bound an open boundary edge of another chart is a shared curve.
struct GroupChart {
    const DiskMesh* disk = nullptr;
    const SquareMap* map = nullptr;
    uint32_t resolution = 0;
    std::vector<uint32_t> groupVertex;
};

struct MatchedGroup {
    std::vector<MatchedBorder> charts;         // per chart: map, corners, its own seams (cut paths)
    std::vector<CrossSeamSegment> crossSeams;  // the shared curves, chartA < chartB
    uint32_t level = 0;                        // the coarsest watertight level K of every chart
    size_t sharedCurves = 0;                   // length classes shared by two charts
    size_t repairWalks = 0;                    // solveGroupLengths' walks at the chosen level
    bool matched = false;                      // false: every chart keeps its map (see problem)
    std::string problem;
};

// Matches the borders of `charts` together. K is the coarsest level <= levelLimit (and <= log2
// of the smallest resolution) whose rounding costs at most maxExtraLengthChange of the
// perimeters beyond the matching at full resolution, and at least minLevel where a matching
// exists there whatever it costs (the stored level: a curve node between stored samples is
// interpolated differently by the two charts' restores). If no level has integer lengths, a
// corner cannot be placed, or a chart's interior would flip, matched is false with the
// reason and the maps are returned unchanged. Throws ngi::Error on inconsistent input (a
// groupVertex table of the wrong size, a resolution that is not a power of two).
MatchedGroup matchBorders(std::span<const GroupChart> charts, uint32_t levelLimit, double maxExtraLengthChange = 0.05,
                          unsigned threads = 2, uint32_t minLevel = 0);

}  // namespace ngi
