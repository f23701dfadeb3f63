// ngi-bake --target-bytes (ngi/bake/rate_control.h): the asset never exceeds its budget, a
// larger budget never restores worse, a budget below the smallest asset is a clear error; the
// score weighs each sample by the surface it stands for (ngi/sample_surface_area.h); given the
// input, levels compete by the distance of their restores to it.
#include "ngi/asset.h"
#include "ngi/bake/network_choice.h"
#include "ngi/bake/rate_control.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/nn/feature_map.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/param/detail_transfer.h"
#include "ngi/sample_surface_area.h"

#include "tiny_network.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>

namespace {

// A bumpy cap at full resolution 64, normalized to [0, 1]^3, with its analytic normals.
void makeBake(ngi::Asset& asset, std::vector<ngi::ChartBake>& charts)
{
    asset.sourceName = "analytic:cap";
    asset.parameterization = "analytic";
    asset.metadataJson =
        R"({"bake":{"totalSeconds":1.5,"parameterization":{"areaDistortionMean":0.1},"clean":{"x":1}}})";
    ngi::ChartBake& bake = charts.emplace_back();
    bake.fullPositions = ngi::GeometryImage(65);
    bake.fullNormals = ngi::GeometryImage(65);
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const double u = x / 64.0 * 2 - 1, v = y / 64.0 * 2 - 1;
            const glm::dvec3 d = glm::normalize(glm::dvec3(u, v, 1.5));
            const double r = 1.0 + 0.04 * std::sin(9 * u) * std::cos(7 * v);
            bake.fullPositions.at(x, y) = glm::vec3(d * r * 0.45 + glm::dvec3(0.5, 0.5, 0.0));
            bake.fullNormals.at(x, y) = glm::vec3(d);
        }
    ngi::AssetChart& chart = asset.charts.emplace_back();
    chart.fullResolution = 64;
    chart.storedLevel = 2;
    ngi::storeGeometryImage(chart, ngi::GeometryImage(17), ngi::GeometryImage(17));
}

TEST(RateControl, NeverExceedsTheBudgetAndLargerBudgetsRestoreCloser)
{
    ngi::Asset baked;
    std::vector<ngi::ChartBake> charts;
    makeBake(baked, charts);
    double previous = INFINITY;
    size_t fitted = 0;
    for (size_t budget = 200; budget <= 12000; budget = budget * 5 / 4) {
        ngi::Asset asset = baked;
        try {
            const ngi::RateControlReport report = ngi::fitAssetToBytes(asset, charts, budget);
            const std::vector<uint8_t> bytes = ngi::serializeAsset(asset);
            EXPECT_LE(bytes.size(), budget);
            EXPECT_EQ(bytes.size(), report.chosen.bytes);
            EXPECT_LE(report.chosen.error, previous * 1.0001) << budget;
            previous = report.chosen.error;
            // What the file holds is what applyAssetCoding gives.
            ngi::Asset decoded = asset;
            ngi::applyAssetCoding(decoded);
            EXPECT_EQ(ngi::parseAsset(bytes, "fit.ngi").charts[0].positions, decoded.charts[0].positions);
            ++fitted;
        } catch (const ngi::Error& e) {
            EXPECT_EQ(fitted, 0u) << "a budget failed after a smaller one fitted: " << e.what();
            EXPECT_NE(std::string(e.what()).find("below the smallest asset"), std::string::npos) << e.what();
        }
    }
    EXPECT_GT(fitted, 5u);
}

TEST(RateControl, ScoresTheLevelAShippedNetworkRestoresByItsGainedRestore)
{
    ngi::Asset baked;
    std::vector<ngi::ChartBake> charts;
    makeBake(baked, charts);
    // An x4 network: it restores the 17^2 level (level 2) of the 64 image and no other.
    std::vector<ngi::ShippedNetwork> shipped(1);
    shipped[0].network = ngi::test::smallDefaultNetwork("rate-x4", 7, 0.2f);
    shipped[0].path = "rate-x4.ngiw";
    shipped[0].hash = ngi::networkHash(shipped[0].network);
    ngi::Asset asset = baked;
    ngi::reserveNetworkFields(asset, shipped);
    const size_t budget = 600;  // picks the 17^2 level at a coarse step (~180 units)
    const ngi::RateControlReport report = ngi::fitAssetToBytes(asset, charts, budget, 0, shipped);
    size_t measured = 0;
    for (const ngi::RateCandidate& c : report.candidates) {
        if (c.storedLevel != 2) {
            EXPECT_LT(c.networkError, 0.0) << "level " << c.storedLevel << " has no x4 restore";
            continue;
        }
        if (c.networkError < 0.0) continue;
        ++measured;
        EXPECT_EQ(c.networkId, "rate-x4");
        // The gain is clamped to [0, 1] and fitted by least squares: never worse than bicubic.
        EXPECT_LE(c.networkError, c.error * (1.0 + 1e-6));
        EXPECT_GT(c.error, 0.0);
    }
    EXPECT_EQ(measured, 1u) << "one reference forward for the level's best bicubic candidate";
    double smallest = INFINITY;
    for (const ngi::RateCandidate& c : report.candidates) smallest = std::min(smallest, c.score());
    EXPECT_EQ(report.chosen.score(), smallest);
    EXPECT_LE(ngi::serializeAsset(asset).size(), budget);

    // The final naming fits the gain on what a reader decodes: its bicubic error is the rate
    // control's for the chosen candidate (the fit on the uncoded samples would differ by the
    // coding error, which at this budget is most of it).
    if (report.chosen.storedLevel == 2) {
        const ngi::NetworkChoice choice = ngi::nameNetworkAndFitGains(asset, charts, shipped);
        ASSERT_NE(choice.named, nullptr);
        EXPECT_EQ(asset.networkId, "rate-x4");
        ASSERT_TRUE(choice.gains[0].has_value());
        EXPECT_NEAR(choice.gains[0]->rmsCubic * choice.gains[0]->rmsCubic, report.chosen.error,
                    1e-6 * report.chosen.error);
        if (report.chosen.networkError >= 0.0) {
            EXPECT_NEAR(choice.gains[0]->rmsGained * choice.gains[0]->rmsGained, report.chosen.networkError,
                        1e-6 * report.chosen.networkError);
        }
        EXPECT_EQ(asset.charts[0].residualGain, choice.gains[0]->gain);
    } else {
        ADD_FAILURE() << "the budget was meant to pick the 17^2 level; it picked level " << report.chosen.storedLevel;
    }
}

