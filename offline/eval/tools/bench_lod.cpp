// ngi-bench-lod: triangles at equal error (docs/DESIGN.md "Metrics"). For each input mesh and
// its asset, at each object-space bound E: the adaptive surface ngi draws (ngi/adaptive_lod.h,
// as `ngi-eval mesh --max-error E` writes it), its triangle count and its Hausdorff distance
// to the input; the uniform draw that meets the same bound (every chart at the finest level any
// of its tiles needs: one level per chart); and the fewest triangles meshoptimizer's
// simplifier needs for a Hausdorff distance no larger (binary search over target counts), with
// the ratio. Prints a markdown table (and JSON lines with --json).
//
//   ngi-bench-lod MESH=ASSET... [--bounds 0.005,0.01,0.02,0.04] [--samples N] [--restore bicubic|bilinear]
#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/eval/simplify.h"
#include "ngi/eval/surface_distance.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mip_pyramid.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using ngi::UsageError;

constexpr const char* kUsage =
    "usage: ngi-bench-lod MESH=ASSET... [--bounds LIST] [--samples N] [--restore bicubic|bilinear] [--nested-levels] "
    "[--json]\n"
    "  For each input MESH and its baked ASSET and each bound E of LIST (fractions of the\n"
    "  asset's longest side, default 0.005,0.01,0.02,0.04): the adaptive mesh ngi draws\n"
    "  within E of its full restored surface (ngi-eval mesh --max-error E), its triangles and\n"
    "  Hausdorff distance HD to MESH; the triangles of one uniform level per chart meeting E;\n"
    "  and the fewest triangles meshoptimizer's simplifier needs for HD no larger. Distances\n"
    "  on N samples per surface (default 200000, DESIGN.md's metric). The coarse levels are\n"
    "  fitted to the full surface as the engine draws them (ngi/fitted_levels.h);\n"
    "  --nested-levels draws the nested subsamples instead.\n";

struct Row {
    std::string mesh;
    float bound = 0.0f;
    uint64_t ngiTriangles = 0, uniformTriangles = 0, peerTriangles = 0;
    double ngiHd = 0.0, ngiCd = 0.0, peerHd = 0.0, peerCdAtNgiCount = 0.0;
    uint32_t tiles = 0, forced = 0;
};

// The fewest triangles (within a factor 1.03) meshoptimizer needs for HD <= `hd`, and that mesh's HD.
std::pair<uint64_t, double> peerTrianglesFor(const ngi::TriangleMesh& input, double hd,
                                             const ngi::SurfaceDistanceOptions& distance)
{
    uint64_t lo = 4, hi = input.triangles.size();
    double hiHd = 0.0;
    while (hi > uint64_t(double(lo) * 1.03) + 1) {
        const uint64_t mid = uint64_t(std::sqrt(double(lo) * double(hi)));
        ngi::SimplifyOptions options;
        options.targetTriangleCount = uint32_t(mid);
        const ngi::SimplifyResult simplified = ngi::simplifyMesh(input, options);
        const double d =
            simplified.mesh.triangles.empty() ? 1e9 : ngi::surfaceDistance(input, simplified.mesh, distance).hausdorff;
        if (d <= hd) {
            hi = std::max<uint64_t>(simplified.mesh.triangles.size(), lo + 1);
            hiHd = d;
        } else {
            lo = mid;
        }
    }
    return {hi, hiHd};
}

