// The per-chart residual gain of the super-resolution restore: a least-squares fit of the blend
// between the bicubic and the network against the full image, along its normals
// (ngi/nn/residual_gain.h).
#include "ngi/nn/residual_gain.h"

#include "ngi/error.h"
#include "ngi/network_catalog.h"
#include "ngi/nn/feature_map.h"
#include "ngi/nn/reference_forward.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace ngi::nn {

ResidualGainFit fitResidualGain(const NetworkWeights& network, const AssetChart& chart,
                                const GeometryImage& fullPositions, const GeometryImage& fullNormals,
                                std::span<const double> weights)
{
    if (!networkRestoresChart(network, chart))
        throw Error(networkLabel(network) + ": upsamples x" + std::to_string(network.scaleFactor) +
                    ", the chart stores level " + std::to_string(chart.storedLevel));
    if (fullPositions.size != chart.fullSize() || fullNormals.size != chart.fullSize())
        throw Error("fitResidualGain: the full images have " + std::to_string(fullPositions.size) + " and " +
                    std::to_string(fullNormals.size) + " samples per side, not " + std::to_string(chart.fullSize()));
    if (!weights.empty() && weights.size() != fullPositions.texels.size())
        throw Error("fitResidualGain: " + std::to_string(weights.size()) + " sample weights for " +
                    std::to_string(fullPositions.texels.size()) + " samples");
    const auto w = [&](size_t i) { return weights.empty() ? 1.0 : weights[i]; };
    const RestoreEndpoints ends =
        referenceForwardEndpoints(network, featureMapFromGeometryImage(storedPositions(chart)),
                                  featureMapFromGeometryImage(storedNormals(chart)));
    const size_t plane = fullPositions.texels.size();
    // Per sample: the normal components of n - c and t - c (feature maps are channel planes).
    std::vector<double> d(plane), e(plane);
    double dt = 0.0, dd = 0.0;
    for (size_t i = 0; i < plane; ++i) {
        const glm::vec3 t = fullPositions.texels[i], N = fullNormals.texels[i];
        for (int k = 0; k < 3; ++k) {
            const double c = ends.cubic.data[size_t(k) * plane + i], n = ends.network.data[size_t(k) * plane + i];
            d[i] += (n - c) * N[k];
            e[i] += (double(t[k]) - c) * N[k];
        }
        dt += w(i) * d[i] * e[i];
        dd += w(i) * d[i] * d[i];
    }
    ResidualGainFit fit;
    fit.gain = dd > 0.0 ? float(std::clamp(dt / dd, 0.0, 1.0)) : 1.0f;
    double cubic = 0.0, net = 0.0, gained = 0.0;
    for (size_t i = 0; i < plane; ++i) {
        cubic += w(i) * e[i] * e[i];
        net += w(i) * (d[i] - e[i]) * (d[i] - e[i]);
        gained += w(i) * (fit.gain * d[i] - e[i]) * (fit.gain * d[i] - e[i]);
    }
    const double n = double(std::max<size_t>(plane, 1));
    fit.rmsCubic = std::sqrt(cubic / n);
    fit.rmsNetwork = std::sqrt(net / n);
    fit.rmsGained = std::sqrt(gained / n);
    return fit;
}

}  // namespace ngi::nn