TEST(RateControl, CompactMetadataKeepsWhatTheReportReads)
{
    const std::string compact = ngi::compactBakeMetadata(
        R"({"bake":{"totalSeconds":2.5,"parameterization":{"areaDistortionMean":0.1,"otIterations":9},"clean":{}},"seams":[1,2]})");
    EXPECT_EQ(compact, R"({"bake":{"parameterization":{"areaDistortionMean":0.1},"totalSeconds":2.5}})");
    EXPECT_EQ(ngi::compactBakeMetadata("not json"), "{}");
}

TEST(RateControl, ChunkBytesAddUpToTheFile)
{
    ngi::Asset baked;
    std::vector<ngi::ChartBake> charts;
    makeBake(baked, charts);
    ngi::fitAssetToBytes(baked, charts, 4000);
    const std::vector<uint8_t> bytes = ngi::serializeAsset(baked);
    // Every chunk's payload after the header, the table and the chunk before it (alignment:
    // under 8 bytes each), the last one ending the file.
    const std::vector<ngi::AssetChunkSize> chunks = ngi::assetChunkSizes(bytes, "fitted.ngi");
    uint64_t end = 24 + 32 * chunks.size();
    for (const ngi::AssetChunkSize& chunk : chunks) {
        EXPECT_GE(chunk.offset, end) << chunk.name;
        EXPECT_LT(chunk.offset, end + 8) << chunk.name;
        end = chunk.offset + chunk.bytes;
    }
    EXPECT_EQ(end, bytes.size());
}

// A plane z = 0.5 whose image rows are unevenly spaced on the surface: row y sits at
// s = rowS(y). Exact per-sample areas of a planar grid: each cell's area to its corners by quarters.
TEST(SampleSurfaceArea, PlanarCellsGiveEachCornerAQuarterAndWeightsAverageOne)
{
    const auto rowS = [](uint32_t y) { return 0.01 * y * y; };
    ngi::GeometryImage image(5);
    for (uint32_t y = 0; y < 5; ++y)
        for (uint32_t x = 0; x < 5; ++x) image.at(x, y) = glm::vec3(0.1f * x, float(rowS(y)), 0.5f);
    const std::vector<double> area = ngi::sampleSurfaceAreas(image);
    ASSERT_EQ(area.size(), 25u);
    const auto cell = [&](uint32_t y) { return 0.1 * (rowS(y + 1) - rowS(y)); };  // row y's cells
    EXPECT_NEAR(area[0], cell(0) / 4, 1e-7);                                      // a corner: one cell
    EXPECT_NEAR(area[2], cell(0) / 2, 1e-7);                                      // a border sample: two
    EXPECT_NEAR(area[2 * 5 + 2], (cell(1) + cell(2)) / 2, 1e-7);                  // inside: four
    double sum = 0.0;
    for (const double a : area) sum += a;
    EXPECT_NEAR(sum, 0.4 * rowS(4), 1e-6);  // the plane's area
    const std::vector<double> w = ngi::surfaceAreaWeights(image);
    double mean = 0.0;
    for (const double v : w) mean += v / 25.0;
    EXPECT_NEAR(mean, 1.0, 1e-12);
    EXPECT_NEAR(w[24] / w[0], area[24] / area[0], 1e-9);
    // No area at all: equal weights.
    for (const double v : ngi::surfaceAreaWeights(ngi::GeometryImage(4))) EXPECT_EQ(v, 1.0);
}

