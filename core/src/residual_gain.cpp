// The per-chart residual gain of the super-resolution restore: a least-squares fit of the
// network's residual against the full image (ngi/nn/residual_gain.h).
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
    const SkipAndResidual split = referenceForwardSplit(network, featureMapFromGeometryImage(storedPositions(chart)),
                                                        featureMapFromGeometryImage(storedNormals(chart)));
    const FeatureMap target = featureMapFromGeometryImage(fullPositions);
    double rt = 0.0, rr = 0.0;
    for (size_t i = 0; i < target.data.size(); ++i) {
        const double r = split.residual.data[i], d = double(target.data[i]) - split.skip.data[i];
        rt += r * d;
        rr += r * r;
    }
    ResidualGainFit fit;
    fit.gain = rr > 0.0 ? float(std::clamp(rt / rr, 0.0, 1.0)) : 1.0f;
    double skip = 0.0, net = 0.0, gained = 0.0;
    for (size_t i = 0; i < target.data.size(); ++i) {
        const double s = split.skip.data[i], r = split.residual.data[i], t = target.data[i];
        skip += (s - t) * (s - t);
        net += (s + r - t) * (s + r - t);
        gained += (s + fit.gain * r - t) * (s + fit.gain * r - t);
    }
    const double n = double(std::max<size_t>(target.data.size() / 3, 1));
    fit.rmsSkip = std::sqrt(skip / n);
    fit.rmsNetwork = std::sqrt(net / n);
    fit.rmsGained = std::sqrt(gained / n);
    return fit;
}

} // namespace ngi::nn
