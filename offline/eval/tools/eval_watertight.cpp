// `ngi-eval watertight`: the open edges and widest gaps of the drawn mesh at every LoD and
// adaptive bound.
#include "eval_commands.h"

#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/eval/open_edges.h"

#include <algorithm>
#include <cstdio>

namespace ngi::eval_cli {

int watertightCommand(const std::vector<std::string>& arguments)
{
    std::vector<std::string> paths;
    std::optional<std::string> weightsPath, networks;
    ngi::AssetMeshOptions options;
    bool restoreGiven = false;
    ngi::ArgReader args(arguments);
    while (args.next()) {
        const std::string& a = args.flag();
        if (args.is("--sr"))
            options.restore = ngi::AssetRestore::Network, restoreGiven = true;
        else if (args.is("--no-sr"))
            options.restore = ngi::AssetRestore::Bilinear, restoreGiven = true;
        else if (args.is("--bicubic"))
            options.restore = ngi::AssetRestore::Bicubic, restoreGiven = true;
        else if (args.is("--weights"))
            weightsPath = args.value();
        else if (args.is("--networks"))
            networks = args.value();
        else if (args.positional())
            paths.push_back(a);
        else
            throw args.unknown();
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

}  // namespace ngi::eval_cli
