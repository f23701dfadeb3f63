// ngi-eval: measures how good a surface is (DESIGN.md "Metrics"), for people and scripts.
//
//   ngi-eval mesh ASSET (--lod F | --grid N) [--no-sr | --bicubic | --sr [--weights NET.ngiw]] -o OUT.{obj,off,ply,glb,gltf}
//   ngi-eval distance REFERENCE CANDIDATE [--json[=PATH]] [--samples N] [--seed S] [--threads T] [--no-colour]
//   ngi-eval report --meshes DIR_OR_LIST --out DIR [--resolution R] [--stored LIST] [--params LIST]
//                   [--jobs N] [--reuse] [--samples N] [--weights NET.ngiw] [--note TEXT]
//                   [--budgets LIST] [--networks DIR]
//
// mesh: writes the triangle mesh the renderer draws for ASSET, in original coordinates (as
// glTF with its normals, chart uvs and base colour textures). distance: prints CD (x1e-4) and
// HD (x1e-2) of CANDIDATE against REFERENCE, both in the reference's frame, and the colour
// PSNR of Y, Cb, Cr when both have appearance (colour_distance.h). report: bakes (or reuses) assets and writes DIR/report.md with the
// paper's tables, peers at equal bytes, SVG plots and contact sheets. Errors: one line "ngi-eval: message" on stderr, exit 1; usage errors exit 2.
// Output files (mesh -o, distance --json=PATH) are checked before the work (directory exists,
// not a directory, not an input, a mesh format writeMesh writes) and replace an existing file
// only once complete (ngi/output_files.h).
#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/eval/asset_appearance.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/eval/colour_distance.h"
#include "ngi/eval/gltf_export.h"
#include "ngi/eval/open_edges.h"
#include "ngi/eval/surface_distance.h"
#ifdef NGI_EVAL_HAS_REPORT
#include "ngi/eval/report.h"
#endif
#include "ngi/mesh/mesh_io.h"
#include "ngi/network_catalog.h"
#include "ngi/output_files.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <optional>
#include <unistd.h>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage =
    "usage: ngi-eval mesh ASSET (--lod F | --grid N | --max-error E | --eye X,Y,Z --look-at X,Y,Z --max-error-px P "
    "[--fov DEG] [--size WxH]) [--no-sr | --bicubic | --sr [--weights NET.ngiw] [--networks DIR]]\n"
    "                -o OUT.{obj,off,ply,glb,gltf}\n"
    "       ngi-eval watertight ASSET [--no-sr | --bicubic | --sr [--weights NET.ngiw] [--networks DIR]]\n"
    "       ngi-eval distance REFERENCE CANDIDATE [options]\n"
    "       ngi-eval report --meshes DIR_OR_LIST --out DIR [options]\n"
    "\n"
    "mesh: the triangle mesh the renderer draws for ASSET (.ngi) at continuous LoD F\n"
    "  (0 = full resolution .. levels - 1) or on a fixed N x N grid, in the input mesh's\n"
    "  original coordinates. --no-sr restores the full image by bilinear upsampling of\n"
    "  the stored level (as ngi-render --no-sr); --bicubic by bicubic\n"
    "  upsampling (a comparison baseline); --sr by the super-resolution network (its C++\n"
    "  reference forward, which the engine's GLSL matches): --weights NET.ngiw, else the\n"
    "  asset's own WGHT chunk, else the shipped network the asset names (in --networks DIR,\n"
    "  else $NGI_NETWORK_DIR, else the assets/ beside the executable). Charts the network's\n"
    "  factor does not restore are restored bicubically (said on stdout). Default (none of\n"
    "  the three): --sr when the asset carries weights or the network it names is found and\n"
    "  restores it, else (a warning when it names one) --bicubic: what ngi-render draws.\n"
    "  Adaptive LoD (each 8x8-quad tile of each chart at its own level, crack-free):\n"
    "  --max-error E draws every tile at the coarsest level within E (a fraction of the\n"
    "  asset's longest side, (0, 1]) of the full restored surface; a camera (--eye and\n"
    "  --look-at in the input's coordinates, --fov DEG default 45, --size WxH default\n"
    "  1280x720) draws each tile within --max-error-px P pixels, near tiles finer, far and\n"
    "  flat ones coarser, geomorphed. The whole surface is written (tiles outside the view\n"
    "  too); stdout says how many the renderer would cull. OUT.glb (binary) or OUT.gltf\n"
    "  (embedded) is glTF 2.0 with normals, each vertex's chart uv as TEXCOORD_0 and one\n"
    "  material per coloured chart whose base colour texture is the chart's image (PNG).\n"
    "\n"
    "watertight: for every LoD 0, 0.5, 1, ... to the coarsest drawn level, and for the adaptive\n"
    "  surface within 0.2%, 0.5%, 1%, 2%, 5% and 20% of the size, the mesh of 'mesh'\n"
    "  with vertices welded within 1e-6 of the bounding box's longest side: its open edges\n"
    "  (0 for a closed input with matched seams; else the input's own boundary loops) and the\n"
    "  widest gap between open edges (% of the longest side).\n"
    "\n"
    "distance:\n"
    "  Chamfer (CD, x1e-4) and Hausdorff (HD, x1e-2) distance of CANDIDATE against\n"
    "  REFERENCE, as DESIGN.md \"Metrics\" defines them: both meshes centred on the\n"
    "  reference's bounding-box centre and scaled so its longest side is 1; point-to-surface\n"
    "  distances (CGAL AABB tree) from area-uniform samples on each surface.\n"
    "  Colour, when both meshes have appearance (textures, vertex colours or materials):\n"
    "  PSNR of Y, Cb, Cr (BT.709, 8-bit sRGB, full range; inf for identical colours) of the\n"
    "  base colour at the reference's samples against the candidate's at its closest\n"
    "  surface point. A mesh whose appearance does not read is measured without colour\n"
    "  (said on stderr).\n"
    "  Meshes: OBJ, OFF, PLY, STL, glTF (.gltf/.glb).\n"
    "\n"
    "distance options:\n"
    "  --json         print JSON on stdout instead of text\n"
    "  --json=PATH    also write the JSON to PATH\n"
    "  --samples N    samples per surface (default 200000, the DESIGN.md value)\n"
    "  --seed S       sampling seed (default: the fixed DESIGN.md seed)\n"
    "  --threads T    threads for the closest-point queries (default 2)\n"
    "  --no-colour    read geometry only: no colour PSNR\n"
    "\n"
    "report: bakes every mesh (DIR: all mesh files in it; or a comma-separated list of files)\n"
    "  with each parameterization and writes DIR/report.md: Table 1 (CD/HD of each map's\n"
    "  full image), Table 4 (OT stored at each resolution, restored without SR), peers at\n"
    "  equal bytes (meshoptimizer + Draco 14-bit, Loop, Butterfly) and at equal triangle\n"
    "  count, SVG plots (DIR/plots) and contact sheets (DIR/pictures). A failed bake is a\n"
    "  reported row, not an error. Progress with ETA on stderr.\n"
    "report options:\n"
    "  --resolution R       full geometry image (default 1024)\n"
    "  --stored LIST        stored resolutions (default 32,64,128,256,512)\n"
    "  --params LIST        parameterizations (default tutte,harmonic,ricci,authalic,ot)\n"
    "  --jobs N             meshes processed at once (default 1)\n"
    "  --reuse              reuse DIR/assets from an earlier run (and its recorded failures)\n"
    "  --samples N          samples per surface (default 200000)\n"
    "  --picture-size N     contact-sheet tile side in pixels (default 200)\n"
    "  --weights NET.ngiw   the trained SR network, if any (its bytes are reported)\n"
    "  --note TEXT          a note quoted in the report (e.g. why this resolution)\n"
    "  --budgets LIST       byte budgets of the rate-distortion curves: ngi-bake --target-bytes N\n"
    "                       against meshopt+Draco's best qp 10/12/14 (default\n"
    "                       4096,8192,16384,32768,65536; 'none': no curves)\n"
    "  --networks DIR       the shipped networks the budget assets may name (default: ngi-bake's)\n";

