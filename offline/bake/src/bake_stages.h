// ngi offline: the stages of the bake as bakeMesh (bake.cpp) runs them, and the state they
// hand on. Private to ngi_bake; the public contract is ngi/bake/bake.h.
//   bake.cpp        repair -> connected components (stage 2), then the order below
//   bake_split.cpp  components split into matched charts (BakeOptions::splitPieces, and
//                   the hand-over of BakeOptions::splitThinParts)
//   bake_chart.cpp  one chart per component: remesh -> cut -> flow -> OT -> sample (3-7)
//   bake_appearance.cpp  each chart's base colour over its square (after 7, with BakeOptions::appearance)
//   bake_store.cpp  the charts ordered, normalized and stored into the asset (8)
#pragma once

#include "ngi/bake/bake.h"
#include "ngi/error.h"
#include "ngi/param/rasterize.h"
#include "ngi/seam.h"
#include "ngi/stopwatch.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace ngi::detail {

// printf into a string (report lines and errors), whole; the compiler checks the arguments
// against the format.
[[gnu::format(printf, 1, 2)]] inline std::string format(const char* fmt, ...)
{
    va_list args, again;
    va_start(args, fmt);
    va_copy(again, args);
    const int length = std::vsnprintf(nullptr, 0, fmt, args);
    va_end(args);
    std::string text(size_t(std::max(length, 0)), '\0');
    std::vsnprintf(text.data(), text.size() + 1, fmt, again);
    va_end(again);
    return text;
}

// The wall time of the stage runStage finished last on this thread (announce passes it on).
inline thread_local double lastStageSeconds = 0.0;

// Runs one stage: times it, adds its time to the report (summed over charts), and prefixes
// errors with the source and stage.
template <typename Function>
auto runStage(const char* stage, const BakeOptions& options, BakeReport& report, Function&& function)
{
    const StopwatchClock::time_point start = StopwatchClock::now();
    try {
        auto result = function();
        const double seconds = secondsSince(start);
        auto same = std::find_if(report.stages.begin(), report.stages.end(),
                                 [&](const StageTime& s) { return s.stage == stage; });
        if (same == report.stages.end())
            report.stages.push_back({stage, seconds});
        else
            same->seconds += seconds;
        lastStageSeconds = seconds;
        return result;
    } catch (const Error& e) {
        const std::string message = e.what();
        if (message.rfind(options.sourceName + ":", 0) == 0) throw;  // already names the file
        throw Error(options.sourceName + ": " + stage + ": " + message);
    }
}

// Passes a finished stage's summary to BakeOptions::stageDone (with lastStageSeconds).
inline void announce(const BakeOptions& options, const char* stage, const std::string& summary)
{
    if (options.stageDone) options.stageDone(stage, lastStageSeconds, summary);
}

// The 3D area of `mesh` (sum of its triangles' areas).
double surfaceArea(const TriangleMesh& mesh);

// The connected components of the repaired input (stage 2), each with its area. `totalArea`
// stays the whole surface's when components leave `parts` for a split group, so that a
// component's share is always of the whole.
struct Components {
    std::vector<TriangleMesh> parts;
    std::vector<double> areas;  // parallel to parts
    double totalArea = 0.0;
    // The cleaned input's bounding box centre, subtracted from every part (double precision):
    // the later stages' floats (geometry images) hold the shape near the origin, not at the
    // input's coordinates, which may lie far from it (survey, CAD). The asset's offset adds it back.
    glm::dvec3 centre{0.0};

    // The share of the surface's area in parts[c] (1 for a surface of no area).
    double shareOf(size_t c) const { return totalArea > 0.0 ? areas[c] / totalArea : 1.0; }
    // round(perWhole x shareOf(c)): the pieces parts[c] gets when the whole would get perWhole.
    uint32_t piecesFor(size_t c, uint32_t perWhole) const { return uint32_t(std::lround(perWhole * shareOf(c))); }
};

// A chart's base colour image (bakeAppearance): 8-bit sRGB RGBA over level `level` of its
// full image.
struct BakedColor {
    uint32_t level = 0;
    std::vector<uint8_t> rgba;  // empty: no colour
};

// What the chart stages add besides BakeResult::charts and BakeReport::charts (the three
// stay parallel, in the order the charts are baked).
struct BakedCharts {
    glm::dvec3 centre{0.0};                       // Components::centre (stage 8 adds it back)
    std::vector<RasterizedGeometryImage> images;  // each chart's full-resolution images, welded
    std::vector<CrossSeamSegment> crossSeams;     // curves shared by charts of a split group (chart indices)
    int splitGroups = 0;                          // split components so far (ChartReport::splitGroup)
    std::vector<BakedColor> baseColors;           // per chart after bakeAppearance (empty: none)
};

