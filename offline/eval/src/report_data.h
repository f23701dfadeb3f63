// ngi offline eval, report internals: the measured rows that report.cpp fills and
// report_markdown.cpp turns into tables, plots and the Markdown page.
#pragma once

#include "ngi/eval/report.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace ngi::report_detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// One CD/HD measurement of a candidate mesh against the input (report scales applied:
// cd x1e-4, hd x1e-2), or the reason it could not be made.
struct Measured {
    bool ok = false;
    std::string failure;  // "" when ok, else "failed: reason" / "not run: reason"
    double cd = kNaN;     // x1e-4
    double hd = kNaN;     // x1e-2
    size_t triangles = 0;
};

struct BakeRow {
    std::string method;  // "tutte", ..., "ot"
    bool ok = false;
    std::string failure;  // the baker's message when !ok
    bool reused = false;
    double seconds = 0.0;  // bake time (0 when reused)
    double areaDistortionMean = kNaN, angleDistortionMean = kNaN;
    Measured full;  // full-resolution image mesh (LoD 0 of the level-0 asset)
};

// The bytes of an .ngi file: the whole file and its chunks' stored sizes.
struct AssetBytes {
    size_t file = 0, positions = 0, normals = 0, metadata = 0, weights = 0;
};

struct StoredRow {
    uint32_t stored = 0;            // stored resolution (cells per side)
    uint32_t level = 0;             // mip level kept
    double compressionRatio = 0.0;  // resolution^2 / stored^2 (paper's CR, pixels; ngi/stored_level.h)
    AssetBytes bytes;
    std::string assetFile;  // relative to outDir
    Measured ngi;           // LoD 0, bilinear restore (no SR)
    // Peers at equal bytes (budget = bytes.file).
    Measured equalBytes;  // meshoptimizer + Draco 14-bit, decoded
    size_t dracoBytes = 0;
    bool budgetMet = false;
    bool wholeInputFits = false;
    Measured loop, butterfly;  // subdivision of the decoded simplified mesh
    uint32_t subdivisionIterations = 0;
    // Equal triangle count: the stored level's grid (LoD = level) vs the input simplified.
    Measured ngiGrid;
    Measured simplifiedEqualTriangles;
    bool inputHasFewerTriangles = false;
};

// The peer at one budget and one Draco position precision.
struct PeerAtQp {
    int qp = 0;  // Draco position quantization bits
    size_t dracoBytes = 0;
    bool budgetMet = false;  // false: even the smallest simplification is over the budget
    Measured m;              // the decoded mesh (m.triangles: its triangle count)
};

// Rate-distortion at one byte budget : the asset ngi-bake --target-bytes writes and
// the peer's best precision at the same budget.
struct BudgetRow {
    size_t budget = 0;
    bool ngiFits = false;  // false: below the smallest asset (ngiFailure says which)
    std::string ngiFailure;
    size_t ngiBytes = 0;           // the whole .ngi file (<= budget)
    std::string assetFile;         // relative to outDir
    uint32_t stored = 0;           // stored resolution of the largest chart (cells per side)
    size_t charts = 0;             // charts of the asset (a split for thin parts or one per component)
    uint32_t step = 0;             // position step, 1/65536 of the bounding box
    std::string networkId;         // the network the asset names ("" none)
    double gain = kNaN;            // the largest chart's residual gain (where the network restores it)
    bool networkRestores = false;  // the named network restores the largest chart
    Measured ngiBicubic;           // LoD 0, bicubic restore (ngi-eval mesh --bicubic)
    Measured ngiNetwork;           // LoD 0, the named network with its gains (ngi-eval mesh --sr);
                                   //   = ngiBicubic where no network restores the asset
    std::vector<PeerAtQp> peers;   // qp 10, 12, 14
    int bestPeer = -1;             // index into peers of the smallest CD within budget, -1 none
    bool wholeInputFits = false;   // the best peer is the whole input, unsimplified
};

struct LodRow {
    uint32_t lod = 0;
    uint32_t gridSize = 0;
    Measured m;
};

struct MeshReport {
    std::string name;  // file stem
    std::string path;
    size_t inputVertices = 0, inputTriangles = 0;
    size_t inputDracoBytes = 0;  // the whole input as Draco 14-bit (the peer's ceiling)
    std::vector<BakeRow> bakes;
    bool otOk = false;
    std::string otFailure;
    std::vector<StoredRow> stored;
    uint32_t lodStored = 0;         // the stored resolution of the LoD rows and pictures
    std::vector<LodRow> lods;       // only for the first mesh (the LoD plot)
    std::string budgetBakeFailure;  // the budget bake's error ("" when it baked)
    std::vector<BudgetRow> budgets;
    std::string pictureFile;                // relative to outDir ("" if none)
    std::vector<std::string> pictureTiles;  // tile labels in reading order
    uint32_t pictureColumns = 0;
    std::string pictureFailure;
    // The input coloured by its distance to the LoD 0 of the asset stored at lodStored
    // (ngi/eval/distance_heat_map.h), red at the farthest triangle's distance.
    std::string heatMapFile;     // relative to outDir ("" if none)
    double heatMapFarthest = 0;  // x1e-2 of the size (kHausdorffReportScale)
    std::string heatMapFailure;
};

// Writes plots/*.svg and report.md into options.outDir (atomically). Returns report.md's path.
std::filesystem::path writeReportFiles(const ReportOptions& options, const std::vector<MeshReport>& meshes,
                                       double seconds, const std::string& networkNote);

inline bool finite(double v) { return std::isfinite(v); }

}  // namespace ngi::report_detail
