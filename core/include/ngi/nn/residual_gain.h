// ngi nn: the per-chart residual gain of the super-resolution restore ("the network must never
// be worse than bicubic"). With c the bicubic (Catmull-Rom) upsampling of the stored
// level and n the network's output, the restore is c + alpha (n - c), alpha per chart the
// least-squares weight against the chart's full-resolution image t along its normals N (the
// point-to-plane error: what a surface distance sees; a sample moved along the surface costs
// nothing),
//   alpha = clamp(<(n - c).N, (t - c).N> / <(n - c).N, (n - c).N>, 0, 1)   (sums over samples),
// stored as AssetChart::residualGain. alpha = 0 is the bicubic, so the restore is never worse
// than bicubic in RMS point-to-plane error; alpha = 1 is the network as trained. Point-to-plane,
// because the 3D RMS also counts the tangential drift the network may add, which a surface
// distance does not see (docs/networks.md). The alpha = 0 end is the bicubic, not the network's
// own skip, because where the network loses its skip loses as much (ngi/nn/reference_forward.h).
// Every sum may weigh sample i by w_i, the surface area it stands for
// (ngi/sample_surface_area.h): alpha then minimizes the error a surface distance sees.
#pragma once

#include "ngi/asset.h"
#include "ngi/geometry_image.h"
#include "ngi/network_weights.h"

#include <span>

namespace ngi::nn {

// The fit and what it buys, as RMS point-to-plane distances to t in normalized units (the
// asset's [0,1]^3), each sample's square weighted by w_i (sqrt(sum w_i e_i^2 / samples)).
struct ResidualGainFit {
    float gain = 1.0f;        // alpha in [0, 1]; 1 when n = c along the normals (nothing to blend)
    double rmsCubic = 0.0;    // |(c - t).N|
    double rmsNetwork = 0.0;  // |(n - t).N|
    double rmsGained = 0.0;   // |(c + alpha (n - c) - t).N|
};

// Runs `network`'s reference forward (reference_forward.h) on `chart`'s stored level as a reader
// decodes it (storedPositions/storedNormals) and fits alpha against `fullPositions` along
// `fullNormals` (the chart's full images, positions normalized like the asset, unit normals;
// chart.fullSize() samples per side). ngi::Error when the
// network does not restore the chart (networkRestoresChart), its output is not written by a skip
// layer (whose coarse input c upsamples), or a full image has the wrong size. `weights`: w_i per
// full-image sample (row-major; surfaceAreaWeights(fullPositions), mean 1, is what the bake passes),
// empty = 1 each; ngi::Error when neither empty nor one per sample. Single-threaded: ~3 GFLOP for
// the shipped x8 network on a 129^2 stored level.
ResidualGainFit fitResidualGain(const NetworkWeights& network, const AssetChart& chart,
                                const GeometryImage& fullPositions, const GeometryImage& fullNormals,
                                std::span<const double> weights = {});

}  // namespace ngi::nn
