// Rate control of the asset: see ngi/bake/rate_control.h.
#include "ngi/bake/rate_control.h"

#include "ngi/bake/network_choice.h"

#include "ngi/color_codec.h"
#include "ngi/mesh/surface_color.h"

#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/nn/feature_map.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/param/detail_transfer.h"
#include "ngi/pyramid_codec.h"
#include "ngi/sample_surface_area.h"
#include "ngi/stopwatch.h"

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

namespace ngi {
namespace {

constexpr size_t kChunkTableEntryBytes = 32;       // BCOL's entry in the asset's chunk table (ngi/asset.h)
constexpr uint32_t kCoarsestStoredResolution = 8;  // 9^2 samples: below that no surface is left
// Tangent step scales tried (pyramid_codec.h's residual frame; experiments/codec-rd.sh measures
// them): at equal CD they take fewer bytes than xyz residuals; a larger scale loses (the
// tangential noise spoils the predictions).
constexpr uint32_t kTangentScales[] = {2, 4, 8};
// And for each, the step grades of kPyramidStepGrades (uniform, and each coarser level sqrt 2
// finer): at small budgets the graded steps win on dense meshes (rate_control.h).

// The steps tried: quarter octaves from 1 (lossless) to kMaxPyramidStep, so a budget is
// filled to within ~10% in bytes.
std::vector<uint32_t> stepLadder()
{
    std::vector<uint32_t> steps;
    for (int i = 0; i <= 48; ++i) {
        const uint32_t q = uint32_t(std::lround(std::exp2(i / 4.0)));
        if (q <= kMaxPyramidStep && (steps.empty() || q != steps.back())) steps.push_back(q);
    }
    return steps;
}

// A colour image of n x n texels at the next coarser level of its grid ((n - 1) / 2 + 1 per
// side, nested: texel x there is texel 2x here), filtered by the 3 x 3 tent in linear light.
std::vector<uint8_t> coarserColor(const std::vector<uint8_t>& rgba, uint32_t n)
{
    const uint32_t m = (n - 1) / 2 + 1;
    std::vector<uint8_t> out(size_t(m) * m * 4);
    const double w[3] = {0.25, 0.5, 0.25};
    for (uint32_t y = 0; y < m; ++y)
        for (uint32_t x = 0; x < m; ++x)
            for (int k = 0; k < 4; ++k) {
                double sum = 0.0, weight = 0.0;
                for (int dy = -1; dy <= 1; ++dy)
                    for (int dx = -1; dx <= 1; ++dx) {
                        const long sx = long(2 * x) + dx, sy = long(2 * y) + dy;
                        if (sx < 0 || sy < 0 || sx >= long(n) || sy >= long(n)) continue;
                        const double v = rgba[(size_t(sy) * n + size_t(sx)) * 4 + size_t(k)] / 255.0;
                        const double c = w[dx + 1] * w[dy + 1];
                        sum += c * (k == 3 ? v : srgbToLinear(v));
                        weight += c;
                    }
                const double v = sum / weight;
                out[(size_t(y) * m + x) * 4 + size_t(k)] = uint8_t(std::lround(255.0 * (k == 3 ? v : linearToSrgb(v))));
            }
    return out;
}

// Squared error summed over the texels of `reference` (n x n) of `image` (m x m, the same grid
// `shift` levels coarser) upsampled bilinearly onto it, 8-bit units, RGBA.
double colorSquaredError(const std::vector<uint8_t>& reference, uint32_t n, const std::vector<uint8_t>& image,
                         uint32_t m, uint32_t shift)
{
    double sum = 0.0;
    const double scale = 1.0 / double(1u << shift);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const double fx = std::min(x * scale, double(m - 1)), fy = std::min(y * scale, double(m - 1));
            const uint32_t x0 = uint32_t(fx), y0 = uint32_t(fy), x1 = std::min(x0 + 1, m - 1),
                           y1 = std::min(y0 + 1, m - 1);
            const double ax = fx - x0, ay = fy - y0;
            for (int k = 0; k < 4; ++k) {
                auto at = [&](uint32_t xx, uint32_t yy) {
                    return double(image[(size_t(yy) * m + xx) * 4 + size_t(k)]);
                };
                const double v = (at(x0, y0) * (1 - ax) + at(x1, y0) * ax) * (1 - ay) +
                    (at(x0, y1) * (1 - ax) + at(x1, y1) * ax) * ay;
                const double d = v - reference[(size_t(y) * n + x) * 4 + size_t(k)];
                sum += d * d;
            }
        }
    return sum;
}

// The base colours of `asset` fitted into `budget` bytes of the file (BCOL chunks with their
// padding and table entries):
// for each number of levels coarser (0 to 4, every chart alike, none below 2 x 2), the highest
// WebP quality (101: lossless) that fits, and of those the smallest RMS error against the
// bake's images. Writes the images and
// the quality into `asset`, and the smallest colour coding tried into *smallestBytes (if
// given). ngi::Error naming that size when nothing fits.
ColorFit fitColorsToBytes(Asset& asset, size_t budget, const std::string& name, size_t* smallestBytes)
{
    ColorFit best;
    best.present = true;
    double bestError = std::numeric_limits<double>::infinity();
    std::vector<std::vector<uint8_t>> bestImages;
    std::vector<uint32_t> bestLevels;
    std::vector<std::vector<uint8_t>> images;
    std::vector<uint32_t> levels, sizes;
    for (const AssetChart& chart : asset.charts)
        images.push_back(chart.baseColor), levels.push_back(chart.baseColorLevel),
            sizes.push_back(chart.baseColorSize());
    size_t smallest = SIZE_MAX;
    for (uint32_t shift = 0; shift <= 4; ++shift) {
        if (shift > 0) {
            bool coarsened = false;
            for (size_t c = 0; c < images.size(); ++c) {
                if (images[c].empty() || levels[c] + 1 >= asset.charts[c].levelCount()) continue;
                images[c] = coarserColor(images[c], sizes[c]);
                ++levels[c], sizes[c] = (sizes[c] - 1) / 2 + 1, coarsened = true;
            }
            if (!coarsened) break;
        }
        // Format 9's one BCOL chunk: its table entry and padding, and per chart a level byte, the
        // image's length (LEB128, at most 3 bytes below 2 MB) and the image.
        auto bytesAt = [&](uint32_t quality) {
            size_t bytes = kChunkTableEntryBytes + 7;
            for (size_t c = 0; c < images.size(); ++c)
                bytes += 1 + (images[c].empty() ? 0 : 3 + encodeColorImage(images[c], sizes[c], quality, name).size());
            return bytes;
        };
        uint32_t lo = 0, hi = 101;  // 101: lossless
        const size_t lowest = bytesAt(lo);
        smallest = std::min(smallest, lowest);
        if (lowest > budget) continue;
        while (lo < hi) {  // the highest quality that fits: bytes grow with quality
            const uint32_t mid = (lo + hi + 1) / 2;
            if (bytesAt(mid) <= budget)
                lo = mid;
            else
                hi = mid - 1;
        }
        double error = 0.0, count = 0.0;
        for (size_t c = 0; c < images.size(); ++c) {
            if (images[c].empty()) continue;
            const std::vector<uint8_t> decoded =
                decodeColorImage(encodeColorImage(images[c], sizes[c], lo, name), sizes[c], name);
            const uint32_t n = asset.charts[c].baseColorSize();
            error += colorSquaredError(asset.charts[c].baseColor, n, decoded, sizes[c], shift);
            count += 4.0 * n * n;
        }
        if (error < bestError) {
            bestError = error;
            best.quality = lo, best.levelsCoarser = shift, best.bytes = bytesAt(lo),
            best.rms = std::sqrt(error / count);
            bestImages = images, bestLevels = levels;
        }
    }
    if (smallestBytes) *smallestBytes = smallest;
    if (bestImages.empty())
        throw Error(name + ": the base colours need at least " + std::to_string(smallest) + " bytes, more than their " +
                    std::to_string(budget) + " bytes of the budget (--target-bytes x " +
                    std::to_string(kColorBudgetShare) + ")");
    for (size_t c = 0; c < asset.charts.size(); ++c)
        if (!bestImages[c].empty())
            asset.charts[c].baseColor = std::move(bestImages[c]), asset.charts[c].baseColorLevel = bestLevels[c];
    asset.coding.colorQuality = best.quality;
    return best;
}

// The bytes to reserve for the base colours of `asset`: what they add to its file (the file
// with them less the file without), plus 7 for the alignment padding before their first chunk,
// which depends on where the geometry before them ends, and 7 more where a WGHT chunk follows
// them. So the shape of any candidate fits beside the same colours in the budget less this.
size_t colorBytesInFile(const Asset& asset)
{
    Asset shapeOnly = asset;
    for (AssetChart& chart : shapeOnly.charts) chart.baseColor.clear();
    const size_t with = serializeAsset(asset).size(), without = serializeAsset(shapeOnly).size();
    return (with > without ? with - without : 0) + 7 + (asset.weights.empty() ? 0 : 7);
}

// The asset with every chart stored at `level` (clamped per chart) and coded at step 2^k.
Asset candidateAsset(const Asset& baked, const std::vector<ChartBake>& charts, uint32_t level, uint32_t step,
                     uint32_t tangentScale, double grade, uint32_t normalBits)
{
    Asset a = baked;
    a.coding.pyramid = true;
    a.coding.positionStep = step;
    a.coding.positionStepGrade = grade;
    a.coding.positionTangentScale = tangentScale;
    a.coding.normalBits = normalBits;
    for (size_t c = 0; c < a.charts.size(); ++c) {
        AssetChart& chart = a.charts[c];
        chart.storedLevel = std::min<uint32_t>(level, uint32_t(std::countr_zero(chart.fullResolution)));
        storeGeometryImage(chart, downsampleNested(charts[c].fullPositions, chart.storedLevel),
                           downsampleNested(charts[c].fullNormals, chart.storedLevel));
    }
    return a;
}

// Per chart, the surface each sample stands for (surfaceAreaWeights, mean 1 within the chart) and
// the chart's share of the asset's surface: the score weighs a sample's squared error by its
// surface area, as the evaluation's Chamfer distance (uniform samples on the surface) does: a
// thin part can hold a larger share of the surface than of the image.
struct SurfaceWeights {
    std::vector<std::vector<double>> perSample;
    std::vector<double> chartShare;  // sums to 1 (by sample count when the charts have no area)
};

SurfaceWeights surfaceWeights(const std::vector<ChartBake>& charts)
{
    SurfaceWeights w;
    std::vector<double> area;
    double total = 0.0, samples = 0.0;
    for (const ChartBake& chart : charts) {
        const std::vector<double> areas = sampleSurfaceAreas(chart.fullPositions);
        w.perSample.push_back(surfaceAreaWeights(areas));
        double a = 0.0;
        for (const double s : areas) a += s;
        total += area.emplace_back(a);
        samples += double(chart.fullPositions.texels.size());
    }
    for (size_t c = 0; c < charts.size(); ++c)
        w.chartShare.push_back(total > 0.0         ? area[c] / total
                                   : samples > 0.0 ? charts[c].fullPositions.texels.size() / samples
                                                   : 0.0);
    return w;
}

// The chart's full image restored from its (decoded) stored level by Catmull-Rom, as the tools
// restore without a network.
GeometryImage bicubicRestore(const AssetChart& chart)
{
    const GeometryImage stored = storedPositions(chart);
    if (chart.storedLevel == 0) return stored;
    const nn::FeatureMap coarse = nn::featureMapFromGeometryImage(stored);
    const nn::FeatureMap zero(3, chart.fullSize(), chart.fullSize());
    return nn::geometryImageFromFeatureMap(nn::cubicSkip(coarse, zero, 1u << chart.storedLevel));
}

// Per chart: the surface-weighted mean squared point-to-plane distance of the bicubic restore of
// the coded asset to the full-resolution image (sum of w_i d_i^2 over the chart's samples).
std::vector<double> bicubicRestoreErrors(const Asset& coded, const std::vector<ChartBake>& charts,
                                         const SurfaceWeights& weights)
{
    std::vector<double> out;
    for (size_t c = 0; c < coded.charts.size(); ++c) {
        const GeometryImage restored = bicubicRestore(coded.charts[c]);
        const GeometryImage& full = charts[c].fullPositions;
        const GeometryImage& normals = charts[c].fullNormals;
        const std::vector<double>& w = weights.perSample[c];
        double sum = 0.0;
        for (size_t i = 0; i < full.texels.size() && i < restored.texels.size(); ++i) {
            const double d = glm::dot(glm::dvec3(restored.texels[i] - full.texels[i]), glm::dvec3(normals.texels[i]));
            sum += w[i] * d * d;
        }
        out.push_back(full.texels.empty() ? 0.0 : sum / double(full.texels.size()));
    }
    return out;
}

// Every kInputStride-th sample per side is measured against the input surface: an odd stride
// meets every phase of the stored grid (an even one would meet only stored samples at the finer
// levels: their quantization, not the interpolation between them), with a ninth of the queries.
constexpr uint32_t kInputStride = 3;

// For each asset (one candidate per level, decoded as a reader decodes it): the surface-weighted
// mean squared distance of its bicubic restore's samples to `input` (object space, as read; the
// distance in the asset's normalized units), the charts summed by their share of the surface. All
// levels in one query pass: one AABB tree of the input.
struct InputRestoreErrors {
    std::vector<double> meanSquared;  // per asset
    std::vector<size_t> samples;      // per asset: the samples of positive weight it was measured on
};
InputRestoreErrors inputRestoreErrors(const std::vector<const Asset*>& decoded, const SurfaceWeights& weights,
                                      const TriangleMesh& input)
{
    std::vector<glm::dvec3> points;
    std::vector<double> pointWeight;
    std::vector<std::pair<size_t, size_t>> ranges;  // per (asset, chart): its points
    for (const Asset* asset : decoded)
        for (size_t c = 0; c < asset->charts.size(); ++c) {
            const GeometryImage restored = bicubicRestore(asset->charts[c]);
            const std::vector<double>& w = weights.perSample[c];
            const size_t begin = points.size();
            for (uint32_t y = 0; y < restored.size; y += kInputStride)
                for (uint32_t x = 0; x < restored.size; x += kInputStride) {
                    const size_t i = size_t(y) * restored.size + x;
                    points.push_back(glm::dvec3(asset->offset) +
                                     glm::dvec3(asset->scale) * glm::dvec3(restored.texels[i]));
                    pointWeight.push_back(i < w.size() ? w[i] : 1.0);
                }
            ranges.emplace_back(begin, points.size());
        }
    const std::vector<double> d2 = points.empty() ? std::vector<double>{} : squaredDistancesToSurface(input, points);
    InputRestoreErrors out;
    size_t range = 0;
    for (const Asset* asset : decoded) {
        const double unit = double(asset->scale.x) > 0.0 ? 1.0 / double(asset->scale.x) : 1.0;
        double sum = 0.0;
        size_t samples = 0;
        for (size_t c = 0; c < asset->charts.size(); ++c, ++range) {
            double weighted = 0.0, weightSum = 0.0;
            for (size_t i = ranges[range].first; i < ranges[range].second; ++i) {
                weighted += pointWeight[i] * d2[i], weightSum += pointWeight[i];
                samples += pointWeight[i] > 0.0;
            }
            if (weightSum > 0.0) sum += weights.chartShare[c] * weighted / weightSum;
        }
        out.meanSquared.push_back(sum * unit * unit);
        out.samples.push_back(samples);
    }
    return out;
}

// The asset's score: the charts' mean squares summed by their share of the surface.
double meanError(const std::vector<double>& perChart, const SurfaceWeights& weights)
{
    double sum = 0.0;
    for (size_t c = 0; c < perChart.size(); ++c) sum += weights.chartShare[c] * perChart[c];
    return sum;
}

}  // namespace

