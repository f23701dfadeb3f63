// ngi offline: the ngi-bake pipeline (paper section 3.1 and "Input Precondition"):
//   1 read  2 clean, connected components (optionally split into matched pieces)
//   3 remesh  4 cut to a disk  5-6 map to the square (conformal start + optimal transport, or
//   another --param method)  6b matched border  7 rasterize (3-7 per chart; a component with
//   thin parts is handed over to the split and baked after the rest)  then the charts' order,
//   the appearance, and 8 store the mip level.
// Stages 1 and the file writes are the tool's (ngi_bake_main.cpp); this library runs 2-8 in
// memory and returns the asset plus a full report.
#pragma once

#include "ngi/asset.h"
#include "ngi/geometry_image.h"
#include "ngi/mesh/appearance.h"
#include "ngi/mesh/clean.h"
#include "ngi/mesh/cut.h"
#include "ngi/mesh/mesh_topology.h"
#include "ngi/mesh/remesh.h"
#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/detail_transfer.h"
#include "ngi/param/matched_border.h"
#include "ngi/param/parameterize.h"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ngi {

// The cut search (one Ricci flow per candidate cut) runs on a remesh of the part with this
// many vertices when the bake's remesh has more than twice as many; the chosen cut is then
// made on the remesh (cutByPlan).
inline constexpr size_t kCutSearchVertices = 6000;

struct BakeOptions {
    uint32_t resolution = 1024;      // full geometry image: resolution + 1 samples per side
    uint32_t storeResolution = 128;  // stored mip level: storeResolution + 1 samples per side
    ParameterizationMethod method = ParameterizationMethod::OptimalTransport;
    size_t remeshVertexCount = 0;  // 0: remeshVertexCountFor(resolution)
    // The cut search runs on a remesh of the part with this many vertices when the remesh has
    // more than twice as many (kCutSearchVertices; 0: always on the remesh itself).
    size_t cutSearchVertices = kCutSearchVertices;
    double featureAngleDegrees = RemeshOptions{}.featureAngleDegrees;  // creases kept by the remesher; <= 0: none
    // Match the border so that seams stay closed at every level of detail (matched_border.h).
    // Off: the map's own border, seams crack (the paper's behaviour; for comparisons).
    bool matchSeams = true;
    // Move the rasterized samples onto the input surface (detail_transfer.h), so the remesh
    // carries only the map. Off: the samples interpolate the remesh (for comparisons).
    bool transferDetail = true;
    // OT target measure: 0 preserves area (the paper); S > 0 gives each site its area times
    // 1 + S * (its mean curvature over the surface's mean, at most kMaxDetailRatio): samples
    // follow detail (ngi/param/detail_density.h). Other maps ignore it.
    double detailDensity = 0.0;
    // ngi-bake --split-pieces (docs/splitting.md, docs/cross-chart-seams.md): > 1 remeshes every component whose share
    // of the area gives round(splitPieces x share) >= 2 once, cuts the remesh into that many
    // geodesic Voronoi pieces (chart_split.h), one chart each at one resolution, and matches
    // their borders together (matchBorders: shared curves sample the same points at every
    // level <= K; the full images are welded across charts, BakeResult::crossSeams, stored in
    // the asset as format 7, welded again after every restore by the engine and ngi-eval).
    // Not a default: it loses on compact shapes (docs/splitting.md). 0 or 1: no split.
    uint32_t splitPieces = 0;
    // Components with thin parts are split (docs/splitting.md):
    // where the one-chart bake of a component would remesh it densely for thin parts (a
    // conformal shrink above e^kMaxCoarseRemeshShrink on the cut search's coarse remesh or on
    // the remesh, or a remesh that cuts through thin parts, kMaxRemeshFarArea), the bake's
    // sign of limbs that one chart undersamples, the component is cut into
    // round(splitThinParts x its area share) matched charts as splitPieces does instead. Where
    // that rounds below 2, or the pieces' borders cannot be matched, it is one chart on the
    // dense remesh. A component of genus above kMaxOneChartGenus is split at once;
    // a split component of genus g gets at least g / 2 pieces. Needs transferDetail and no
    // remeshVertexCount (the adaptive remesh). 0 or 1: never.
    uint32_t splitThinParts = 8;
    // The input's appearance as the reader found it (mesh_io.h), or null: each chart then gets
    // a base colour image over its square (docs/appearance.md). Must outlive the bake.
    const MeshAppearance* appearance = nullptr;
    std::string sourceName = "mesh";  // recorded in the asset and named in errors
    uint64_t sourceHash = 0;          // FNV-1a 64 of the source file (0 = none)
    // One call per finished stage: (stage name, seconds, one-line summary). Library code never
    // prints; the tool does.
    std::function<void(const std::string& stage, double seconds, const std::string& summary)> stageDone;
    // Progress inside the parameterization stages (forwarded to ParameterizeOptions::progress).
    std::function<void(const std::string&)> progress;
};

