// The network an asset names and its residual gains: see ngi/bake/network_choice.h.
#include "ngi/bake/network_choice.h"

#include "ngi/error.h"
#include "ngi/sample_surface_area.h"

#include <chrono>

namespace ngi {

void reserveNetworkFields(Asset& asset, std::span<const ShippedNetwork> shipped)
{
    if (shipped.empty()) return;
    for (const ShippedNetwork& s : shipped)
        if (s.network.name.size() > asset.networkId.size()) asset.networkId = s.network.name;
    for (AssetChart& chart : asset.charts) chart.residualGain = 0.5f;
}

NetworkChoice nameNetworkAndFitGains(Asset& asset, const std::vector<ChartBake>& charts,
                                     std::span<const ShippedNetwork> shipped)
{
    if (charts.size() != asset.charts.size())
        throw Error((asset.sourceName.empty() ? std::string("asset") : asset.sourceName) +
                    ": the residual gains need every chart's full-resolution images");
    NetworkChoice choice;
    choice.named = nameMatchingNetwork(asset, shipped);
    choice.gains.resize(asset.charts.size());
    choice.gainSeconds.assign(asset.charts.size(), 0.0);
    // The network restores what a reader decodes: coding moves samples by up to half a step.
    Asset decoded = asset;
    applyAssetCoding(decoded);
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        AssetChart& chart = asset.charts[c];
        chart.residualGain = 1.0f;
        if (!choice.named || !networkRestoresChart(choice.named->network, chart)) continue;
        const auto start = std::chrono::steady_clock::now();
        // Weighted by the surface each sample stands for, as the rate control scores (rate_control.h).
        const std::vector<double> weights = surfaceAreaWeights(charts[c].fullPositions);
        choice.gains[c] = nn::fitResidualGain(choice.named->network, decoded.charts[c], charts[c].fullPositions,
                                              charts[c].fullNormals, weights);
        chart.residualGain = choice.gains[c]->gain;
        choice.gainSeconds[c] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return choice;
}

}  // namespace ngi