std::string brokenInputMeasurement(const RateCandidate& candidate)
{
    const double e = candidate.inputError;
    if (std::isnan(e)) return "its mean squared distance to the input is NaN";
    if (std::isinf(e)) return "its mean squared distance to the input is infinite";
    if (e < 0.0) return "it was not measured against the input";
    if (candidate.inputSamples == 0) return "it was measured on no samples";
    if (e == 0.0)
        return "its mean squared distance to the input is exactly 0 over " + std::to_string(candidate.inputSamples) +
            " samples: a restore at a byte budget never lies exactly on the input";
    return {};
}

std::string compactBakeMetadata(const std::string& metadataJson)
{
    const nlohmann::json meta = nlohmann::json::parse(metadataJson, nullptr, false);
    nlohmann::json out = nlohmann::json::object();
    if (meta.is_object() && meta.contains("bake") && meta["bake"].is_object()) {
        const nlohmann::json& bake = meta["bake"];
        if (bake.contains("totalSeconds")) out["bake"]["totalSeconds"] = bake["totalSeconds"];
        if (bake.contains("parameterization") && bake["parameterization"].is_object())
            for (const char* key : {"areaDistortionMean", "angleDistortionMean"})
                if (bake["parameterization"].contains(key))
                    out["bake"]["parameterization"][key] = bake["parameterization"][key];
    }
    return out.dump();
}