using ngi::UsageError;  // core/include/ngi/command_line.h, shared by every tool

std::string hex(uint64_t v)
{
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "0x%016llx", static_cast<unsigned long long>(v));
    return buffer;
}

int distanceCommand(const std::vector<std::string>& args)
{
    std::vector<std::string> paths;
    bool jsonToStdout = false;
    std::optional<std::string> jsonPath;
    ngi::SurfaceDistanceOptions options;
    bool withColour = true;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(a + " expects a value");
            return args[++i];
        };
        if (a == "--json")
            jsonToStdout = true;
        else if (a == "--json=")
            throw UsageError("--json=: the output path is empty");
        else if (a.rfind("--json=", 0) == 0)
            jsonPath = a.substr(7);
        else if (a == "--samples")
            options.sampleCount = uint32_t(ngi::parseIntegerOptionInRange(a, value(), 0, 100000000));
        else if (a == "--seed")
            options.seed = ngi::parseIntegerOptionInRange(a, value(), 0, UINT64_MAX);
        else if (a == "--threads")
            options.threadCount = unsigned(ngi::parseIntegerOptionInRange(a, value(), 0, 256));
        else if (a == "--no-colour")
            withColour = false;
        else if (a.size() > 1 && a[0] == '-')
            throw UsageError("unknown option '" + a + "'");
        else
            paths.push_back(a);
    }
    if (paths.size() != 2)
        throw UsageError("distance expects REFERENCE and CANDIDATE, got " + std::to_string(paths.size()) + " path(s)");
    if (options.sampleCount == 0) throw UsageError("--samples must be at least 1");
    if (jsonPath && jsonPath->empty()) throw UsageError("--json= expects a path");

    ngi::OutputFiles outputs(jsonPath ? std::vector<fs::path>{*jsonPath} : std::vector<fs::path>{},
                             {paths[0], paths[1]});
    // With appearance where it reads; a texture that does not read costs the colour, not CD/HD.
    std::string noColour = withColour ? "" : "--no-colour";
    auto read = [&](const std::string& path, ngi::MeshAppearance& appearance) {
        if (!withColour) return ngi::readMesh(path);
        std::string why;
        try {
            return ngi::readMesh(path, appearance);
        } catch (const ngi::Error& e) {
            why = e.what();
            appearance = {};
        }
        ngi::TriangleMesh mesh = ngi::readMesh(path);  // a geometry error is the command's error
        std::fprintf(stderr, "ngi-eval: warning: colour not measured: %s\n", why.c_str());
        noColour = why;
        return mesh;
    };
    ngi::MeshAppearance referenceLook, candidateLook;
    const ngi::TriangleMesh reference = read(paths[0], referenceLook);
    const ngi::TriangleMesh candidate = read(paths[1], candidateLook);
    if (noColour.empty() && (referenceLook.empty() || candidateLook.empty()))
        noColour = paths[referenceLook.empty() ? 0 : 1] + " has no appearance";
    const auto start = std::chrono::steady_clock::now();
    const ngi::SurfaceDistance r = ngi::surfaceDistance(reference, candidate, options);
    std::optional<ngi::ColourDistance> colour;
    if (noColour.empty())
        colour = ngi::colourDistance(reference, referenceLook, candidate, candidateLook,
                                     {options.sampleCount, options.seed, options.threadCount});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const double cd = r.chamfer * ngi::kChamferReportScale;
    const double hd = r.hausdorff * ngi::kHausdorffReportScale;
    nlohmann::json j;
    j["reference"] = {
        {"path", paths[0]}, {"vertices", reference.positions.size()}, {"triangles", reference.triangles.size()}};
    j["candidate"] = {
        {"path", paths[1]}, {"vertices", candidate.positions.size()}, {"triangles", candidate.triangles.size()}};
    j["frame"] = {{"centre", {r.frame.centre.x, r.frame.centre.y, r.frame.centre.z}}, {"scale", r.frame.scale}};
    j["samples_per_surface"] = r.sampleCount;
    j["seed"] = options.seed;
    j["chamfer_x1e-4"] = cd;
    j["hausdorff_x1e-2"] = hd;
    j["chamfer"] = r.chamfer;
    j["hausdorff"] = r.hausdorff;
    j["mean_squared_reference_to_candidate"] = r.meanSquaredReferenceToCandidate;
    j["mean_squared_candidate_to_reference"] = r.meanSquaredCandidateToReference;
    j["max_reference_to_candidate"] = r.maxReferenceToCandidate;
    j["max_candidate_to_reference"] = r.maxCandidateToReference;
    j["p99_reference_to_candidate"] = r.p99ReferenceToCandidate;
    j["p99_candidate_to_reference"] = r.p99CandidateToReference;
    const glm::dvec3 fa = r.farthestReferenceSample, fb = r.farthestCandidateSample;
    j["farthest_reference_sample"] = {fa.x, fa.y, fa.z};
    j["farthest_candidate_sample"] = {fb.x, fb.y, fb.z};
    if (colour) {
        // JSON has no infinity: an infinite PSNR (identical colours) is the string "inf".
        auto db = [](double v) { return std::isinf(v) ? nlohmann::json("inf") : nlohmann::json(v); };
        j["colour"] = {{"psnr_y", db(colour->psnrY)},
                       {"psnr_cb", db(colour->psnrCb)},
                       {"psnr_cr", db(colour->psnrCr)},
                       {"mse_y", colour->mseY},
                       {"mse_cb", colour->mseCb},
                       {"mse_cr", colour->mseCr},
                       {"footprint", colour->footprint},
                       {"samples", colour->sampleCount},
                       {"definition",
                        "colour_distance.h: base colour at reference samples against the candidate's "
                        "closest point, 8-bit sRGB, BT.709 YCbCr full range, PSNR = 10 log10(255^2/MSE)"}};
    } else {
        j["colour"] = nullptr;
        j["colour_not_measured"] = noColour;
    }
    j["seconds"] = seconds;
    j["definition"] = "DESIGN.md Metrics: reference frame (bbox centre, longest side 1), "
                      "point-to-surface, CD = mean d(a,B)^2 + mean d(b,A)^2, HD = max";
    const std::string text = j.dump(2) + "\n";
    if (jsonPath) {
        outputs.write(*jsonPath, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
        outputs.commit();
    }
    if (jsonToStdout) {
        std::cout << text;
        return 0;
    }
    std::printf("reference  %s  (%zu vertices, %zu triangles)\n", paths[0].c_str(), reference.positions.size(),
                reference.triangles.size());
    std::printf("candidate  %s  (%zu vertices, %zu triangles)\n", paths[1].c_str(), candidate.positions.size(),
                candidate.triangles.size());
    std::printf("frame      reference bbox centre (%.6g, %.6g, %.6g), longest side %.6g -> 1\n", r.frame.centre.x,
                r.frame.centre.y, r.frame.centre.z, 1.0 / r.frame.scale);
    std::printf("samples    %u per surface, seed %s, point-to-surface (AABB tree)\n", r.sampleCount,
                hex(options.seed).c_str());
    std::printf("CD = %.4f x1e-4   (mean d(ref,cand)^2 %.4f + mean d(cand,ref)^2 %.4f, x1e-4)\n", cd,
                r.meanSquaredReferenceToCandidate * ngi::kChamferReportScale,
                r.meanSquaredCandidateToReference * ngi::kChamferReportScale);
    std::printf("HD = %.4f x1e-2   (max d(ref,cand) %.4f, max d(cand,ref) %.4f, x1e-2)\n", hd,
                r.maxReferenceToCandidate * ngi::kHausdorffReportScale,
                r.maxCandidateToReference * ngi::kHausdorffReportScale);
    std::printf("99th pct   d(ref,cand) %.4f, d(cand,ref) %.4f, x1e-2\n",
                r.p99ReferenceToCandidate * ngi::kHausdorffReportScale,
                r.p99CandidateToReference * ngi::kHausdorffReportScale);
    std::printf("farthest   reference sample at (%.6g, %.6g, %.6g), candidate sample at (%.6g, %.6g, %.6g)"
                " (input coordinates)\n",
                fa.x, fa.y, fa.z, fb.x, fb.y, fb.z);
    if (colour)
        std::printf("colour     PSNR Y %.2f dB, Cb %.2f dB, Cr %.2f dB   (BT.709 8-bit, reference samples against the "
                    "candidate's closest points, footprint %.4g)\n",
                    colour->psnrY, colour->psnrCb, colour->psnrCr, colour->footprint);
    else
        std::printf("colour     not measured (%s)\n", noColour.c_str());
    std::printf("time       %.2f s (sampling + trees + queries, %u thread%s)\n", seconds, options.threadCount,
                options.threadCount == 1 ? "" : "s");
    return 0;
}

