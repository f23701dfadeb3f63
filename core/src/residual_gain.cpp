// The per-chart residual gain of the super-resolution restore: a least-squares fit of the blend
// between the bicubic and the network against the full image (ngi/nn/residual_gain.h).
#include "ngi/nn/residual_gain.h"

#include "ngi/error.h"
#include "ngi/network_catalog.h"
#include "ngi/nn/feature_map.h"
#include "ngi/nn/reference_forward.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ngi::nn {

ResidualGainFit fitResidualGain(const NetworkWeights& network, const AssetChart& chart, const GeometryImage& fullPositions)
{
    if (!networkRestoresChart(network, chart))
        throw Error(networkLabel(network) + ": upsamples x" + std::to_string(network.scaleFactor) +
                    ", the chart stores level " + std::to_string(chart.storedLevel));
    if (fullPositions.size != chart.fullSize())
        throw Error("fitResidualGain: the full image has " + std::to_string(fullPositions.size) + " samples per side, not " +
                    std::to_string(chart.fullSize()));
    const RestoreEndpoints ends = referenceForwardEndpoints(network, featureMapFromGeometryImage(storedPositions(chart)),
                                                           featureMapFromGeometryImage(storedNormals(chart)));
    const FeatureMap target = featureMapFromGeometryImage(fullPositions);
    double dt = 0.0, dd = 0.0;
    for (size_t i = 0; i < target.data.size(); ++i) {
        const double d = double(ends.network.data[i]) - ends.cubic.data[i], e = double(target.data[i]) - ends.cubic.data[i];
        dt += d * e;
        dd += d * d;
    }
    ResidualGainFit fit;
    fit.gain = dd > 0.0 ? float(std::clamp(dt / dd, 0.0, 1.0)) : 1.0f;
    double cubic = 0.0, net = 0.0, gained = 0.0;
    for (size_t i = 0; i < target.data.size(); ++i) {
        const double c = ends.cubic.data[i], n = ends.network.data[i], t = target.data[i], g = c + fit.gain * (n - c);
        cubic += (c - t) * (c - t);
        net += (n - t) * (n - t);
        gained += (g - t) * (g - t);
    }
    const double n = double(std::max<size_t>(target.data.size() / 3, 1));
    fit.rmsCubic = std::sqrt(cubic / n);
    fit.rmsNetwork = std::sqrt(net / n);
    fit.rmsGained = std::sqrt(gained / n);
    return fit;
}

} // namespace ngi::nn
