// ngi core: the seam of a chart, i.e. which border samples of its geometry image are the same
// point of the surface (the two sides of the cut), and the weld that makes them identical.
//
// Matched boundary parameterization after Gu, Gortler, Hoppe 2002, "Geometry Images",
// section 4: the two sides of every cut path get the same length on the square's border and
// every cut node (and every corner) lands on a sample of the coarsest watertight level, so a
// border sample's mate is again a border sample, at every level of the nested pyramid
// (mip_pyramid.h: level L+1 = even samples of level L).
//
// Border samples are addressed by their PERIMETER index t in [0, 4R) (R = resolution),
// counter-clockwise from the corner (0, 0), as the parameterization lays the disk's
// boundary loop out: t in [0, R] -> (t, 0), [R, 2R] -> (R, t - R), [2R, 3R] -> (3R - t, R),
// [3R, 4R) -> (0, 4R - t).
//
// A segment pair {a, b, length} says that sample a + i and sample b + length - i are one
// surface point for i = 0..length (the second side runs the opposite way, as the two sides
// of a cut do). Border samples in no segment lie on a boundary loop of the input (open).
// Why the weld: the bake samples mates at the same 3D point up to rounding, and every
// restore (network, bilinear, bicubic) computes the two sides from different neighbourhoods;
// copying one canonical sample onto its mates after each restore makes them bitwise equal,
// and nested subsampling plus symmetric geomorph targets keep them equal at every level.
#pragma once

#include "ngi/geometry_image.h"

#include <glm/vec2.hpp>

#include <cstddef>

#include <cstdint>
#include <string>
#include <vector>