float parseFloat(const std::string& option, const std::string& text)
{
    return ngi::parseFloatOption(option, text);  // rejects text, nan, inf and 1e999
}

// The network --sr restores with (ngi/network_catalog.h): --weights, the asset's WGHT chunk
// (restoreFullResolution parses it), or the shipped network the asset names. Prints which, a
// warning when --weights overrides the asset's network, and the charts left to bicubic.
// With no restore option given (`restoreGiven` false): the network the asset carries or names
// when it is found and restores it (defaultRestoreNetwork), else bicubic as ngi-render's
// default, with a warning when the asset names a network that is not found.
void chooseNetwork(const std::string& assetPath, const ngi::Asset& asset, const std::optional<std::string>& weightsPath,
                   const std::optional<std::string>& networks, ngi::NetworkWeights& network,
                   ngi::AssetMeshOptions& options, bool restoreGiven)
{
    // Network files that do not read are skipped (the asset's own network may be beside them).
    std::vector<std::string> skipped;
    auto warnSkipped = [&] {
        for (const std::string& file : skipped)
            std::fprintf(stderr, "ngi-eval: warning: skipped a network file that does not read: %s\n", file.c_str());
    };
    if (!restoreGiven) {
        std::string why;
        std::optional<ngi::NetworkWeights> found;
        try {
            found = ngi::defaultRestoreNetwork(asset, ngi::networkSearchPath(networks.value_or("")), why, skipped);
        } catch (const ngi::Error& e) {
            throw ngi::Error(assetPath + ": " + e.what());
        }
        warnSkipped();
        if (!found) {
            if (!asset.networkId.empty())
                std::fprintf(stderr,
                             "ngi-eval: warning: %s: %s: restoring without it (bicubic; --sr makes this an error)\n",
                             assetPath.c_str(), why.c_str());
            options.restore = ngi::AssetRestore::Bicubic;
            return;
        }
        network = std::move(*found);
        options.restore = ngi::AssetRestore::Network;
        options.network = &network;
        std::printf("super-resolution: network %s (x%u)\n", ngi::networkLabel(network).c_str(), network.scaleFactor);
        for (size_t c = 0; c < asset.charts.size(); ++c)
            if (!ngi::networkRestoresChart(network, asset.charts[c]))
                std::printf("super-resolution: chart %zu (x%u) is not restored by the x%u network: bicubic\n", c,
                            1u << asset.charts[c].storedLevel, network.scaleFactor);
        return;
    }
    if (options.restore != ngi::AssetRestore::Network) return;
    if (weightsPath || asset.weights.empty()) {
        std::string warning;
        try {
            network = ngi::networkForRestore(asset, weightsPath.value_or(""),
                                             ngi::networkSearchPath(networks.value_or("")), warning, skipped);
        } catch (const ngi::Error& e) {
            // The weights file's own errors name it; the others name the asset.
            if (weightsPath) throw;
            throw ngi::Error(assetPath + ": " + e.what());
        }
        warnSkipped();
        if (!warning.empty())
            std::fprintf(stderr, "ngi-eval: warning: %s: %s (--weights overrides it)\n", assetPath.c_str(),
                         warning.c_str());
        options.network = &network;
        std::printf("super-resolution: network %s (x%u)\n", ngi::networkLabel(network).c_str(), network.scaleFactor);
        bool any = false;
        for (const ngi::AssetChart& c : asset.charts) any |= ngi::networkRestoresChart(network, c);
        for (size_t c = 0; c < asset.charts.size() && any; ++c)
            if (!ngi::networkRestoresChart(network, asset.charts[c]))
                std::printf("super-resolution: chart %zu (x%u) is not restored by the x%u network: bicubic\n", c,
                            1u << asset.charts[c].storedLevel, network.scaleFactor);
    }
}

