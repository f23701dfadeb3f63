// Test helper: compares the tiles a GpuTileSelection wrote for one job with the CPU's
// selection of the same view (ngi/adaptive_lod.h): the same tiles, morphs within two of
// 32767 steps (the GPU's log may differ from the CPU's in the last bits) and border states.
#pragma once

#include "ngi/adaptive_lod.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/gpu_tile_selection.h"
#include "ngi_shared.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <tuple>
#include <vector>

namespace ngi::test {

constexpr int kMorphTolerance = 2;  // morph steps

using TileKey = std::tuple<uint32_t, uint32_t, uint32_t, uint32_t>;  // chart, level, x, y

// The CPU's drawn tiles of `selection` as the GPU records them: morph, and per border vertex
// whether it is drawn coarser and its morph step.
inline std::map<TileKey, ngi::vk::GpuSelectedTile> cpuRecords(const ngi::vk::AdaptiveSurface& surface,
                                                              const ngi::TileSelection& selection)
{
    std::map<TileKey, ngi::vk::GpuSelectedTile> out;
    constexpr uint32_t P = ngi::kTileQuads;
    for (const ngi::SelectedTile& t : selection.tiles) {
        if (t.culled) continue;
        ngi::vk::GpuSelectedTile r;
        r.chart = t.chart, r.level = t.level, r.x = t.x, r.y = t.y, r.morph = t.morph;
        for (uint32_t b = 0; b < 4 * P; ++b) {
            const uint32_t i0 = b <= P ? b : b <= 2 * P ? P : b <= 3 * P ? 3 * P - b : 0;
            const uint32_t j0 = b <= P ? 0 : b <= 2 * P ? b - P : b <= 3 * P ? P : 4 * P - b;
            const ngi::BorderState s =
                selection.borderState(surface.mates(), t.chart, (t.x * P + i0) << t.level, (t.y * P + j0) << t.level);
            r.border[b] = uint16_t((s.level > t.level ? NGI_TILE_COARSER_BIT : 0u) |
                                   uint32_t(std::lround(s.morph * float(ngi::kMorphSteps))));
        }
        out[{t.chart, t.level, t.x, t.y}] = r;
    }
    return out;
}

// Compares job `job`'s GPU tiles with the CPU's selection; returns the mismatches (each reported).
inline size_t compareJob(const ngi::vk::AdaptiveSurface& surface, const std::vector<ngi::vk::GpuSelectedTile>& gpu,
                         uint32_t job, const ngi::TileSelection& cpu)
{
    const auto expected = cpuRecords(surface, cpu);
    std::map<TileKey, ngi::vk::GpuSelectedTile> got;
    for (const ngi::vk::GpuSelectedTile& t : gpu)
        if (t.instance == job) got[{t.chart, t.level, t.x, t.y}] = t;
    size_t mismatches = 0;
    for (const auto& [key, e] : expected) {
        const auto it = got.find(key);
        if (it == got.end()) {
            ADD_FAILURE() << "job " << job << ": the GPU misses tile level " << e.level << " (" << e.x << ", " << e.y
                          << ") of chart " << e.chart;
            ++mismatches;
            continue;
        }
        const ngi::vk::GpuSelectedTile& g = it->second;
        bool same = std::abs(g.morph - e.morph) <= kMorphTolerance / float(ngi::kMorphSteps);
        for (uint32_t b = 0; b < 4 * ngi::kTileQuads; ++b)
            same = same && (g.border[b] & NGI_TILE_COARSER_BIT) == (e.border[b] & NGI_TILE_COARSER_BIT) &&
                std::abs(int(g.border[b] & 0x7FFF) - int(e.border[b] & 0x7FFF)) <= kMorphTolerance;
        if (!same) {
            ADD_FAILURE() << "job " << job << ": tile level " << e.level << " (" << e.x << ", " << e.y
                          << ") differs in its morph or border states (GPU morph " << g.morph << ", CPU " << e.morph
                          << ")";
            ++mismatches;
        }
    }
    for (const auto& [key, g] : got)
        if (!expected.count(key)) {
            ADD_FAILURE() << "job " << job << ": the GPU draws tile level " << g.level << " (" << g.x << ", " << g.y
                          << ") that the CPU does not";
            ++mismatches;
        }
    return mismatches;
}

}  // namespace ngi::test