// A sheet whose last 8 of 64 image rows hold 8/9 of its surface (each of their cells has 56x the
// area of one in the first 56 rows) and carry a bump the coarse levels lose: a tail
// squeezed into few samples, as the OT map does on diplodocus.
void makeStretchedBake(ngi::Asset& asset, std::vector<ngi::ChartBake>& charts)
{
    asset.sourceName = "analytic:stretched";
    asset.parameterization = "analytic";
    asset.metadataJson = R"({"bake":{"totalSeconds":1.0}})";
    ngi::ChartBake& bake = charts.emplace_back();
    bake.fullPositions = ngi::GeometryImage(65);
    bake.fullNormals = ngi::GeometryImage(65);
    const double pi = std::numbers::pi;
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const double u = x / 64.0;
            const double s = y <= 56 ? 0.1 * y / 56.0 : 0.1 + 0.8 * (y - 56) / 8.0;  // in [0, 0.9]
            const double t = std::max(0.0, (s - 0.1) / 0.8);                         // the tail, in [0, 1]
            const double a = 0.03;
            const double z = 0.5 + a * std::sin(pi * t) * std::sin(2 * pi * t) * std::sin(2 * pi * u);
            // d z / d s and d z / d u (x = 0.05 + 0.9 u, y = 0.05 + s)
            const double dzdt = a * pi *
                (std::cos(pi * t) * std::sin(2 * pi * t) + 2 * std::sin(pi * t) * std::cos(2 * pi * t)) *
                std::sin(2 * pi * u);
            const double dzds = s > 0.1 ? dzdt / 0.8 : 0.0;
            const double dzdx = a * std::sin(pi * t) * std::sin(2 * pi * t) * 2 * pi * std::cos(2 * pi * u) / 0.9;
            bake.fullPositions.at(x, y) = glm::vec3(float(0.05 + 0.9 * u), float(0.05 + s), float(z));
            bake.fullNormals.at(x, y) = glm::vec3(glm::normalize(glm::dvec3(-dzdx, -dzds, 1.0)));
        }
    ngi::AssetChart& chart = asset.charts.emplace_back();
    chart.fullResolution = 64;
    chart.storedLevel = 2;
    ngi::storeGeometryImage(chart, ngi::GeometryImage(17), ngi::GeometryImage(17));
}

// Chart `chart`'s mean squared point-to-plane error of the bicubic restore of candidate `c`,
// computed here from the candidate's own stored level and step (every chart stored at it and
// coded as a reader decodes them; the charts here are 65^2): weighted by `weights`.
double restoreError(const ngi::Asset& baked, const std::vector<ngi::ChartBake>& charts, const ngi::RateCandidate& c,
                    const std::vector<double>& weights, size_t chart = 0)
{
    ngi::Asset a = baked;
    a.coding = {.pyramid = true,
                .positionStep = c.step,
                .positionTangentScale = c.tangentScale,
                .positionStepGrade = c.stepGrade};
    for (size_t k = 0; k < charts.size(); ++k) {
        a.charts[k].storedLevel = c.storedLevel;
        ngi::storeGeometryImage(a.charts[k], ngi::downsampleNested(charts[k].fullPositions, c.storedLevel),
                                ngi::downsampleNested(charts[k].fullNormals, c.storedLevel));
    }
    ngi::applyAssetCoding(a);
    const ngi::nn::FeatureMap coarse = ngi::nn::featureMapFromGeometryImage(ngi::storedPositions(a.charts[chart]));
    const ngi::GeometryImage restored = ngi::nn::geometryImageFromFeatureMap(
        ngi::nn::cubicSkip(coarse, ngi::nn::FeatureMap(3, 65, 65), 1u << c.storedLevel));
    const ngi::ChartBake& bake = charts[chart];
    double sum = 0.0;
    for (size_t i = 0; i < restored.texels.size(); ++i) {
        const double d = glm::dot(glm::dvec3(restored.texels[i] - bake.fullPositions.texels[i]),
                                  glm::dvec3(bake.fullNormals.texels[i]));
        sum += weights[i] * d * d;
    }
    return sum / double(restored.texels.size());
}

TEST(RateControl, ScoresEachSampleByTheSurfaceItStandsFor)
{
    ngi::Asset baked;
    std::vector<ngi::ChartBake> charts;
    makeStretchedBake(baked, charts);
    const std::vector<double> surface = ngi::surfaceAreaWeights(charts[0].fullPositions);
    const std::vector<double> equal(surface.size(), 1.0);
    EXPECT_NEAR(surface.back() / surface.front(), 56.0, 56.0 * 0.02) << "the tail's corner vs the head's";
    size_t finer = 0;
    // From the smallest asset (~370 B) to where the 33^2 level fits losslessly.
    for (size_t budget = 380; budget <= 1500; budget = budget * 9 / 8) {
        ngi::Asset asset = baked;
        const ngi::RateControlReport report = ngi::fitAssetToBytes(asset, charts, budget);
        // Compared among the uniform-step candidates (grade 1), where the fixture was measured:
        // the graded ones move both choices alike.
        const ngi::RateCandidate* equalBest = nullptr;
        const ngi::RateCandidate* weightedBest = nullptr;
        double equalBestError = INFINITY;
        for (const ngi::RateCandidate& c : report.candidates) {
            // The score is the surface-weighted error (to rounding: 1e-6 relative).
            const double weighted = restoreError(baked, charts, c, surface),
                         unweighted = restoreError(baked, charts, c, equal);
            EXPECT_NEAR(c.error, weighted, 1e-6 * weighted)
                << budget << " B, level " << c.storedLevel << " step " << c.step;
            if (c.stepGrade != 1.0) continue;
            if (unweighted < equalBestError) equalBestError = unweighted, equalBest = &c;
            if (!weightedBest || c.error < weightedBest->error) weightedBest = &c;
            // At a fine step the restore's own error dominates and sits in the tail, which weighs
            // several times its share of the image (~7x measured; coarse steps add noise evenly).
            if (c.step <= 16) {
                EXPECT_GT(weighted, 3.0 * unweighted) << budget << " B, level " << c.storedLevel;
            }
        }
        ASSERT_NE(equalBest, nullptr);
        ASSERT_NE(weightedBest, nullptr);
        // Where the choice differs from the image's equal weights, it keeps the finer level
        // (the tail's detail) at a coarser step.
        if (equalBest->storedLevel != weightedBest->storedLevel) {
            EXPECT_LT(weightedBest->storedLevel, equalBest->storedLevel) << budget << " B";
            ++finer;
        }
    }
    // Measured: at 427 and 480 B equal weights keep 9^2 and 17^2 at a fine step, the surface
    // weights 17^2 and 33^2 at a coarse one.
    EXPECT_GE(finer, 1u) << "the fixture no longer makes the weighting change a choice";
}