int run(int argc, char** argv)
{
    std::vector<std::pair<std::string, std::string>> pairs;
    std::vector<float> bounds = {0.005f, 0.01f, 0.02f, 0.04f};
    ngi::SurfaceDistanceOptions distance;
    ngi::AssetMeshOptions meshOptions;
    meshOptions.restore = ngi::AssetRestore::Bicubic;
    bool json = false;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        const std::string& a = args.flag();
        if (args.is("--bounds")) {
            bounds.clear();
            const std::string list = args.value();
            for (size_t start = 0; start <= list.size();) {
                const size_t comma = std::min(list.find(',', start), list.size());
                bounds.push_back(ngi::parseFloatOptionInRange(a, list.substr(start, comma - start), 1e-7, 1.0,
                                                              "fractions of the size"));
                start = comma + 1;
            }
        } else if (args.is("--samples")) {
            distance.sampleCount = ngi::parseUintOption(a, args.value());
            if (distance.sampleCount < 1000) throw UsageError("--samples expects at least 1000");
        } else if (args.is("--restore")) {
            const std::string r = args.value();
            if (r == "bicubic")
                meshOptions.restore = ngi::AssetRestore::Bicubic;
            else if (r == "bilinear")
                meshOptions.restore = ngi::AssetRestore::Bilinear;
            else
                throw UsageError("--restore expects bicubic or bilinear, got '" + r + "'");
        } else if (args.is("--json")) {
            json = true;
        } else if (args.is("--nested-levels")) {
            meshOptions.fittedLevels = false;
        } else if (args.is("-h", "--help")) {
            std::fputs(kUsage, stdout);
            return 0;
        } else if (args.positional() && a.find('=') != std::string::npos) {
            const size_t eq = a.find('=');
            pairs.emplace_back(a.substr(0, eq), a.substr(eq + 1));
        } else if (args.positional()) {
            throw UsageError("unexpected argument '" + a + "' (expected MESH=ASSET)");
        } else {
            throw args.unknown();
        }
    }
    if (pairs.empty()) throw UsageError("expects at least one MESH=ASSET");

    std::printf("| mesh | bound | ngi triangles (tiles, forced) | ngi HD x1e-2 | one level per chart | meshoptimizer "
                "triangles at HD <= ngi's | ngi / meshoptimizer | CD x1e-4 at ngi's count: ngi / meshoptimizer |\n"
                "|---|---|---|---|---|---|---|---|\n");
    std::fflush(stdout);
    for (const auto& [meshPath, assetPath] : pairs) {
        const ngi::TriangleMesh input = ngi::readMesh(meshPath);
        const ngi::Asset asset = ngi::readAsset(assetPath);
        const std::string name = std::filesystem::path(meshPath).stem().string();
        // The floor: the full restored image itself (every chart at level 0), whose own distance
        // to the input no bound can go below.
        {
            ngi::AssetMeshOptions full = meshOptions;
            full.lod = 0.0f;
            const ngi::AssetMesh drawn = ngi::assetMesh(asset, full);
            const double hd = ngi::surfaceDistance(input, drawn.mesh, distance).hausdorff;
            const auto [peer, peerHd] = peerTrianglesFor(input, hd, distance);
            std::printf("| %s | full image | %zu | %.3f | %zu | %llu (HD %.3f) | %.2fx | |\n", name.c_str(),
                        drawn.mesh.triangles.size(), 100.0 * hd, drawn.mesh.triangles.size(), (unsigned long long)peer,
                        100.0 * peerHd, double(drawn.mesh.triangles.size()) / double(peer));
            std::fflush(stdout);
        }
        for (float bound : bounds) {
            Row row;
            row.mesh = name;
            row.bound = bound;
            ngi::AssetMeshOptions options = meshOptions;
            ngi::AdaptiveView view;
            view.maxError = bound;
            options.adaptive = view;
            const ngi::AssetMesh drawn = ngi::assetMesh(asset, options);
            row.ngiTriangles = drawn.mesh.triangles.size();
            row.tiles = uint32_t(drawn.adaptive->tiles.size());
            row.forced = drawn.adaptive->forcedSplits;
            std::vector<uint32_t> finest(asset.charts.size(), 99);
            for (const ngi::SelectedTile& t : drawn.adaptive->tiles)
                finest[t.chart] = std::min(finest[t.chart], t.level);
            for (size_t c = 0; c < asset.charts.size(); ++c)
                row.uniformTriangles +=
                    ngi::gridTriangleCount(ngi::mipLevelSize(asset.charts[c].fullSize(), finest[c]));
            const ngi::SurfaceDistance d = ngi::surfaceDistance(input, drawn.mesh, distance);
            row.ngiHd = d.hausdorff;
            row.ngiCd = d.chamfer;
            const auto [peer, peerHd] = peerTrianglesFor(input, row.ngiHd, distance);
            row.peerTriangles = peer;
            row.peerHd = peerHd;
            ngi::SimplifyOptions same;
            same.targetTriangleCount = uint32_t(std::min<uint64_t>(row.ngiTriangles, input.triangles.size()));
            const ngi::SimplifyResult atCount = ngi::simplifyMesh(input, same);
            row.peerCdAtNgiCount = ngi::surfaceDistance(input, atCount.mesh, distance).chamfer;
            std::printf(
                "| %s | %.3g | %llu (%u, %u) | %.3f | %llu | %llu (HD %.3f) | %.2fx | %.4g / %.4g |\n", name.c_str(),
                double(bound), (unsigned long long)row.ngiTriangles, row.tiles, row.forced, 100.0 * row.ngiHd,
                (unsigned long long)row.uniformTriangles, (unsigned long long)row.peerTriangles, 100.0 * row.peerHd,
                double(row.ngiTriangles) / double(row.peerTriangles), 1e4 * row.ngiCd, 1e4 * row.peerCdAtNgiCount);
            if (json)
                std::printf(
                    "{\"mesh\":\"%s\",\"bound\":%g,\"ngi_triangles\":%llu,\"ngi_hd\":%g,\"ngi_cd\":%g,"
                    "\"uniform_triangles\":%llu,\"peer_triangles\":%llu,\"peer_hd\":%g,\"peer_cd_at_ngi_count\":%g}\n",
                    name.c_str(), double(bound), (unsigned long long)row.ngiTriangles, row.ngiHd, row.ngiCd,
                    (unsigned long long)row.uniformTriangles, (unsigned long long)row.peerTriangles, row.peerHd,
                    row.peerCdAtNgiCount);
            std::fflush(stdout);
        }
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    try {
        return run(argc, argv);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "ngi-bench-lod: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bench-lod: %s\n", e.what());
        return 1;
    }
}
