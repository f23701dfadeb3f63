// ngi-bake --target-bytes (ngi/bake/rate_control.h): the asset never exceeds its budget, a
// larger budget never restores worse, a budget below the smallest asset is a clear error.
#include "ngi/bake/network_choice.h"
#include "ngi/bake/rate_control.h"
#include "ngi/error.h"

#include "tiny_network.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace {

// A bumpy cap at full resolution 64, normalized to [0, 1]^3, with its analytic normals.
void makeBake(ngi::Asset& asset, std::vector<ngi::ChartBake>& charts)
{
    asset.sourceName = "analytic:cap";
    asset.parameterization = "analytic";
    asset.metadataJson = R"({"bake":{"totalSeconds":1.5,"parameterization":{"areaDistortionMean":0.1},"clean":{"x":1}}})";
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
        EXPECT_NEAR(choice.gains[0]->rmsCubic * choice.gains[0]->rmsCubic, report.chosen.error, 1e-6 * report.chosen.error);
        if (report.chosen.networkError >= 0.0)
            EXPECT_NEAR(choice.gains[0]->rmsGained * choice.gains[0]->rmsGained, report.chosen.networkError,
                        1e-6 * report.chosen.networkError);
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
    size_t sum = 0;
    for (const auto& [name, size] : ngi::assetChunkBytes(bytes)) sum += size;
    EXPECT_EQ(sum, bytes.size());
}

} // namespace