// A component handed over by its one-chart bake to the split: why (for the report), its
// genus and its coarse remesh where one was made.
struct HandOver {
    size_t part = 0;
    std::string reason;
    long genus = 0;
    std::optional<RemeshResult> remesh;
    // The one-chart map failed its checks, or the genus is above what one chart is tried for:
    // where the split is abandoned, the part takes the last resort at once.
    bool oneChartFails = false;
};

// Stages 3-7 for components.parts[c] as one chart (bake_chart.cpp): remesh, cut to a disk,
// conformal start and optimal transport to the square, matched border, rasterize with the
// detail transfer and the image checks. Appends one entry to result.report.charts,
// result.charts and baked.images and returns true. With `handOvers` (BakeOptions::
// splitThinParts and the adaptive remesh), a part found to have thin parts or too high a genus,
// or whose one-chart map fails its checks (flips, sampling, image: a warning names the check),
// is appended to *handOvers instead, nothing else is left appended, and false is returned.
// Throws ngi::Error "SOURCE: [chart i/n: ]stage: problem" where the chart is refused (without
// `handOvers`, or where the failure comes before the map).
bool bakeComponentAsOneChart(const Components& components, size_t c, uint32_t storedLevel, const BakeOptions& options,
                             BakeResult& result, BakedCharts& baked, std::vector<HandOver>* handOvers);

// bakeComponentAsOneChart's last resort for components.parts[c] at once, without the regular
// attempts: for a part whose one-chart map already failed its checks and whose split was
// abandoned, where the regular map would only fail again (at the cost of its cut search).
// `why` is what failed before, for the warning. Throws ngi::Error where even this fails.
void bakeComponentWithLastResort(const Components& components, size_t c, uint32_t storedLevel,
                                 const BakeOptions& options, BakeResult& result, BakedCharts& baked,
                                 const std::string& why);

// BakeOptions::splitPieces > 1 (bake_split.cpp): every component whose share gives at least
// two pieces is split into matched charts and appended as a group; the components left (too
// small, or whose split could not be matched: a warning) stay in `components` for one chart
// each, their areas with them.
void splitEveryComponent(Components& components, uint32_t storedLevel, const BakeOptions& options, BakeResult& result,
                         BakedCharts& baked);

// BakeOptions::splitThinParts (bake_split.cpp): each handed-over component is split into
// matched charts (at least genus / 2 pieces, capped so the asset holds at most kMaxCharts
// charts) and appended as a group; where its borders cannot be matched (a warning) it is
// baked as one chart after all, without a hand-over. Consumes the hand-overs' remeshes.
void splitHandedOver(std::vector<HandOver>& handedOver, const Components& components, uint32_t storedLevel,
                     const BakeOptions& options, BakeResult& result, BakedCharts& baked);

// Reorders the charts largest resolution first, stably (bake_store.cpp): BakeReport::charts,
// BakeResult::charts and baked.images together, the cross-chart seams renumbered (chartA <
// chartB) and moved into result.crossSeams.
void orderChartsByResolution(BakeResult& result, BakedCharts& baked);

// The level of a chart's full image (resolution cells per side) whose grid its colour image
// samples: the coarsest with at least as many samples per side as the colour needs,
// sqrt(samplesPerArea x the chart's area), and at least 256 (or the full image); the 2 x 2
// level for a colour that does not vary (samplesPerArea 0).
uint32_t colorLevelFor(uint32_t resolution, double areaShare, double samplesPerArea, double totalArea);

// The appearance stage (bake_appearance.cpp): with BakeOptions::appearance, each chart's base
// colour image from the input's textures, vertex colours and materials (SurfaceColor), at
// colorLevelFor's level, seam mates one colour; into baked.baseColors, ChartReport::colorLevel
// and BakeReport::colorSamplesPerArea. Charts in their final order (after orderChartsByResolution),
// positions still relative to baked.centre (before storeAsset; `input` is in its own coordinates).
// Nothing without appearance.
void bakeAppearance(const TriangleMesh& input, const BakeOptions& options, BakeResult& result, BakedCharts& baked);

// Stage 8 (bake_store.cpp): one normalization for every chart's images (normalizationFor,
// baked.centre put back: the asset's object space is the input's coordinates; a warning where
// a float consumer would round them coarser than the stored positions' 16-bit steps), each
// chart's full images kept in result.charts in the asset's frame, its nested level
// `storedLevel` stored, the cross-chart seams and the bake report (BakeReport::totalSeconds
// from `bakeStart`) written into result.asset. Consumes baked.images.
void storeAsset(uint32_t storedLevel, const BakeOptions& options, StopwatchClock::time_point bakeStart,
                BakeResult& result, BakedCharts& baked);

}  // namespace ngi::detail