// Two charts: the stretched sheet and the bumpy cap shrunk to half its size (a quarter of its
// area). The score sums the charts' surface-weighted errors by their share of the surface, not
// of the samples (both charts have 65^2).
TEST(RateControl, SumsChartsByTheirShareOfTheSurface)
{
    ngi::Asset baked, cap;
    std::vector<ngi::ChartBake> charts, capCharts;
    makeStretchedBake(baked, charts);
    makeBake(cap, capCharts);
    for (glm::vec3& p : capCharts[0].fullPositions.texels) p = 0.5f * p + glm::vec3(0.25f);
    charts.push_back(capCharts[0]);
    baked.charts.push_back(cap.charts[0]);
    double area[2] = {0.0, 0.0};
    for (size_t k = 0; k < 2; ++k)
        for (const double a : ngi::sampleSurfaceAreas(charts[k].fullPositions)) area[k] += a;
    const double share0 = area[0] / (area[0] + area[1]);
    ASSERT_GT(share0, 0.6) << "the sheet holds most of the surface";
    ngi::Asset asset = baked;
    const ngi::RateControlReport report = ngi::fitAssetToBytes(asset, charts, 1500);
    ASSERT_FALSE(report.candidates.empty());
    size_t distinct = 0;
    for (const ngi::RateCandidate& c : report.candidates) {
        const double e0 = restoreError(baked, charts, c, ngi::surfaceAreaWeights(charts[0].fullPositions), 0);
        const double e1 = restoreError(baked, charts, c, ngi::surfaceAreaWeights(charts[1].fullPositions), 1);
        const double expected = share0 * e0 + (1.0 - share0) * e1;
        EXPECT_NEAR(c.error, expected, 1e-6 * expected) << "level " << c.storedLevel << " step " << c.step;
        // The samples' share (1/2 each) would give a different score wherever the charts differ.
        if (std::abs(e0 - e1) > 0.5 * std::max(e0, e1)) {
            EXPECT_GT(std::abs(c.error - 0.5 * (e0 + e1)), 1e-3 * expected) << "level " << c.storedLevel;
            ++distinct;
        }
    }
    EXPECT_GE(distinct, 1u) << "no candidate tells the surface's shares from the samples'";
}

}  // namespace

// A full image that is not the input: the smooth cap (the input, a fine mesh of it) with streaks
// of its own, +kNoise along the normal on the columns x = 2 mod 8 and -kNoise on x = 6 mod 8, as a map-limited bake's
// image carries errors the input does not have. The 33^2 level stores the streaks and restores
// half of them between its samples: closest to the full image. The coarser levels store clean
// columns only: farther from the image, closest to the input. Given the input, the rate control
// chooses between levels by the distance to it.
TEST(RateControl, GivenTheInputChoosesTheLevelClosestToIt)
{
    constexpr double kNoise = 0.004;
    auto cap = [](double u, double v) { return glm::normalize(glm::dvec3(u, v, 1.5)); };
    ngi::Asset baked;
    std::vector<ngi::ChartBake> charts;
    makeBake(baked, charts);
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const double sign = x % 8 == 2 ? 1.0 : x % 8 == 6 ? -1.0 : 0.0;
            const glm::dvec3 d = cap(x / 64.0 * 2 - 1, y / 64.0 * 2 - 1);
            charts[0].fullPositions.at(x, y) = glm::vec3(d * (0.45 + sign * kNoise) + glm::dvec3(0.5, 0.5, 0.0));
        }
    // The input: the same cap without noise, 8x finer than the image (asset frame = object frame).
    ngi::GeometryImage smooth(513);
    for (uint32_t y = 0; y < 513; ++y)
        for (uint32_t x = 0; x < 513; ++x)
            smooth.at(x, y) = glm::vec3(cap(x / 512.0 * 2 - 1, y / 512.0 * 2 - 1) * 0.45 + glm::dvec3(0.5, 0.5, 0.0));
    const ngi::TriangleMesh input = ngi::geometryImageMesh(smooth);

    // Mean squared distance to the input of an asset's bicubic restore, every sample.
    auto distanceToInput = [&](const ngi::Asset& asset) {
        ngi::Asset decoded = asset;
        ngi::applyAssetCoding(decoded);
        const ngi::AssetChart& chart = decoded.charts[0];
        const ngi::nn::FeatureMap coarse = ngi::nn::featureMapFromGeometryImage(ngi::storedPositions(chart));
        const ngi::GeometryImage restored = ngi::nn::geometryImageFromFeatureMap(
            ngi::nn::cubicSkip(coarse, ngi::nn::FeatureMap(3, 65, 65), 1u << chart.storedLevel));
        std::vector<glm::dvec3> points(restored.texels.begin(), restored.texels.end());
        double sum = 0.0;
        for (const double d2 : ngi::squaredDistancesToSurface(input, points)) sum += d2;
        return sum / double(points.size());
    };

    const size_t budget = 20000;  // every level fits at a fine step
    ngi::Asset imageChoice = baked, inputChoice = baked;
    const ngi::RateControlReport byImage = ngi::fitAssetToBytes(imageChoice, charts, budget);
    const ngi::RateControlReport byInput = ngi::fitAssetToBytes(inputChoice, charts, budget, 0, {}, &input);
    EXPECT_EQ(byImage.chosen.storedLevel, 1u) << "the full image's score keeps the noise: the finest level";
    for (const ngi::RateCandidate& c : byImage.candidates)
        EXPECT_LT(c.inputError, 0.0) << "not measured without the input";
    EXPECT_GT(byInput.chosen.storedLevel, 1u) << "the input's score prefers a level that averages the noise away";
    EXPECT_LE(ngi::serializeAsset(inputChoice).size(), budget);
    // Each level's best was measured against the input, and the chosen one is the smallest of them.
    size_t measured = 0;
    const ngi::RateCandidate* finest = nullptr;
    for (const ngi::RateCandidate& c : byInput.candidates) {
        if (c.inputError < 0.0) continue;
        ++measured;
        if (c.storedLevel == 1) finest = &c;
        EXPECT_GE(c.inputError, byInput.chosen.inputError) << "level " << c.storedLevel;
    }
    EXPECT_EQ(measured, 3u) << "one per level (33^2, 17^2, 9^2)";
    // Measured independently, at every sample: the input's choice restores closer to the input
    // (33^2: a quarter of the samples streaked by kNoise, half by 0.625 kNoise; the coarser
    // levels only the cap's own interpolation error).
    const double imageDistance = distanceToInput(imageChoice), inputDistance = distanceToInput(inputChoice);
    EXPECT_GT(imageDistance, 0.2 * kNoise * kNoise);
    EXPECT_LT(inputDistance, 0.1 * imageDistance)
        << "input's choice " << inputDistance << ", image's " << imageDistance;
    // The score reported for the 33^2 level (the image's choice: the same candidate) is that
    // distance, estimated from every third sample, within 25%.
    ASSERT_NE(finest, nullptr);
    EXPECT_EQ(finest->step, byImage.chosen.step);
    EXPECT_NEAR(finest->inputError, imageDistance, 0.25 * imageDistance);
}

