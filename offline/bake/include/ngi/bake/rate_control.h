// ngi offline: rate control of the asset (`ngi-bake --target-bytes N`): choose the
// stored level and the position quantization step so the whole asset file is at most N
// bytes with the smallest restore error.
//
// Per stored level (513^2 down to 9^2 of a 1024 image) and tangent step scale, the smallest step of the pyramid
// coder (ngi/pyramid_codec.h) on a ladder of quarter octaves (1, 1.19, 1.41, ... 4096 units of
// 1/65536) whose asset fits is found by bisection (file size decreases with the step); each level's fitting candidate is then restored to full
// resolution by the bicubic restore (nn::cubicSkip, the restore without a network) and scored
// by the mean squared distance of the restored samples to the full-resolution image along its
// normals (a point-to-plane proxy of the surface distance the evaluation reports: a sample
// that moves within the surface costs nothing), each sample's square weighted by the surface
// area it stands for (ngi/sample_surface_area.h, mean weight 1 per chart; charts summed by
// their share of the surface): the Chamfer distance samples the surface, not the image, and a
// map that squeezes thin parts into few samples would hide their error. Where a shipped
// network restores a level, the level's best candidate is scored by the network's restore
// instead (network_choice.h: its residual gain fitted, so never worse than bicubic). The
// smallest score wins within a level; between levels, given the input mesh, the smallest
// distance of the level's best restore to the input surface (the full image is not the input
// where the map undersamples). The asset's META chunk is reduced to the few bake fields tools
// read (compactBakeMetadata); --json keeps all.
#pragma once

