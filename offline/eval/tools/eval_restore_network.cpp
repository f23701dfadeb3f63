// The network `ngi-eval mesh` and `watertight` restore with (eval_commands.h).
#include "eval_commands.h"

#include "ngi/error.h"
#include "ngi/network_catalog.h"

#include <cstdio>

namespace ngi::eval_cli {

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

}  // namespace ngi::eval_cli