BudgetChoice fitCloserOfTwoBakes(Asset& first, const std::vector<ChartBake>& firstCharts, Asset* second,
                                 const std::vector<ChartBake>* secondCharts, size_t targetBytes, uint32_t normalBits,
                                 std::span<const ShippedNetwork> shipped, const TriangleMesh& input)
{
    if ((second == nullptr) != (secondCharts == nullptr))
        throw Error("fitCloserOfTwoBakes: the second bake needs both its asset and its charts");
    BudgetChoice choice;
    choice.first = fitAssetToBytes(first, firstCharts, targetBytes, normalBits, shipped, &input);
    if (second) {
        choice.second = fitAssetToBytes(*second, *secondCharts, targetBytes, normalBits, shipped, &input);
        const std::string firstBroken = brokenInputMeasurement(choice.first.chosen);
        const std::string secondBroken = brokenInputMeasurement(choice.second->chosen);
        if (!firstBroken.empty() && !secondBroken.empty()) {
            choice.keptFirst = true;
            choice.warnings.push_back("neither bake of the choice was measured against the input (the first: " +
                                      firstBroken + "; the second: " + secondBroken + "): kept the first");
        } else if (!firstBroken.empty() || !secondBroken.empty()) {
            choice.keptFirst = firstBroken.empty();
            choice.warnings.push_back(std::string(firstBroken.empty() ? "the second" : "the first") +
                                      " bake of the choice loses: its measurement against the input is broken (" +
                                      (firstBroken.empty() ? secondBroken : firstBroken) + ")");
        } else {
            choice.keptFirst = choice.first.chosen.inputError <= choice.second->chosen.inputError;
        }
    }
    return choice;
}