int watertightCommand(const std::vector<std::string>& args)
{
    std::vector<std::string> paths;
    std::optional<std::string> weightsPath, networks;
    ngi::AssetMeshOptions options;
    bool restoreGiven = false;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "--sr")
            options.restore = ngi::AssetRestore::Network, restoreGiven = true;
        else if (a == "--no-sr")
            options.restore = ngi::AssetRestore::Bilinear, restoreGiven = true;
        else if (a == "--bicubic")
            options.restore = ngi::AssetRestore::Bicubic, restoreGiven = true;
        else if (a == "--weights" || a == "--networks") {
            if (i + 1 >= args.size()) throw UsageError(a + " expects a value");
            (a == "--weights" ? weightsPath : networks) = args[++i];
        } else if (a.size() > 1 && a[0] == '-')
            throw UsageError("unknown option '" + a + "'");
        else
            paths.push_back(a);
    }
    if (paths.size() != 1)
        throw UsageError("watertight expects one ASSET, got " + std::to_string(paths.size()) + " path(s)");
    if (weightsPath && !(restoreGiven && options.restore == ngi::AssetRestore::Network))
        throw UsageError("--weights needs --sr");
    if (networks && restoreGiven && options.restore != ngi::AssetRestore::Network)
        throw UsageError("--networks needs --sr (or no restore option: the default looks there)");
    const ngi::Asset asset = ngi::readAsset(paths[0]);
    ngi::NetworkWeights network;
    chooseNetwork(paths[0], asset, weightsPath, networks, network, options, restoreGiven);
    const float side = std::max({asset.scale.x, asset.scale.y, asset.scale.z});
    const uint32_t coarsest = asset.charts.front().coarsestDrawnLevel();
    std::printf("%s: %zu chart(s), seams %s, coarsest drawn level %u\n", paths[0].c_str(), asset.charts.size(),
                asset.charts.front().seams.matched ? "matched" : "not matched", coarsest);
    std::printf("| LoD | triangles | open edges | largest gap (%% of size) |\n|---|---|---|---|\n");
    auto row = [&](const std::string& label) {
        ngi::AssetMesh drawn;
        try {
            drawn = ngi::assetMesh(asset, options);
        } catch (const ngi::Error& e) {
            throw ngi::Error(paths[0] + ": " + e.what());
        }
        const ngi::OpenEdgeReport r = ngi::measureOpenEdges(drawn.mesh, 1e-6 * double(side));
        std::printf("| %s | %zu | %zu | %.4f |\n", label.c_str(), drawn.mesh.triangles.size(), r.openEdges,
                    100.0 * r.largestGap / double(side));
    };
    char label[64];
    for (float lod = 0.0f; lod <= float(coarsest) + 1e-3f; lod += 0.5f) {
        options.lod = lod;
        std::snprintf(label, sizeof label, "%.1f", double(lod));
        row(label);
    }
    // The adaptive surface (every tile at its own level) at uniform bounds, as ngi-eval mesh
    // --max-error writes it.
    for (float bound : {0.002f, 0.005f, 0.01f, 0.02f, 0.05f, 0.2f}) {
        ngi::AdaptiveView view;
        view.maxError = bound;
        options.adaptive = view;
        std::snprintf(label, sizeof label, "adaptive %g%%", 100.0 * double(bound));
        row(label);
    }
    return 0;
}