TEST(RateControl, OfTwoBakesKeepsTheOneCloserToTheInputAndTheFirstOnATie)
{
    // ngi-bake --target-bytes' thin-part choice and the report's budget rows (fitCloserOfTwoBakes):
    // a clean cap against a cap with a broad bump (no level averages it away), the input being
    // the clean cap.
    auto cap = [](double u, double v) { return glm::normalize(glm::dvec3(u, v, 1.5)); };
    ngi::Asset clean, noisy;  // noisy: the bumped cap
    std::vector<ngi::ChartBake> cleanCharts, noisyCharts;
    makeBake(clean, cleanCharts);
    makeBake(noisy, noisyCharts);
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const glm::dvec3 d = cap(x / 64.0 * 2 - 1, y / 64.0 * 2 - 1);
            cleanCharts[0].fullPositions.at(x, y) = glm::vec3(d * 0.45 + glm::dvec3(0.5, 0.5, 0.0));
            const double bump = 0.02 * std::sin(3.0 * x / 64.0) * std::cos(2.0 * y / 64.0);
            noisyCharts[0].fullPositions.at(x, y) = glm::vec3(d * (0.45 + bump) + glm::dvec3(0.5, 0.5, 0.0));
        }
    ngi::GeometryImage smooth(257);
    for (uint32_t y = 0; y < 257; ++y)
        for (uint32_t x = 0; x < 257; ++x)
            smooth.at(x, y) = glm::vec3(cap(x / 256.0 * 2 - 1, y / 256.0 * 2 - 1) * 0.45 + glm::dvec3(0.5, 0.5, 0.0));
    const ngi::TriangleMesh input = ngi::geometryImageMesh(smooth);
    const size_t budget = 6000;

    ngi::Asset a = clean, b = noisy;
    const ngi::BudgetChoice cleanFirst =
        ngi::fitCloserOfTwoBakes(a, cleanCharts, &b, &noisyCharts, budget, 0, {}, input);
    ASSERT_TRUE(cleanFirst.second.has_value());
    EXPECT_LT(cleanFirst.first.chosen.inputError, 0.5 * cleanFirst.second->chosen.inputError);
    EXPECT_TRUE(cleanFirst.keptFirst);
    EXPECT_EQ(&cleanFirst.kept(), &cleanFirst.first);
    EXPECT_LE(ngi::serializeAsset(a).size(), budget);
    EXPECT_LE(ngi::serializeAsset(b).size(), budget) << "both are fitted to the budget";

    ngi::Asset c = noisy, d = clean;
    const ngi::BudgetChoice noisyFirst =
        ngi::fitCloserOfTwoBakes(c, noisyCharts, &d, &cleanCharts, budget, 0, {}, input);
    EXPECT_FALSE(noisyFirst.keptFirst);
    EXPECT_EQ(&noisyFirst.kept(), &*noisyFirst.second);
    EXPECT_EQ(noisyFirst.second->chosen.inputError, cleanFirst.first.chosen.inputError)
        << "the same bake, the same fit";

    ngi::Asset e = clean, f = clean;
    EXPECT_TRUE(ngi::fitCloserOfTwoBakes(e, cleanCharts, &f, &cleanCharts, budget, 0, {}, input).keptFirst) << "a tie";
    EXPECT_EQ(ngi::serializeAsset(e), ngi::serializeAsset(f));

    ngi::Asset alone = noisy;
    const ngi::BudgetChoice single =
        ngi::fitCloserOfTwoBakes(alone, noisyCharts, nullptr, nullptr, budget, 0, {}, input);
    EXPECT_TRUE(single.keptFirst);
    EXPECT_FALSE(single.second.has_value());
    ngi::Asset g = clean, h = clean;
    EXPECT_THROW(ngi::fitCloserOfTwoBakes(g, cleanCharts, &h, nullptr, budget, 0, {}, input), ngi::Error);
}

