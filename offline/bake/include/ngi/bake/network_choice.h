// ngi offline: the super-resolution network a baked asset names and the per-chart residual
// gains of its restore ("the network never makes it worse" than bicubic, DESIGN.md):
// what ngi-bake, its rate control and ngi-eval report share, so an asset baked by any of them
// is the same bytes.
//
// The shipped network named is the one whose factor takes the largest chart's stored level to
// its full resolution (ngi/network_catalog.h); each chart it restores gets the gain alpha of
// restore = bicubic + alpha (network - bicubic), fitted by the network's reference forward on the
// stored level as a reader decodes it (ngi/nn/residual_gain.h). Charts it does not restore keep
// alpha = 1 (the tools restore them without a network).
#pragma once

#include "ngi/asset.h"
#include "ngi/bake/bake.h"
#include "ngi/network_catalog.h"
#include "ngi/nn/residual_gain.h"

#include <optional>
#include <span>
#include <vector>

namespace ngi {

struct NetworkChoice {
    const ShippedNetwork* named = nullptr;                  // into the `shipped` span; null: none
    std::vector<std::optional<nn::ResidualGainFit>> gains;  // per chart; empty where not restored
    std::vector<double> gainSeconds;                        // per chart: the fit's reference forward
};

// Before rate control: gives `asset` the longest network id of `shipped` and placeholder gains
// (0.5, so format 6's chart table is counted), so the bytes the rate control measures are at
// least what the final asset takes whichever network ends up named. No-op for empty `shipped`.
void reserveNetworkFields(Asset& asset, std::span<const ShippedNetwork> shipped);

// Names in `asset` the shipped network restoring its largest chart (nameMatchingNetwork) and
// sets every chart's residualGain: the fit (nn::fitResidualGain against `charts[c]`'s full
// images, each sample weighted by its surface area, surfaceAreaWeights: the rate control's
// score, so rmsGained^2 is that chart's term of it) where the named network restores the chart, 1 elsewhere. `asset` holds the chosen
// stored level as serialized (uncoded samples): the fit runs on a copy decoded as a reader
// decodes it (applyAssetCoding). ngi::Error when
// `charts` does not match `asset`'s charts; the fit's errors otherwise.
NetworkChoice nameNetworkAndFitGains(Asset& asset, const std::vector<ChartBake>& charts,
                                     std::span<const ShippedNetwork> shipped);

}  // namespace ngi