int meshCommand(const std::vector<std::string>& args)
{
    std::vector<std::string> paths;
    std::optional<std::string> out;
    std::optional<float> lod, maxError, maxErrorPx, fov;
    std::optional<glm::vec3> eye, lookAt;
    std::optional<std::pair<uint32_t, uint32_t>> size;
    std::optional<std::string> weightsPath, networks;
    ngi::AssetMeshOptions options;
    bool restoreGiven = false;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(a + " expects a value");
            return args[++i];
        };
        if (a == "--lod")
            lod = parseFloat(a, value());
        else if (a == "--grid")
            options.gridSize = uint32_t(ngi::parseIntegerOptionInRange(a, value(), 0, 1u << 20));
        else if (a == "--max-error")
            maxError = ngi::parseFloatOptionInRange(a, value(), 1e-7, 1.0, "a fraction of the asset's size");
        else if (a == "--max-error-px")
            maxErrorPx = ngi::parseFloatOptionInRange(a, value(), 1e-3, 1e4, "pixels");
        else if (a == "--fov")
            fov = ngi::parseFloatOptionInRange(a, value(), 1.0, 179.0, "degrees");
        else if (a == "--eye")
            eye = ngi::parseVec3Option(a, value());
        else if (a == "--look-at")
            lookAt = ngi::parseVec3Option(a, value());
        else if (a == "--size")
            size = ngi::parseSizeOption(a, value());
        else if (a == "--sr")
            options.restore = ngi::AssetRestore::Network, restoreGiven = true;
        else if (a == "--no-sr")
            options.restore = ngi::AssetRestore::Bilinear, restoreGiven = true;
        else if (a == "--bicubic")
            options.restore = ngi::AssetRestore::Bicubic, restoreGiven = true;
        else if (a == "--weights")
            weightsPath = value();
        else if (a == "--networks")
            networks = value();
        else if (a == "-o")
            out = value();
        else if (a.size() > 1 && a[0] == '-')
            throw UsageError("unknown option '" + a + "'");
        else
            paths.push_back(a);
    }
    if (paths.size() != 1) throw UsageError("mesh expects one ASSET, got " + std::to_string(paths.size()) + " path(s)");
    if (!out) throw UsageError("mesh expects -o OUT");
    const bool camera = eye || lookAt || maxErrorPx || fov || size;
    if (int(bool(lod)) + int(bool(options.gridSize)) + int(bool(maxError)) + int(camera) > 1)
        throw UsageError("--lod, --grid, --max-error and a camera (--eye ...) are exclusive");
    if (!lod && !options.gridSize && !maxError && !camera)
        throw UsageError("mesh expects --lod F or --grid N, or the adaptive surface: --max-error E or a camera "
                         "(--eye X,Y,Z --look-at X,Y,Z --max-error-px P)");
    if (camera && !(eye && lookAt && maxErrorPx))
        throw UsageError(
            "a camera needs --eye X,Y,Z, --look-at X,Y,Z and --max-error-px P (--fov and --size optional)");
    if (lod) options.lod = *lod;

    if (weightsPath && !(restoreGiven && options.restore == ngi::AssetRestore::Network))
        throw UsageError("--weights needs --sr");
    if (networks && restoreGiven && options.restore != ngi::AssetRestore::Network)
        throw UsageError("--networks needs --sr (or no restore option: the default looks there)");
    if (out->empty()) throw UsageError("-o: the output path is empty");
    ngi::OutputFiles outputs({*out}, {paths[0], weightsPath.value_or("")});
    // Checked now, naming the path given; the mesh is staged only once it is drawn.
    const bool gltf = ngi::isGltfPath(*out);
    if (!gltf) ngi::checkMeshOutputFormat(*out);
    const ngi::Asset asset = ngi::readAsset(paths[0]);
    ngi::NetworkWeights network;
    chooseNetwork(paths[0], asset, weightsPath, networks, network, options, restoreGiven);
    ngi::AssetMesh drawn;
    try {
        if (maxError) {
            ngi::AdaptiveView view;
            view.maxError = *maxError;
            options.adaptive = view;
        } else if (camera) {
            const auto [width, height] = size.value_or(std::pair<uint32_t, uint32_t>{1280, 720});
            options.adaptive =
                ngi::assetAdaptiveView(asset, *eye, *lookAt, fov.value_or(45.0f), width, height, *maxErrorPx);
        }
        drawn = ngi::assetMesh(asset, options);
    } catch (const ngi::Error& e) {
        throw ngi::Error(paths[0] + ": " + e.what());
    }
    if (gltf) {
        ngi::MeshAppearance appearance;
        try {
            appearance = ngi::assetMeshAppearance(asset, drawn);
        } catch (const ngi::Error& e) {
            throw ngi::Error(paths[0] + ": " + e.what());
        }
        outputs.writeWith(
            *out, [&](const fs::path& staged) { ngi::writeGltf(staged, drawn.mesh, appearance, drawn.normals); });
        size_t coloured = 0;
        for (const ngi::AssetChart& chart : asset.charts) coloured += chart.baseColor.empty() ? 0 : 1;
        std::printf("%s: %zu of %zu chart(s) with a base colour texture\n", out->c_str(), coloured,
                    asset.charts.size());
    } else {
        outputs.writeWith(*out, [&](const fs::path& staged) { ngi::writeMesh(staged, drawn.mesh); });
    }
    outputs.commit();
    if (drawn.adaptive) {
        const ngi::TileSelection& s = *drawn.adaptive;
        std::printf("wrote %s: %zu triangles, %zu vertices (adaptive: %u tiles of %ux%u quads, %u forced splits; "
                    "%llu triangles drawn for the view, %u tiles outside the frustum, %u facing away; %s restore), "
                    "original coordinates\n",
                    out->c_str(), drawn.mesh.triangles.size(), drawn.mesh.positions.size(), uint32_t(s.tiles.size()),
                    ngi::kTileQuads, ngi::kTileQuads, s.forcedSplits, (unsigned long long)s.triangles, s.culledFrustum,
                    s.culledBackface,
                    options.restore == ngi::AssetRestore::Network       ? "super-resolution"
                        : options.restore == ngi::AssetRestore::Bicubic ? "bicubic"
                                                                        : "bilinear");
        return 0;
    }
    std::printf("wrote %s: %zu triangles, %zu vertices (level %u of 0..%u, morph %.3f, grid %ux%u, "
                "%s restore), original coordinates\n",
                out->c_str(), drawn.mesh.triangles.size(), drawn.mesh.positions.size(), drawn.selection.level,
                drawn.levelCount - 1, double(drawn.selection.morph), drawn.selection.gridSize, drawn.selection.gridSize,
                options.restore == ngi::AssetRestore::Network       ? "super-resolution"
                    : options.restore == ngi::AssetRestore::Bicubic ? "bicubic"
                                                                    : "bilinear");
    return 0;
}