// The remeshing density used for a resolution: resolution^2 / 64 vertices (a 1024 image has
// ~64 samples per vertex), clamped to [1000, 150000]. The remesh carries the map only: the
// samples take their positions from the input (BakeOptions::transferDetail), so a coarser
// remesh costs little accuracy and saves most of the time. Charts with thin parts are
// remeshed denser (remeshVertexCountForThinParts).
size_t remeshVertexCountFor(uint32_t resolution);

// The density for charts with thin parts (resolution^2 / 16, clamped to [1000, 150000]): used
// when the remesh at remeshVertexCountFor cuts through or off a thin part (kMaxRemeshFarArea)
// or its conformal start shrinks a protrusion by more than e^kMaxCoarseRemeshShrink (on the
// remesh, or already on the cut search's coarse remesh, BakeOptions::cutSearchVertices).
size_t remeshVertexCountForThinParts(uint32_t resolution);
inline constexpr double kMaxCoarseRemeshShrink = 8.0;
// With BakeOptions::splitThinParts, a component of higher genus is split at once (into at
// least genus / 2 pieces) instead of trying one chart first.
inline constexpr long kMaxOneChartGenus = 32;

// Fraction of the 3D area of `mesh` in triangles whose share of the uv area is less than
// 1/factor of their share of the 3D area (those get almost no geometry-image samples).
double undersampledAreaFraction(const TriangleMesh& mesh, const std::vector<glm::dvec2>& uv, double factor);
inline constexpr double kUndersampling = 100.0;  // the bake warns above 0.1% of the area at 1/100

// A remesh with more than this share of its area off the input by more than half an edge is
// redone at twice the density (thin parts; the detail transfer cannot repair them).
inline constexpr double kMaxRemeshFarArea = 2e-4;

struct StageTime {
    std::string stage;
    double seconds = 0.0;
};

// What happened to one chart (one connected component of the cleaned input).
struct ChartReport {
    MeshTopology topology;  // of the component as cleaned (genus, boundaries)
    int splitGroup = -1;    // the split component it is a piece of (BakeOptions::splitPieces), -1: none
    // Why its component was split (BakeOptions::splitThinParts): the sign of thin parts its
    // one-chart bake found ("conformal shrink e^X > e^8 on the N-vertex remesh"), or the check
    // its one-chart map failed ("one chart failed its checks: ..."); empty where it was not
    // split or splitPieces split every component.
    std::string splitForThinParts;
    double crossSeamGapBeforeWeld =
        0.0;                    // largest distance between a shared curve's two sides (object units), welded to 0
    double areaFraction = 1.0;  // its share of the cleaned surface area
    uint32_t resolution = 0;    // its full geometry image: resolution^2 cells
    RemeshReport remesh;
    double remeshFarArea = 0.0;       // share of the remesh farther than edge/2 from the input (areaFartherThan)
    uint32_t remeshDensified = 0;     // times the density was doubled because of it
    bool remeshForThinParts = false;  // remeshed at remeshVertexCountForThinParts (strong conformal shrink)
    bool denseRemeshFailed = false;   // the dense remesh's chart failed; the coarse remesh was baked
    std::string denseRemeshProblem;   // why it failed (flips, OT, a sampling or image check)
    CutReport cut;
    double cutConformalShrink = 0.0;        // max log shrink of the conformal start on the chosen cut
    size_t cutRounds = 0;                   // cuts measured (the search's and those on the remeshes)
    size_t cutSearchVertices = 0;           // vertices of the coarse remesh the cut search ran on (0: on the remesh)
    double undersampledAreaFraction = 0.0;  // of the surface at < 1/kUndersampling of its fair sample share
    double farFromImageArea =
        0.0;  // of the input farther than kFarFromImageDistance x size from the image (checkChartImage)
    ParameterizeReport parameterization;
    MatchedBorderReport seam;            // the matched border (watertight seams), see matched_border.h
    double seamGapBeforeWeld = 0.0;      // largest mate distance of the rasterized image (object units), welded to 0
    DetailTransferReport detail;         // samples moved onto the input (if BakeOptions::transferDetail)
    double seamAreaDistortionMax = 0.0;  // max |log(uv area / 3D area)| after matching (before: parameterization)
    double seamAreaDistortionMean = 0.0;
    int colorLevel = -1;  // level of its full image its base colour covers (-1: no colour)
};