#include "ngi/asset.h"
#include "ngi/bake/bake.h"
#include "ngi/network_catalog.h"

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace ngi {

struct RateCandidate {
    uint32_t storedLevel = 0;   // of the largest chart (smaller charts clamp to their own levels)
    uint32_t step = 1;          // position step in 1/65536 of the bounding box
    uint32_t tangentScale = 0;  // the residual frame's tangent step scale (pyramid_codec.h)
    double stepGrade = 1.0;     // each coarser level's step this many times finer (gradedLevelSteps)
    size_t bytes = 0;           // the whole asset file
    double error =
        0.0;  // surface-weighted mean squared point-to-plane error of the bicubic restore (normalized units^2)
    // The same of the named network's restore with its fitted residual gains (network_choice.h);
    // < 0 when not measured (no shipped network restores this level, or not the level's best
    // bicubic candidate).
    double networkError = -1.0;
    std::string networkId;  // the network measured, "" when none
    // The same against the INPUT surface (mean squared distance of the restore's samples to it,
    // surface-weighted, normalized units^2): measured on each level's best candidate when
    // fitAssetToBytes is given the input, < 0 otherwise. It chooses between levels.
    double inputError = -1.0;
    size_t inputSamples = 0;  // the restore's samples (of positive surface weight) inputError was measured on
    double score() const { return networkError >= 0.0 ? networkError : error; }
};

// The share of a byte budget the charts' base colours may take, where the asset has them: the
// geometry is fitted to the rest (fitAssetToBytes).
inline constexpr double kColorBudgetShare = 0.25;

// How the base colours were fitted: WebP quality, how many levels coarser than the bake's
// colour level every chart's image was stored, the BCOL bytes (chunk table entries included)
// and the colour's RMS error over the bake's images (8-bit sRGB units).
struct ColorFit {
    bool present = false;
    uint32_t quality = 0;
    uint32_t levelsCoarser = 0;
    size_t bytes = 0;
    double rms = 0.0;
};

struct RateControlReport {
    size_t targetBytes = 0;
    ColorFit color;  // where the asset has base colours
    // Where the colours did not fit their share: they took more (up to half the budget), or
    // were dropped; empty otherwise.
    std::string colorWarning;
    RateCandidate chosen;
    std::vector<RateCandidate> candidates;  // the best fitting step of every level tried
    double seconds = 0.0;                   // wall time of fitAssetToBytes
    double inputSeconds = 0.0;              // of it, the distances to the input (0 without the input)
};

// Rewrites `asset` (from bakeMesh, with `charts` its full-resolution images) to fit
// `targetBytes`: with base colours, first the colours into kColorBudgetShare of it (the level
// and WebP quality of the smallest colour error that fits, report.color; where even their
// smallest coding does not fit, that coding if it fits half the budget, else none:
// report.colorWarning says which), then the geometry into the rest: the chosen level's samples (before coding: serializeAsset(asset) writes
// exactly report.chosen.bytes; applyAssetCoding gives what a reader gets), coding and
// compact metadata. ngi::Error naming
// the smallest asset possible when even the coarsest level at the largest step does not fit.
// `normalBits`: the normals' residual bits (AssetCoding::normalBits; 0 = predicted from the
// positions, enough for the bicubic restore, which does not read them; the network's Hermite
// skip does: 4 bits recover most of what it gets from the stored normals).
// `shipped`: the networks the asset may name (network_choice.h). At each level one of them
// restores, the level's best bicubic candidate is also scored by the network's restore with its
// fitted gains, and the candidate of the smallest score() wins within its level: so a shipped
// network moves the choice toward the level it restores well. Empty: bicubic scores only.
// `input`: the mesh as read (object space). Given, each level's best is also scored against it
// (RateCandidate::inputError: every third sample per side of its bicubic restore, its distance to
// the input's triangles; a network's restore scales it by the network's ratio to the bicubic against
// the full image), and the level of the smallest input score is chosen (a broken measurement,
// brokenInputMeasurement, never; the full image's score when every level's is broken): the full image is not the input where the map undersamples,
// and a level that reproduces the full image's own error scored better there and measured worse.
// Null: levels compete by score() too.
RateControlReport fitAssetToBytes(Asset& asset, const std::vector<ChartBake>& charts, size_t targetBytes,
                                  uint32_t normalBits = 0, std::span<const ShippedNetwork> shipped = {},
                                  const TriangleMesh* input = nullptr);

// The choice between two bakes of one mesh at a byte budget (ngi-bake --target-bytes and the
// report's budget rows alike): a split for thin parts against one chart per
// component, or --split-pieces auto's one chart against its split. Each is fitted to
// `targetBytes` by fitAssetToBytes with the input, and the one whose chosen restore is closer
// to the input (RateCandidate::inputError, the rate control's own measure) is kept; `first`
// on a tie. A bake whose measurement is broken (brokenInputMeasurement: exactly 0, NaN,
// infinite, not measured or on no samples) never wins: it loses with a warning saying why, and
// when both are broken `first` is kept with a warning. Null `second` (that bake was refused,
// e.g. cheese in one chart): `first` alone. The kept asset is the one rewritten for the budget;
// the other is rewritten too and dropped by the caller.
struct BudgetChoice {
    RateControlReport first;
    std::optional<RateControlReport> second;
    bool keptFirst = true;
    std::vector<std::string> warnings;  // why a bake lost without a comparison (for the caller to print)
    const RateControlReport& kept() const { return keptFirst ? first : *second; }
};
BudgetChoice fitCloserOfTwoBakes(Asset& first, const std::vector<ChartBake>& firstCharts, Asset* second,
                                 const std::vector<ChartBake>* secondCharts, size_t targetBytes, uint32_t normalBits,
                                 std::span<const ShippedNetwork> shipped, const TriangleMesh& input);

// Why `candidate`'s distance to the input (RateCandidate::inputError) cannot be compared: it is
// NaN, infinite, negative (not measured), made on no samples, or exactly 0 (a restore from a
// coarser stored level at a byte budget never lies exactly on the input: an exact 0 means the
// measurement failed, not that the bake is perfect). Empty when it is a real measurement.
std::string brokenInputMeasurement(const RateCandidate& candidate);

// META reduced to {"bake": {"totalSeconds", "parameterization": {area/angle distortion mean}}}
// (what ngi-eval report reads), from the bake's full metadata JSON.
std::string compactBakeMetadata(const std::string& metadataJson);

}  // namespace ngi