#ifdef NGI_EVAL_HAS_REPORT
std::vector<std::string> splitList(const std::string& text)
{
    std::vector<std::string> items;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t end = std::min(text.find(',', start), text.size());
        if (end > start) items.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return items;
}

std::string duration(double seconds)
{
    char buffer[32];
    const long s = long(seconds + 0.5);
    if (s >= 3600)
        std::snprintf(buffer, sizeof buffer, "%ldh%02ldm", s / 3600, (s / 60) % 60);
    else
        std::snprintf(buffer, sizeof buffer, "%ldm%02lds", s / 60, s % 60);
    return buffer;
}

int reportCommand(const std::vector<std::string>& args, const std::string& commandLine)
{
    ngi::ReportOptions options;
    std::optional<std::string> meshes, out;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw UsageError(a + " expects a value");
            return args[++i];
        };
        if (a == "--meshes")
            meshes = value();
        else if (a == "--out")
            out = value();
        else if (a == "--resolution")
            options.resolution = uint32_t(ngi::parseIntegerOptionInRange(a, value(), 0, 1u << 16));
        else if (a == "--stored") {
            options.storedResolutions.clear();
            for (const std::string& item : splitList(value()))
                options.storedResolutions.push_back(uint32_t(ngi::parseIntegerOptionInRange(a, item, 0, 1u << 16)));
        } else if (a == "--params") {
            options.parameterizations.clear();
            for (const std::string& item : splitList(value())) {
                try {
                    options.parameterizations.push_back(ngi::parseParameterizationMethod(item));
                } catch (const ngi::Error& e) {
                    throw UsageError(std::string("--params: ") + e.what());
                }
            }
        } else if (a == "--jobs")
            options.jobs = unsigned(ngi::parseIntegerOptionInRange(a, value(), 0, 64));
        else if (a == "--reuse")
            options.reuse = true;
        else if (a == "--samples")
            options.sampleCount = uint32_t(ngi::parseIntegerOptionInRange(a, value(), 0, 100000000));
        else if (a == "--picture-size")
            options.pictureSize = uint32_t(ngi::parseIntegerOptionInRange(a, value(), 0, 2048));
        else if (a == "--weights")
            options.networkWeights = value();
        else if (a == "--note")
            options.resolutionNote = value();
        else if (a == "--budgets") {
            options.budgets.clear();
            const std::string& list = value();
            if (list != "none")
                for (const std::string& item : splitList(list)) {
                    options.budgets.push_back(size_t(ngi::parseIntegerOptionInRange(a, item, 0, uint64_t(1) << 32)));
                    if (options.budgets.back() == 0) throw UsageError("--budgets: a budget must be at least 1 byte");
                }
        } else if (a == "--networks") {
            options.networks = value();
            if (!fs::is_directory(options.networks))
                throw UsageError("--networks " + options.networks.string() + ": not a directory");
        } else
            throw UsageError("unknown report option '" + a + "'");
    }
    if (!meshes) throw UsageError("report expects --meshes DIR_OR_LIST");
    if (!out) throw UsageError("report expects --out DIR");
    options.meshes = ngi::resolveMeshList(*meshes);
    options.outDir = *out;
    std::vector<fs::path> inputs = options.meshes;
    inputs.push_back(options.networkWeights);
    ngi::refuseOutputEqualToInput({options.outDir}, inputs);  // --out is a directory it fills
    options.command = commandLine;

    const auto start = std::chrono::steady_clock::now();
    const bool tty = isatty(fileno(stderr));
    options.progress = [&](const ngi::ReportProgress& p) {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double fraction = p.total > 0.0 ? p.done / p.total : 1.0;
        const int width = 30, filled = int(fraction * width + 0.5);
        const std::string bar = std::string(size_t(filled), '#') + std::string(size_t(width - filled), '.');
        const std::string eta = fraction > 0.0 ? duration(elapsed * (1.0 - fraction) / fraction) : "?";
        std::fprintf(stderr, "%s[%s] %3.0f%%  %s elapsed, ETA %s  %-40.40s%s", tty ? "\r" : "", bar.c_str(),
                     fraction * 100.0, duration(elapsed).c_str(), eta.c_str(), p.step.c_str(), tty ? "" : "\n");
        std::fflush(stderr);
    };
    const ngi::ReportResult result = ngi::runReport(options);
    if (tty) std::fputc('\n', stderr);
    for (const std::string& file : result.skippedNetworkFiles)
        std::fprintf(stderr, "ngi-eval: warning: skipped a network file that does not read: %s\n", file.c_str());
    std::printf("wrote %s: %zu meshes, %zu failed bakes, %zu failed measurements, %s\n", result.reportPath.c_str(),
                result.meshCount, result.failedBakes, result.failedMeasurements, duration(result.seconds).c_str());
    return 0;
}
#endif

}  // namespace

int main(int argc, char** argv)
{
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        std::fputs(kUsage, args.empty() ? stderr : stdout);
        return args.empty() ? 2 : 0;
    }
    const std::string command = args[0];
    args.erase(args.begin());
    try {
        if (command == "distance") return distanceCommand(args);
        if (command == "mesh") return meshCommand(args);
        if (command == "watertight") return watertightCommand(args);
#ifdef NGI_EVAL_HAS_REPORT
        if (command == "report") {
            std::string line = "ngi-eval";
            for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
            return reportCommand(args, line);
        }
#endif
        throw UsageError("unknown command '" + command + "'");
    } catch (const UsageError& e) {
        std::fprintf(stderr, "ngi-eval: %s\n\n%s", e.what(), kUsage);
        return 2;
    } catch (const ngi::Error& e) {
        std::fprintf(stderr, "ngi-eval: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-eval: unexpected error: %s\n", e.what());
        return 1;
    }
}