struct BakeReport {
    CleanReport clean;
    MeshTopology cleaned;              // topology of the whole cleaned input
    std::vector<ChartReport> charts;   // one per chart, in the asset's order (largest first)
    std::string method;                // parameterizationName(options.method)
    double detailDensity = 0.0;        // options.detailDensity (OT only)
    double colorSamplesPerArea = 0.0;  // the colour's need (SurfaceColor::samplesPerArea; 0: no appearance)
    std::vector<StageTime> stages;     // clean, remesh, cut, parameterize, rasterize, store (summed over charts)
    double totalSeconds = 0.0;
    std::vector<std::string> warnings;
};

// One chart's intermediate results (for exports, tests and the evaluation).
struct ChartBake {
    GeometryImage fullPositions;  // full resolution, normalized to [0,1]^3 (asset frame)
    GeometryImage fullNormals;    // full resolution, unit normals
    DiskMesh disk;                // the remeshed, cut component
    SquareMap map;                // its uv map (border matched when seams.matched)
    ChartSeams seams;             // the chart's seam (also in the asset's chart)
};

struct BakeResult {
    Asset asset;                    // ready to write (writeAsset)
    std::vector<ChartBake> charts;  // parallel to asset.charts
    // Curves shared by charts of a split component (BakeOptions::splitPieces), in asset chart
    // indices; the full images are welded along them (also in asset.crossSeams).
    std::vector<CrossSeamSegment> crossSeams;
    BakeReport report;
};

// The full resolution of a chart that holds `areaFraction` of the surface when the whole
// surface gets `resolution`^2 cells: samples proportional to area, a power of two (rounded
// in log2), at least kMinChartResolution (so a small part keeps a usable shape, and at
// least one sample per side survives at the stored level) and at most `resolution`.
inline constexpr uint32_t kMinChartResolution = 32;

uint32_t chartResolutionFor(uint32_t resolution, uint32_t storedLevel, double areaFraction);

// Runs stages 2-8 on a mesh as read from a file: every connected component becomes one chart,
// or a group of matched charts where it is split (BakeOptions::splitPieces, splitThinParts;
// stages 3-7 per chart), all charts normalized into one frame and stored at the
// same level (so one network restores them all). Throws ngi::Error "SOURCE: problem"
// naming the stage (and chart) that failed; never prints. Resolutions must be powers of two with
// 1 <= storeResolution <= resolution, 2 <= resolution <= kMaxFullResolution (4096, ngi/asset.h).
BakeResult bakeMesh(const TriangleMesh& input, const BakeOptions& options = {});

// True when some component of the bake was split for its thin parts (BakeOptions::splitThinParts,
// ChartReport::splitForThinParts). At a byte budget such a bake competes with one chart per
// component (the same options with splitThinParts = 0): ngi-bake --target-bytes and
// ngi-eval report's budget rows keep whichever the rate control finds closer to the input.
bool anyComponentSplitForThinParts(const BakeReport& report);

// The stage-8 normalization of `image`, whose positions are relative to `centre` (the input's
// coordinates = centre + position): object = offset + scale * normalized, one uniform scale so
// that the longest side of the image's bounding box maps to [0,1] and the others are centred in
// it. offset is rounded down to floats and scale up, so that offset + scale * [0,1]^3 covers the
// image exactly in the input's coordinates (the box widens by at most a float step of the
// distance from the origin). Throws ngi::Error for an image of zero or non-finite size.
void normalizationFor(const GeometryImage& image, const glm::dvec3& centre, glm::vec3& offset, glm::vec3& scale);

// The geometry image as a triangle mesh: one vertex per sample, each cell split into two
// triangles along the diagonal (x, y)-(x+1, y+1). Samples are used as given (no weld at
// the seam), which is what a renderer draws.
TriangleMesh geometryImageMesh(const GeometryImage& image);

// The peak resident memory of this process so far (bytes; 0 where unknown).
size_t peakResidentBytes();

}  // namespace ngi