namespace {

// The colours first, into their share of `targetBytes` (lowered by what they take); the geometry
// is searched without them (each WebP coding costs far more than a geometry candidate) and
// gets the rest of the budget. Returns whether the asset keeps colours; `colors` then holds
// them coded.
bool fitColorsFirst(const Asset& asset, size_t& targetBytes, const std::string& name, RateControlReport& report,
                    Asset& colors)
{
    colors = asset;
    bool anyColor = asset.hasBaseColors();
    if (anyColor) {
        // Where the colours' smallest coding exceeds their share (many charts: each image has
        // its own WebP header and chunk entry), they may take up to half the budget; beyond
        // that they are dropped with a warning: the shape is never refused for its colour.
        const size_t share = size_t(double(targetBytes) * kColorBudgetShare);
        size_t smallest = 0;
        try {
            report.color = fitColorsToBytes(colors, share, name, &smallest);
        } catch (const Error&) {
            if (smallest <= targetBytes / 2) {
                report.color = fitColorsToBytes(colors, smallest, name, &smallest);
            } else {
                for (AssetChart& chart : colors.charts) chart.baseColor.clear();
                anyColor = false;
                report.colorWarning = "the base colours need at least " + std::to_string(smallest) +
                    " bytes, more than half of --target-bytes " + std::to_string(targetBytes) +
                    ": they were dropped (the asset has its shape only)";
            }
        }
        // Their share of the file, measured: their chunks with padding and chunk-table entries
        // (fitColorsToBytes bounds it from above). The shape gets the rest.
        if (anyColor) report.color.bytes = colorBytesInFile(colors);
        if (anyColor && report.color.bytes > share)
            report.colorWarning = "the base colours need at least " + std::to_string(smallest) +
                " bytes, more than their " + std::to_string(int(100.0 * kColorBudgetShare)) +
                "% of the budget: they take " + std::to_string(report.color.bytes) + " bytes and the shape the rest";
        if (anyColor) targetBytes -= std::min(targetBytes, report.color.bytes);
    }
    return anyColor;
}

// The smallest position step at which `base`'s candidate at `level` fits `targetBytes` (the file
// falls as the step grows), or none where the ladder's largest step does not fit. `smallest`
// takes the smallest file seen at that largest step.
std::optional<uint32_t> smallestFittingStep(const Asset& base, const std::vector<ChartBake>& charts, uint32_t level,
                                            uint32_t tangentScale, double grade, uint32_t normalBits,
                                            const std::vector<uint32_t>& ladder, size_t targetBytes, size_t& smallest)
{
    auto bytesAt = [&](size_t i) {
        return serializeAsset(candidateAsset(base, charts, level, ladder[i], tangentScale, grade, normalBits)).size();
    };
    // The smallest step that fits: file size falls as the step grows.
    size_t lo = 0, hi = ladder.size() - 1;
    const size_t largestStepBytes = bytesAt(hi);
    smallest = std::min(smallest, largestStepBytes);
    if (largestStepBytes > targetBytes) return std::nullopt;
    while (lo < hi) {
        const size_t mid = (lo + hi) / 2;
        if (bytesAt(mid) <= targetBytes)
            hi = mid;
        else
            lo = mid + 1;
    }
    // Then the smallest integer step between the ladder's last misfit and lo that fits.
    uint32_t step = ladder[lo];
    if (lo > 0) {
        uint32_t small = ladder[lo - 1] + 1, large = ladder[lo];
        while (small < large) {
            const uint32_t mid = (small + large) / 2;
            if (serializeAsset(candidateAsset(base, charts, level, mid, tangentScale, grade, normalBits)).size() <=
                targetBytes)
                large = mid;
            else
                small = mid + 1;
        }
        step = large;
    }
    return step;
}

// Each level's candidate of the smallest score(): its index in RateControlReport::candidates,
// the asset as stored and as a reader decodes it.
struct LevelBest {
    size_t index;
    Asset asset, decoded;
};

// Every tangent scale and step grade at `level`, each at the smallest step that fits
// `targetBytes`, scored by the bicubic restore against the full images; the best of them also
// by the network's restore where a shipped one restores this level. Appends them to
// report.candidates and returns the level's best, or none where nothing fits.
std::optional<LevelBest> bestAtLevel(const Asset& base, const std::vector<ChartBake>& charts, uint32_t level,
                                     uint32_t normalBits, std::span<const ShippedNetwork> shipped,
                                     const std::vector<uint32_t>& ladder, const SurfaceWeights& weights,
                                     size_t targetBytes, size_t& smallest, RateControlReport& report)
{
    struct Fit {
        RateCandidate r;
        Asset candidate, decoded;
        std::vector<double> perChart;
    };
    std::vector<Fit> fits;
    for (uint32_t tangentScale : kTangentScales)
        for (double grade : kPyramidStepGrades) {
            const std::optional<uint32_t> step = smallestFittingStep(base, charts, level, tangentScale, grade,
                                                                     normalBits, ladder, targetBytes, smallest);
            if (!step) continue;
            Fit f;
            f.candidate = candidateAsset(base, charts, level, *step, tangentScale, grade, normalBits);
            const size_t bytes = serializeAsset(f.candidate).size();
            if (bytes > targetBytes) continue;  // not monotone after all at this level: skip it
            // Scored on what a reader decodes; kept uncoded, so that serializing the result writes
            // exactly these bytes (the residual frame's coder is not idempotent: coding decoded
            // samples again may move them by a unit and change the size).
            f.decoded = f.candidate;
            applyAssetCoding(f.decoded);
            f.perChart = bicubicRestoreErrors(f.decoded, charts, weights);
            f.r = RateCandidate{.storedLevel = level,
                                .step = *step,
                                .tangentScale = tangentScale,
                                .stepGrade = grade,
                                .bytes = bytes,
                                .error = meanError(f.perChart, weights)};
            fits.push_back(std::move(f));
        }
    if (fits.empty()) return std::nullopt;
    // The network's restore, where a shipped one restores this level, scored on the level's best
    // bicubic fit only: one reference forward per level instead of one per tangent
    // scale; its gain over the bicubic hardly depends on the residual frame.
    const auto bestBicubic =
        std::min_element(fits.begin(), fits.end(), [](const Fit& a, const Fit& b) { return a.r.error < b.r.error; });
    Asset withNetwork = bestBicubic->candidate;
    const NetworkChoice choice = nameNetworkAndFitGains(withNetwork, charts, shipped);
    if (choice.named) {
        // The fit weighs samples as bicubicRestoreErrors does (network_choice.h): its
        // rmsGained^2 replaces that chart's term.
        std::vector<double> perChart = bestBicubic->perChart;
        for (size_t c = 0; c < charts.size(); ++c)
            if (const auto& g = choice.gains[c]) perChart[c] = g->rmsGained * g->rmsGained;
        bestBicubic->r.networkError = meanError(perChart, weights);
        bestBicubic->r.networkId = choice.named->network.name;
    }
    Fit* levelBest = nullptr;
    for (Fit& f : fits) {
        report.candidates.push_back(f.r);
        if (!levelBest || f.r.score() < levelBest->r.score()) levelBest = &f;
    }
    return LevelBest{report.candidates.size() - fits.size() + size_t(levelBest - fits.data()),
                     std::move(levelBest->candidate), std::move(levelBest->decoded)};
}

// The level kept: its index in `levelBests` (not empty). Across levels: the smallest score
// against the input surface when it is given, else against the full image. The full image is
// not the input: where the map undersamples a thin part, its own error is the larger one, and a
// finer level that reproduces it better would score better and measure worse. Within a level
// the full image's score still chooses the step, frame and grade: they trade quantization
// noise, which it measures at every sample, and one input measurement per level keeps the cost
// to one query pass. Sets the candidates' input errors and report.inputSeconds.
size_t chooseLevel(const std::vector<LevelBest>& levelBests, const SurfaceWeights& weights, const TriangleMesh* input,
                   RateControlReport& report)
{
    std::vector<double> score;
    if (input) {
        std::vector<const Asset*> decoded;
        for (const LevelBest& b : levelBests) decoded.push_back(&b.decoded);
        const auto inputStart = StopwatchClock::now();
        const InputRestoreErrors measured = inputRestoreErrors(decoded, weights, *input);
        report.inputSeconds = secondsSince(inputStart);
        for (size_t l = 0; l < levelBests.size(); ++l) {
            // A network's restore: the bicubic's input score scaled by the network's ratio to
            // the bicubic against the full image (what nameNetworkAndFitGains measured). A
            // ratio, not a difference: against the full image a map that squeezes a thin part
            // scores far worse than against the input, and subtracting that gain from the
            // input score would drive it to zero.
            RateCandidate& r = report.candidates[levelBests[l].index];
            const double networkRatio = r.error > 0.0 ? std::clamp(r.score() / r.error, 0.0, 1.0) : 1.0;
            r.inputError = measured.meanSquared[l] * networkRatio;
            r.inputSamples = measured.samples[l];
            score.push_back(r.inputError);
        }
    } else {
        for (const LevelBest& b : levelBests) score.push_back(report.candidates[b.index].score());
    }
    // A broken input measurement (brokenInputMeasurement) never wins between levels; when
    // every level's is broken, the full image's score decides.
    if (input) {
        bool anyMeasured = false;
        for (size_t l = 0; l < levelBests.size(); ++l) {
            if (brokenInputMeasurement(report.candidates[levelBests[l].index]).empty())
                anyMeasured = true;
            else
                score[l] = std::numeric_limits<double>::infinity();
        }
        if (!anyMeasured)
            for (size_t l = 0; l < levelBests.size(); ++l) score[l] = report.candidates[levelBests[l].index].score();
    }
    size_t chosen = 0;
    for (size_t l = 1; l < levelBests.size(); ++l)
        if (score[l] < score[chosen]) chosen = l;
    return chosen;
}

// fitAssetToBytes with the colours kept where their smallest coding fits: the colours into
// their share, then each stored level's best geometry in the rest, then the level kept.
RateControlReport fitAssetToBytesOnce(Asset& asset, const std::vector<ChartBake>& charts, size_t targetBytes,
                                      uint32_t normalBits, std::span<const ShippedNetwork> shipped,
                                      const TriangleMesh* input)
{
    const std::string name = asset.sourceName.empty() ? "asset" : asset.sourceName;
    if (charts.size() != asset.charts.size())
        throw Error(name + ": rate control needs every chart's full-resolution images");
    const auto start = StopwatchClock::now();
    RateControlReport report;
    report.targetBytes = targetBytes;
    Asset colors;
    const bool anyColor = fitColorsFirst(asset, targetBytes, name, report, colors);
    Asset base = asset;
    for (AssetChart& chart : base.charts) chart.baseColor.clear();
    base.metadataJson = compactBakeMetadata(asset.metadataJson);
    const uint32_t resolution = asset.fullResolution();
    const uint32_t finest = 1,
                   coarsest = uint32_t(std::countr_zero(resolution / std::min(resolution, kCoarsestStoredResolution)));
    size_t smallest = SIZE_MAX;
    const std::vector<uint32_t> ladder = stepLadder();
    const SurfaceWeights weights = surfaceWeights(charts);
    std::vector<LevelBest> levelBests;
    for (uint32_t level = finest; level <= std::max(finest, coarsest); ++level)
        if (std::optional<LevelBest> b =
                bestAtLevel(base, charts, level, normalBits, shipped, ladder, weights, targetBytes, smallest, report))
            levelBests.push_back(std::move(*b));
    if (report.candidates.empty())
        throw Error(name + ": --target-bytes " + std::to_string(targetBytes) +
                    " is below the smallest asset this mesh makes (" + std::to_string(smallest) + " bytes)");
    const size_t chosen = chooseLevel(levelBests, weights, input, report);
    report.chosen = report.candidates[levelBests[chosen].index];
    Asset best = std::move(levelBests[chosen].asset);
    if (anyColor) {
        for (size_t c = 0; c < best.charts.size(); ++c) {
            best.charts[c].baseColor = std::move(colors.charts[c].baseColor);
            best.charts[c].baseColorLevel = colors.charts[c].baseColorLevel;
        }
        best.coding.colorQuality = colors.coding.colorQuality;
        report.chosen.bytes = serializeAsset(best).size();
    }
    asset = std::move(best);
    report.seconds = secondsSince(start);
    return report;
}

}  // namespace

RateControlReport fitAssetToBytes(Asset& asset, const std::vector<ChartBake>& charts, size_t targetBytes,
                                  uint32_t normalBits, std::span<const ShippedNetwork> shipped,
                                  const TriangleMesh* input)
{
    Asset attempt = asset;
    try {
        RateControlReport report = fitAssetToBytesOnce(attempt, charts, targetBytes, normalBits, shipped, input);
        asset = std::move(attempt);
        return report;
    } catch (const Error&) {
        // The shape first: where the colours leave it too little, they are dropped.
        if (!asset.hasBaseColors()) throw;
        for (AssetChart& chart : asset.charts) chart.baseColor.clear();
        RateControlReport report = fitAssetToBytesOnce(asset, charts, targetBytes, normalBits, shipped, input);
        report.colorWarning = "the base colours leave the shape too little of --target-bytes " +
            std::to_string(targetBytes) + ": they were dropped (the asset has its shape only)";
        return report;
    }
}

}  // namespace ngi