TEST(RateControl, ABrokenInputMeasurementIsNamedAndNeverComparable)
{
    ngi::RateCandidate measured;
    measured.inputError = 1e-8;
    measured.inputSamples = 400;
    EXPECT_EQ(ngi::brokenInputMeasurement(measured), "") << "a real measurement";
    auto broken = [&](double inputError, size_t samples) {
        ngi::RateCandidate c = measured;
        c.inputError = inputError;
        c.inputSamples = samples;
        return ngi::brokenInputMeasurement(c);
    };
    EXPECT_NE(broken(0.0, 400).find("exactly 0"), std::string::npos);
    EXPECT_NE(broken(std::nan(""), 400).find("NaN"), std::string::npos);
    EXPECT_NE(broken(INFINITY, 400).find("infinite"), std::string::npos);
    EXPECT_NE(broken(-1.0, 400).find("not measured"), std::string::npos);
    EXPECT_NE(broken(1e-8, 0).find("no samples"), std::string::npos);
}

TEST(RateControl, OfTwoBakesOneMeasuredAtExactlyZeroLosesToAFarCloserOne)
{
    // A one-sided measure can read exactly 0 for a bake that is far worse: here the second bake
    // is a flat patch lying exactly in the input's plane z = 0, and the input is the clean cap plus
    // that patch. The patch misses the whole cap (its Chamfer distance to the input is that of
    // a missing part), but each of its restored samples lies on the input: its distance reads 0.
    // The clean cap's restore measures its own small interpolation error. The cap must be kept,
    // whichever order the two come in, and the loss must say why.
    auto cap = [](double u, double v) { return glm::normalize(glm::dvec3(u, v, 1.5)); };
    ngi::Asset clean, patch;
    std::vector<ngi::ChartBake> cleanCharts, patchCharts;
    makeBake(clean, cleanCharts);
    makeBake(patch, patchCharts);
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            cleanCharts[0].fullPositions.at(x, y) =
                glm::vec3(cap(x / 64.0 * 2 - 1, y / 64.0 * 2 - 1) * 0.45 + glm::dvec3(0.5, 0.5, 0.0));
            patchCharts[0].fullPositions.at(x, y) = glm::vec3(0.25f + 0.5f * x / 64.0f, 0.25f + 0.5f * y / 64.0f, 0.0f);
            patchCharts[0].fullNormals.at(x, y) = glm::vec3(0.0f, 0.0f, 1.0f);
        }
    ngi::GeometryImage smooth(257);
    for (uint32_t y = 0; y < 257; ++y)
        for (uint32_t x = 0; x < 257; ++x)
            smooth.at(x, y) = glm::vec3(cap(x / 256.0 * 2 - 1, y / 256.0 * 2 - 1) * 0.45 + glm::dvec3(0.5, 0.5, 0.0));
    ngi::TriangleMesh input = ngi::geometryImageMesh(smooth);
    const uint32_t base = uint32_t(input.positions.size());
    for (const glm::dvec3 corner : {glm::dvec3(0, 0, 0), glm::dvec3(1, 0, 0), glm::dvec3(1, 1, 0), glm::dvec3(0, 1, 0)})
        input.positions.push_back(corner);
    input.triangles.push_back({base, base + 1, base + 2});
    input.triangles.push_back({base, base + 2, base + 3});
    const size_t budget = 6000;

    ngi::Asset a = clean, b = patch;
    const ngi::BudgetChoice cleanFirst =
        ngi::fitCloserOfTwoBakes(a, cleanCharts, &b, &patchCharts, budget, 0, {}, input);
    ASSERT_TRUE(cleanFirst.second.has_value());
    // The cap's interpolation error at this budget is a real, positive measurement (RMS well
    // under 1% of the unit box); the patch's is exactly 0 over its samples.
    EXPECT_EQ(ngi::brokenInputMeasurement(cleanFirst.first.chosen), "");
    EXPECT_GT(cleanFirst.first.chosen.inputError, 0.0);
    EXPECT_LT(cleanFirst.first.chosen.inputError, 1e-4);
    EXPECT_GT(cleanFirst.second->chosen.inputSamples, 0u);
    EXPECT_EQ(cleanFirst.second->chosen.inputError, 0.0) << "the patch's restore lies in the input's plane";
    EXPECT_TRUE(cleanFirst.keptFirst) << "0 would have won the plain comparison";
    ASSERT_EQ(cleanFirst.warnings.size(), 1u);
    EXPECT_NE(cleanFirst.warnings[0].find("the second bake"), std::string::npos) << cleanFirst.warnings[0];
    EXPECT_NE(cleanFirst.warnings[0].find("exactly 0"), std::string::npos) << cleanFirst.warnings[0];

    ngi::Asset c = patch, d = clean;
    const ngi::BudgetChoice patchFirst =
        ngi::fitCloserOfTwoBakes(c, patchCharts, &d, &cleanCharts, budget, 0, {}, input);
    EXPECT_FALSE(patchFirst.keptFirst) << "the first bake loses too when its measurement is the broken one";
    ASSERT_EQ(patchFirst.warnings.size(), 1u);
    EXPECT_NE(patchFirst.warnings[0].find("the first bake"), std::string::npos) << patchFirst.warnings[0];
    EXPECT_EQ(ngi::serializeAsset(d), ngi::serializeAsset(a)) << "the kept cap is the same fit either way";

    // Both broken: the first is kept, and the warning names both.
    ngi::Asset e = patch, f = patch;
    const ngi::BudgetChoice bothBroken =
        ngi::fitCloserOfTwoBakes(e, patchCharts, &f, &patchCharts, budget, 0, {}, input);
    EXPECT_TRUE(bothBroken.keptFirst);
    ASSERT_EQ(bothBroken.warnings.size(), 1u);
    EXPECT_NE(bothBroken.warnings[0].find("neither"), std::string::npos) << bothBroken.warnings[0];

    // Two real measurements compare as before, without a warning.
    ngi::Asset g = clean, h = clean;
    EXPECT_TRUE(ngi::fitCloserOfTwoBakes(g, cleanCharts, &h, &cleanCharts, budget, 0, {}, input).warnings.empty());
}

