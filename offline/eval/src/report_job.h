// ngi offline eval, report internals: what the stages of one mesh's report share (its
// options, input, progress and the one CD/HD measurement), and the stages that live in files
// of their own. report.cpp runs the stages in order; report_budgets.cpp is the budget rows.
#pragma once

#include "report_data.h"

#include "ngi/mesh/triangle_mesh.h"
#include "ngi/network_catalog.h"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <mutex>
#include <span>
#include <string>

namespace ngi::report_detail {

inline constexpr double kBakeUnits = 6.0;  // a bake costs about as much as six measurements

// Serializes progress callbacks from worker threads.
class ProgressSink {
public:
    ProgressSink(const ReportOptions& options, double total) : options_(options), total_(total) {}
    void advance(double units, const std::string& step)
    {
        std::lock_guard lock(mutex_);
        done_ = std::min(total_, done_ + units);
        if (options_.progress) options_.progress({done_, total_, step});
    }

private:
    const ReportOptions& options_;
    double total_;
    double done_ = 0.0;
    std::mutex mutex_;
};

// `text` on one line of a Markdown table: newlines and '|' become spaces.
std::string oneLine(std::string text);

// One mesh of the report: its options, its input and what has been measured of it so far.
struct MeshContext {
    const ReportOptions& options;
    ProgressSink& progress;
    const TriangleMesh& input;
    uint64_t sourceHash = 0;
    unsigned distanceThreads = 1;
    MeshReport report;

    // CD/HD of `candidate` against the input (docs/DESIGN.md "Metrics", options.sampleCount
    // samples), or the failure; advances the progress by one unit named `step`.
    Measured measure(const TriangleMesh& candidate, const std::string& step);
    // outDir/assets/NAME.METHOD.SUFFIX: where this mesh's assets are written.
    std::filesystem::path assetPath(const std::string& method, const std::string& suffix) const;
};

// The rate-distortion rows (report_budgets.cpp): one bake with ngi-bake's options, then per
// options.budgets the asset ngi-bake --target-bytes writes (naming one of `shipped`) and the
// peer at each Draco precision, measured, into mesh.report.budgets. A failure is a row's
// reason, not an error.
void measureBudgetRows(MeshContext& mesh, std::span<const ShippedNetwork> shipped);

}  // namespace ngi::report_detail
