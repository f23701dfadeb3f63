// ngi-bench-select: CPU time of the adaptive selection (ngi/adaptive_lod.h: selectTiles, the
// CDLOD quadtree walk, the balance, the border states and culling) per asset and camera
// distance, on the adaptive surface the engine draws (ngi-eval's CPU mirror: restored
// bicubically, coarse levels fitted, compact levels). Cameras orbit the asset's centre at a
// few distances (multiples of its longest side), looking at it, 1280x720, 60 degrees, within
// a budget of pixels. Prints a markdown table: tiles selected and drawn, triangles drawn,
// forced splits, and milliseconds per selection (the mean and the fastest of the repeats).
//
//   ngi-bench-select ASSET... [--distances 0.3,1,3,10] [--budget PX] [--repeats N] [--views N] [--no-cull]
#include "ngi/adaptive_lod.h"
#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/eval/asset_mesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

namespace {

using ngi::UsageError;

constexpr const char* kUsage =
    "usage: ngi-bench-select ASSET... [--distances LIST] [--budget PX] [--repeats N] [--views N] [--no-cull]\n"
    "  CPU milliseconds per adaptive selection (selectTiles) of each ASSET, for cameras\n"
    "  orbiting its centre at each distance of LIST (multiples of its longest side, default\n"
    "  0.3,1,3,10), N views per distance (default 8) at a budget of PX pixels (default 1),\n"
    "  each selection repeated --repeats times (default 10). --no-cull: no frustum or\n"
    "  backface culling.\n";

std::vector<float> parseList(const std::string& flag, const std::string& list)
{
    std::vector<float> values;
    for (size_t start = 0; start <= list.size();) {
        const size_t comma = std::min(list.find(',', start), list.size());
        values.push_back(
            ngi::parseFloatOptionInRange(flag, list.substr(start, comma - start), 1e-3, 1e4, "multiples of the size"));
        start = comma + 1;
    }
    return values;
}

int run(int argc, char** argv)
{
    std::vector<std::string> assets;
    std::vector<float> distances = {0.3f, 1.0f, 3.0f, 10.0f};
    float budget = 1.0f;
    uint32_t repeats = 10, views = 8;
    bool cull = true;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        if (args.is("--distances"))
            distances = parseList(args.flag(), args.value());
        else if (args.is("--budget"))
            budget = ngi::parseFloatOptionInRange(args.flag(), args.value(), 1e-3, 1e4, "pixels");
        else if (args.is("--repeats"))
            repeats = uint32_t(ngi::parseIntegerOptionInRange(args.flag(), args.value(), 1, 100000));
        else if (args.is("--views"))
            views = uint32_t(ngi::parseIntegerOptionInRange(args.flag(), args.value(), 1, 1000));
        else if (args.is("--no-cull"))
            cull = false;
        else if (args.is("--help", "-h")) {
            std::fputs(kUsage, stdout);
            return 0;
        } else if (args.positional())
            assets.push_back(args.flag());
        else
            throw args.unknown();
    }
    if (assets.empty()) throw UsageError("expects at least one ASSET");

    struct Surface {
        std::string name;
        ngi::AdaptiveAsset adaptive;
        std::vector<ngi::AdaptiveView> views;
    };
    std::vector<Surface> surfaces;
    std::printf(
        "| asset | distance | tiles selected | tiles drawn | triangles drawn | forced splits | ms per selection "
        "(mean) | ms (fastest) |\n|---|---|---|---|---|---|---|---|\n");
    for (const std::string& path : assets) {
        const ngi::Asset asset = ngi::readAsset(path);
        Surface& surface = surfaces.emplace_back();
        surface.adaptive = ngi::buildAdaptiveAsset(asset, ngi::restoreAsset(asset, ngi::AssetRestore::Bicubic));
        const ngi::AdaptiveAsset& adaptive = surface.adaptive;
        const glm::vec3 centre = asset.offset + 0.5f * asset.scale;
        const float size = std::max({asset.scale.x, asset.scale.y, asset.scale.z});
        const std::string name = surface.name = std::filesystem::path(path).filename().string();
        for (const float distance : distances) {
            double tiles = 0, drawn = 0, triangles = 0, forced = 0, totalMs = 0, fastestMs = 1e30;
            for (uint32_t v = 0; v < views; ++v) {
                const float yaw = 2.0f * std::numbers::pi_v<float> * float(v) / float(views);
                const glm::vec3 direction = glm::normalize(glm::vec3(std::cos(yaw), 0.35f, std::sin(yaw)));
                ngi::AdaptiveView view = ngi::assetAdaptiveView(asset, centre + distance * size * direction, centre,
                                                                60.0f, 1280, 720, budget);
                view.cull = cull;
                surface.views.push_back(view);
                for (uint32_t r = 0; r < repeats; ++r) {
                    const auto start = std::chrono::steady_clock::now();
                    const ngi::TileSelection selection = ngi::selectTiles(adaptive.charts, adaptive.mates, view);
                    const double ms =
                        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
                    totalMs += ms;
                    fastestMs = std::min(fastestMs, ms);
                    if (r == 0) {
                        tiles += double(selection.tiles.size());
                        drawn += double(selection.tiles.size() - selection.culledFrustum - selection.culledBackface);
                        triangles += double(selection.triangles);
                        forced += double(selection.forcedSplits);
                    }
                }
            }
            std::printf("| %s | %g | %.0f | %.0f | %.0f | %.1f | %.3f | %.3f |\n", name.c_str(), double(distance),
                        tiles / views, drawn / views, triangles / views, forced / views, totalMs / (views * repeats),
                        fastestMs);
            std::fflush(stdout);
        }
    }
    // Every view of every asset at once, as a host selects its instances and passes each
    // frame: one call per view against selectTilesInParallel over the machine's cores.
    std::vector<ngi::SelectionRequest> requests;
    for (const Surface& s : surfaces)
        for (const ngi::AdaptiveView& v : s.views) requests.push_back({&s.adaptive.charts, &s.adaptive.mates, v});
    double oneByOne = 1e30, parallel = 1e30;
    for (uint32_t r = 0; r < repeats; ++r) {
        auto start = std::chrono::steady_clock::now();
        for (const ngi::SelectionRequest& q : requests) (void)ngi::selectTiles(*q.charts, *q.mates, q.view);
        auto end = std::chrono::steady_clock::now();
        oneByOne = std::min(oneByOne, std::chrono::duration<double, std::milli>(end - start).count());
        start = std::chrono::steady_clock::now();
        (void)ngi::selectTilesInParallel(requests);
        end = std::chrono::steady_clock::now();
        parallel = std::min(parallel, std::chrono::duration<double, std::milli>(end - start).count());
    }
    std::printf("\n| %zu views at once | ms, one call per view | ms, selectTilesInParallel (%u threads) | ratio |\n"
                "|---|---|---|---|\n| fastest of %u | %.2f | %.2f | %.2fx |\n",
                requests.size(), std::max(1u, std::thread::hardware_concurrency()), repeats, oneByOne, parallel,
                oneByOne / parallel);
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    try {
        return run(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "ngi-bench-select: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bench-select: %s\n", e.what());
        return 1;
    }
}
