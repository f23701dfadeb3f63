// `ngi-eval mesh`: the triangle mesh the renderer draws for an asset, as a mesh file or glTF.
#include "eval_commands.h"

#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/eval/asset_appearance.h"
#include "ngi/eval/gltf_export.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/output_files.h"

#include <cstdio>
#include <filesystem>

namespace ngi::eval_cli {

namespace fs = std::filesystem;

int meshCommand(const std::vector<std::string>& arguments)
{
    std::vector<std::string> paths;
    std::optional<std::string> out;
    std::optional<float> lod, maxError, maxErrorPx, fov;
    std::optional<glm::vec3> eye, lookAt;
    std::optional<std::pair<uint32_t, uint32_t>> size;
    std::optional<std::string> weightsPath, networks;
    ngi::AssetMeshOptions options;
    bool restoreGiven = false;
    ngi::ArgReader args(arguments);
    while (args.next()) {
        const std::string& a = args.flag();
        if (args.is("--lod"))
            lod = ngi::parseFloatOption(a, args.value());  // rejects text, nan, inf and 1e999
        else if (args.is("--grid"))
            options.gridSize = uint32_t(ngi::parseIntegerOptionInRange(a, args.value(), 0, 1u << 20));
        else if (args.is("--max-error"))
            maxError = ngi::parseFloatOptionInRange(a, args.value(), 1e-7, 1.0, "a fraction of the asset's size");
        else if (args.is("--max-error-px"))
            maxErrorPx = ngi::parseFloatOptionInRange(a, args.value(), 1e-3, 1e4, "pixels");
        else if (args.is("--fov"))
            fov = ngi::parseFloatOptionInRange(a, args.value(), 1.0, 179.0, "degrees");
        else if (args.is("--eye"))
            eye = ngi::parseVec3Option(a, args.value());
        else if (args.is("--look-at"))
            lookAt = ngi::parseVec3Option(a, args.value());
        else if (args.is("--size"))
            size = ngi::parseSizeOption(a, args.value());
        else if (args.is("--sr"))
            options.restore = ngi::AssetRestore::Network, restoreGiven = true;
        else if (args.is("--no-sr"))
            options.restore = ngi::AssetRestore::Bilinear, restoreGiven = true;
        else if (args.is("--bicubic"))
            options.restore = ngi::AssetRestore::Bicubic, restoreGiven = true;
        else if (args.is("--weights"))
            weightsPath = args.value();
        else if (args.is("--networks"))
            networks = args.value();
        else if (args.is("-o"))
            out = args.value();
        else if (args.positional())
            paths.push_back(a);
        else
            throw args.unknown();
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

}  // namespace ngi::eval_cli