namespace ngi {

struct SeamSegment {
    uint32_t a = 0;       // first side: perimeter samples a .. a + length (forward)
    uint32_t b = 0;       // second side: perimeter samples b + length .. b (backward)
    uint32_t length = 0;  // in full-resolution samples, > 0
};

// A curve two charts of one surface share (a component split into several charts):
// perimeter sample chartA:a + i and sample chartB:b + length - i are one surface point for i =
// 0..length, each in its own chart's full-resolution perimeter units (the charts draw the same
// level index, so the curve keeps length >> l samples on both sides at level l). Produced by
// the group matcher (offline matched_group.h), stored in format 7 assets (XSEM chunk, asset.h).
struct CrossSeamSegment {
    uint32_t chartA = 0, a = 0;
    uint32_t chartB = 0, b = 0;
    uint32_t length = 0;
};

struct ChartSeams {
    // True when the bake matched the border (format 3 assets with a SEAM chunk). False for
    // older assets: no weld, every level drawn, seams may crack.
    bool matched = false;
    std::vector<SeamSegment> segments;  // full-resolution perimeter units
    // The coarsest mip level at which every seam stays closed: all segment ends (cut nodes,
    // corners) are multiples of 2^coarsestWatertightLevel. Coarser levels are not drawn.
    uint32_t coarsestWatertightLevel = 0;
};

// The sample (x, y) of perimeter index t (0 <= t < 4R) of an image of resolution R.
glm::uvec2 perimeterSample(uint32_t resolution, uint32_t t);

// The largest level k such that every segment end is a multiple of 2^k, clamped to
// `levelLimit` (a chart with no segment returns levelLimit).
uint32_t seamAlignedLevel(const std::vector<SeamSegment>& segments, uint32_t levelLimit);

// The coarsest level a seam is matched to for a chart of `levelCount` mip levels: the 5 x 5
// level (coarser grids of a closed surface fold onto themselves: a torus's four corners are
// one point), or the coarsest level there is.
uint32_t seamLevelLimit(uint32_t levelCount);

// The coarsest level a chart of `levelCount` levels draws: every level without a matched
// seam; with one, its coarsest watertight level (the bake matches to seamLevelLimit, the
// 5 x 5 level, where the cut allows; a cut with more nodes than a coarse border has samples
// gets a finer level, and the chart's LoD range ends there: no drawn level ever opens).
uint32_t coarsestDrawnLevel(const ChartSeams& seams, uint32_t levelCount);

// Checks a seam against a chart of `resolution` (power of two) with `levelCount` mip levels:
// every segment non-empty and inside [0, 4R], the two sides not overlapping themselves,
// coarsestWatertightLevel < levelCount and every end a multiple of 2^coarsestWatertightLevel.
// Throws ngi::Error "NAME: seam segment K ..." naming the first violation.
void validateSeams(const ChartSeams& seams, uint32_t resolution, uint32_t levelCount, const std::string& name);

// Checks cross-chart seams against the charts' seams and resolutions: chartA < chartB < the
// chart count, both charts matched with one coarsest watertight level K, length > 0, both runs
// inside their perimeters (a + length <= 4 R_A, b + length <= 4 R_B), a, b and length
// multiples of 2^K. Throws ngi::Error "NAME: cross seam K ..." naming the first violation.
void validateCrossSeams(const std::vector<CrossSeamSegment>& crossSeams, const std::vector<ChartSeams>& seams,
                        const std::vector<uint32_t>& resolutions, const std::string& name);

// For every perimeter index t of the full resolution, the canonical sample of its mate class
// (the smallest perimeter index that is the same surface point; t itself if it has no mate).
// Classes are closed transitively, so a cut node shared by several sides has one canonical.
// Requires validateSeams to pass.
std::vector<uint32_t> seamWeldTable(const ChartSeams& seams, uint32_t resolution);

// The table of mip level `level` (resolution R >> level): perimeter index t of that level is
// full-resolution index t << level. Requires level <= seams.coarsestWatertightLevel, so that
// every mate of a level sample is again one (ngi::Error otherwise).
std::vector<uint32_t> seamWeldTable(const ChartSeams& seams, uint32_t resolution, uint32_t level);

// Copies each border sample's canonical value onto it (`table` from seamWeldTable for
// image.resolution()). ngi::Error if the table does not fit the image.
void weldSeams(GeometryImage& image, const std::vector<uint32_t>& table);

// The weld of a group of charts at mip level `level` as two lists per chart: `gather` (perimeter
// index of that level, value slot) for every canonical sample that has a mate, `scatter` (index,
// slot) for every sample that takes a canonical's value. A GPU weld copies gather -> slots, then
// slots -> scatter (engine's seam_weld_group.comp); weldGroupSeams applies the same plan on the
// CPU. Classes as in weldGroupSeams, over the charts named in crossSeams only (the others weld
// themselves; their lists stay empty); the same errors.
struct GroupWeldPlan {
    std::vector<std::vector<glm::uvec2>> gather, scatter;  // [chart]: (perimeter index, slot)
    uint32_t slots = 0;
};
GroupWeldPlan groupWeldPlan(const std::vector<ChartSeams>& seams, const std::vector<uint32_t>& resolutions,
                            const std::vector<CrossSeamSegment>& crossSeams, uint32_t level);

// Welds a group of charts at mip level `level` (images[c]: chart c's level, (R_c >> level) + 1
// samples per side): one class per surface point over every chart's border (its own mates and
// the cross seams, closed transitively), the smallest (chart, perimeter index) canonical, its
// value copied onto the others. What makes the charts of a split component bitwise equal along
// their shared curves after any restore (engine and CPU mirror alike). Requires level <= every
// involved chart's coarsest watertight level (ngi::Error otherwise, or on sizes that do not
// match). Returns the largest distance a sample moved.
double weldGroupSeams(const std::vector<GeometryImage*>& images, const std::vector<ChartSeams>& seams,
                      const std::vector<uint32_t>& resolutions, const std::vector<CrossSeamSegment>& crossSeams,
                      uint32_t level);

// The largest distance between a border sample and its canonical mate, and the number of
// mates that are not bitwise equal: how open the seam of an unwelded image is.
struct SeamGap {
    double maxDistance = 0.0;
    size_t unequalMates = 0;
};
SeamGap measureSeamGap(const GeometryImage& image, const std::vector<uint32_t>& table);

}  // namespace ngi
