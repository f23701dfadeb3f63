// ngi nn: the per-chart residual gain of the super-resolution restore (issue #14, "the network
// must never be worse than bicubic"). The network's output is its skip s (the upsampling of the
// stored level by its final BilinearSkip/CubicSkip/HermiteSkip) plus a residual r; the asset
// stores per chart the least-squares gain of r against the chart's full-resolution image t,
//   alpha = clamp(<r, t - s> / <r, r>, 0, 1)   (sums over every sample and channel),
// and every restore computes s + alpha r (AssetChart::residualGain). alpha = 0 is the skip, so
// the restore is never worse than the skip in image RMS; alpha = 1 is the network as trained.
#pragma once

#include "ngi/asset.h"
#include "ngi/geometry_image.h"
#include "ngi/network_weights.h"

namespace ngi::nn {

// The fit and what it buys, as RMS distances to t in normalized units (the asset's [0,1]^3).
struct ResidualGainFit {
    float gain = 1.0f;        // alpha in [0, 1]; 1 when the residual is zero (nothing to scale)
    double rmsSkip = 0.0;     // |s - t|
    double rmsNetwork = 0.0;  // |s + r - t|
    double rmsGained = 0.0;   // |s + alpha r - t|
};

// Runs `network`'s reference forward (reference_forward.h) on `chart`'s stored level as a reader
// decodes it (storedPositions/storedNormals) and fits alpha against `fullPositions` (the chart's
// full image, normalized like the asset; chart.fullSize() samples per side). ngi::Error when the
// network does not restore the chart (networkRestoresChart), its output is not written by a skip
// layer, or fullPositions has the wrong size. Single-threaded: ~3 GFLOP for the shipped x8
// network on a 129^2 stored level.
ResidualGainFit fitResidualGain(const NetworkWeights& network, const AssetChart& chart, const GeometryImage& fullPositions);

} // namespace ngi::nn