TEST(RateControl, ANetworksGainScalesTheInputScoreAndNeverDrivesItToZero)
{
    // The network's gain is measured against the full image; where the full image is far from
    // the input (here: streaks of noise every 8 columns that the input does not have and the
    // 17^2 level averages away; in a bake, a squeezed thin part), subtracting that gain from the
    // input score drives it below zero: a one-chart bake measured at exactly 0 won the budget
    // choice. As a ratio it scales the bicubic's input score: positive, and no larger.
    auto cap = [](double u, double v) { return glm::normalize(glm::dvec3(u, v, 1.5)); };
    ngi::Asset baked;
    std::vector<ngi::ChartBake> charts;
    makeBake(baked, charts);
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const double sign = x % 8 == 2 ? 1.0 : x % 8 == 6 ? -1.0 : 0.0;
            charts[0].fullPositions.at(x, y) =
                glm::vec3(cap(x / 64.0 * 2 - 1, y / 64.0 * 2 - 1) * (0.45 + sign * 0.004) + glm::dvec3(0.5, 0.5, 0.0));
        }
    ngi::GeometryImage smooth(257);
    for (uint32_t y = 0; y < 257; ++y)
        for (uint32_t x = 0; x < 257; ++x)
            smooth.at(x, y) = glm::vec3(cap(x / 256.0 * 2 - 1, y / 256.0 * 2 - 1) * 0.45 + glm::dvec3(0.5, 0.5, 0.0));
    const ngi::TriangleMesh input = ngi::geometryImageMesh(smooth);
    std::vector<ngi::ShippedNetwork> shipped(1);
    shipped[0].network = ngi::test::smallDefaultNetwork("rate-x4", 7, 0.2f);
    shipped[0].path = "rate-x4.ngiw";
    shipped[0].hash = ngi::networkHash(shipped[0].network);
    ngi::Asset withNetwork = baked, bicubicOnly = baked;
    ngi::reserveNetworkFields(withNetwork, shipped);
    ngi::reserveNetworkFields(bicubicOnly, shipped);
    const size_t budget = 20000;
    const ngi::RateControlReport gained = ngi::fitAssetToBytes(withNetwork, charts, budget, 0, shipped, &input);
    const ngi::RateControlReport plain = ngi::fitAssetToBytes(bicubicOnly, charts, budget, 0, {}, &input);
    size_t networkLevels = 0, compared = 0;
    for (const ngi::RateCandidate& c : gained.candidates) {
        if (c.inputError < 0.0) continue;
        EXPECT_EQ(ngi::brokenInputMeasurement(c), "") << "level " << c.storedLevel;
        if (c.networkError < 0.0) continue;
        ++networkLevels;
        for (const ngi::RateCandidate& p : plain.candidates)
            if (p.inputError >= 0.0 && p.storedLevel == c.storedLevel && p.step == c.step &&
                p.tangentScale == c.tangentScale && p.stepGrade == c.stepGrade) {
                ++compared;
                // The case this guards: the gain against the full image exceeds the whole input
                // score, so the difference would be negative (and clamped to an exact 0).
                EXPECT_LT(p.inputError + c.networkError - c.error, 0.0);
                EXPECT_GT(c.inputError, 0.0);
                // Within 1e-9 relative: the same samples, scaled by networkError / error <= 1.
                EXPECT_NEAR(c.inputError, p.inputError * c.networkError / c.error, 1e-9 * p.inputError);
                EXPECT_LE(c.inputError, p.inputError * (1.0 + 1e-9));
            }
    }
    EXPECT_EQ(networkLevels, 1u) << "the x4 network restores the 17^2 level only";
    EXPECT_EQ(compared, 1u) << "the bicubic-only fit measured the same candidate of that level";
}

TEST(RateControl, ColouredChartsWithoutResidualGainsStayWithinTheBudget)
{
    // Many coloured charts, none with a residual gain (no network shipped): the colours' chunks,
    // padding and table entries (in format 8 also 4 bytes more per chart entry, which once put a
    // 53-chart model 20 bytes over its budget) must be left to them by the shape's fit.
    ngi::Asset one;
    std::vector<ngi::ChartBake> oneBake;
    makeBake(one, oneBake);
    ngi::Asset baked = one;
    baked.charts.clear();
    std::vector<ngi::ChartBake> charts;
    for (uint32_t c = 0; c < 24; ++c) {
        ngi::AssetChart chart = one.charts[0];
        chart.baseColorLevel = 2;  // 17^2
        const uint32_t n = chart.baseColorSize();
        chart.baseColor.resize(size_t(n) * n * 4);
        for (size_t i = 0; i < chart.baseColor.size(); ++i) chart.baseColor[i] = uint8_t((i * 37 + c * 101) % 251);
        baked.charts.push_back(chart);
        charts.push_back(oneBake[0]);
    }
    size_t fitted = 0;
    for (size_t budget = 4000; budget <= 40000; budget = budget * 5 / 4) {
        ngi::Asset asset = baked;
        ngi::RateControlReport report;
        try {
            report = ngi::fitAssetToBytes(asset, charts, budget);
        } catch (const ngi::Error&) {
            continue;  // below the smallest asset: not this test's concern
        }
        ++fitted;
        const std::vector<uint8_t> bytes = ngi::serializeAsset(asset);
        EXPECT_LE(bytes.size(), budget);
        EXPECT_EQ(bytes.size(), report.chosen.bytes);
        if (!report.color.present) continue;
        // The report's colour bytes are what the colours add to this very file, up to twice the
        // 7 bytes of alignment before their first chunk (in the file measured and in this one).
        ngi::Asset shapeOnly = asset;
        for (ngi::AssetChart& chart : shapeOnly.charts) chart.baseColor.clear();
        const size_t added = bytes.size() - ngi::serializeAsset(shapeOnly).size();
        EXPECT_GE(report.color.bytes, added) << budget;
        EXPECT_LE(report.color.bytes, added + 14) << budget;
    }
    EXPECT_GE(fitted, 5u);
}

TEST(RateControl, BaseColoursTakeAtMostTheirShareAndLargerBudgetsKeepThemCloser)
{
    ngi::Asset baked;
    std::vector<ngi::ChartBake> charts;
    makeBake(baked, charts);
    // A 65^2 colour image with detail at every scale (rings), so it does not code to nothing.
    ngi::AssetChart& chart = baked.charts[0];
    chart.baseColorLevel = 0;
    const uint32_t n = chart.baseColorSize();
    chart.baseColor.resize(size_t(n) * n * 4);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const double r = std::hypot(x - 32.0, y - 32.0);
            uint8_t* t = &chart.baseColor[(size_t(y) * n + x) * 4];
            t[0] = uint8_t(128 + 120 * std::sin(r / 2.0)), t[1] = uint8_t(4 * x), t[2] = uint8_t(4 * y), t[3] = 255;
        }
    double previous = INFINITY;
    for (size_t budget : {4000, 8000, 16000, 32000}) {
        ngi::Asset asset = baked;
        const ngi::RateControlReport report = ngi::fitAssetToBytes(asset, charts, budget);
        const std::vector<uint8_t> bytes = ngi::serializeAsset(asset);
        EXPECT_LE(bytes.size(), budget);
        EXPECT_EQ(bytes.size(), report.chosen.bytes);
        ASSERT_TRUE(report.color.present);
        EXPECT_LE(report.color.bytes, size_t(double(budget) * ngi::kColorBudgetShare)) << budget;
        EXPECT_LE(report.color.rms, previous + 1e-9) << budget;
        previous = report.color.rms;
        // The file holds the colour the report measured: the chosen level and quality.
        const ngi::Asset read = ngi::parseAsset(bytes, "coloured.ngi");
        EXPECT_EQ(read.charts[0].baseColorLevel, report.color.levelsCoarser);
        EXPECT_EQ(read.charts[0].baseColorSize(), (64u >> report.color.levelsCoarser) + 1);
    }
    // Measured: 4 KB 10.0 (quality 68), 8 KB 8.5 (96), 16 KB lossless (a 65^2 image in 3.8 KB).
    EXPECT_EQ(previous, 0.0) << "32 KB keeps the 65^2 image lossless";
    // A budget whose quarter cannot hold even the coarsest colour gives it up to half, with a
    // warning; below that the colours are dropped, never the shape.
    const ngi::Asset grey = [&] {
        ngi::Asset a = baked;
        a.charts[0].baseColor.clear();
        return a;
    }();
    ngi::Asset shapeOnly = grey;
    const size_t shapeBytes = ngi::fitAssetToBytes(shapeOnly, charts, 900).chosen.bytes;
    // Measured: the shape alone needs 412 bytes at the least, the colour 97; in 450 bytes the
    // colour would leave the shape too little.
    ngi::Asset tight = baked;
    const ngi::RateControlReport dropped = ngi::fitAssetToBytes(tight, charts, 450);
    EXPECT_FALSE(dropped.color.present);
    EXPECT_NE(dropped.colorWarning.find("were dropped"), std::string::npos) << dropped.colorWarning;
    EXPECT_TRUE(tight.charts[0].baseColor.empty());
    EXPECT_LE(ngi::serializeAsset(tight).size(), 450u);
    // In 600 bytes the colour takes its 97 bytes, its share being 150.
    ngi::Asset roomy = baked;
    EXPECT_TRUE(ngi::fitAssetToBytes(roomy, charts, 600).color.present);
    EXPECT_GT(shapeBytes, 600u) << "900 bytes of shape alone buy a finer level";
}
