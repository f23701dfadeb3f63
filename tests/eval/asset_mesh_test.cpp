// The mesh ngi-eval exports for an asset is the one the renderer draws (core's lod_grid.h):
// same triangle count at every LoD, same vertices, in the original coordinates.
#include "ngi/error.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/mip_pyramid.h"

#include "test_meshes.h"

#include "../support/tiny_network.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>

namespace {

TEST(AssetMesh, hasTheRenderersTriangleCountAtEveryLod)
{
    const ngi::Asset asset = ngi::test::rippleAsset();
    const ngi::SurfacePyramid pyramid = ngi::restoredPyramidWithoutSR(asset);
    ASSERT_EQ(pyramid.fullSize(), 65u);
    ASSERT_EQ(pyramid.levelCount(), 7u);  // 65, 33, 17, 9, 5, 3, 2
    for (float lod : {0.0f, 0.25f, 1.0f, 2.0f, 2.5f, 3.99f, 5.0f, 6.0f}) {
        ngi::AssetMeshOptions o;
        o.lod = lod;
        const ngi::AssetMesh m = ngi::assetMesh(asset, o);
        const ngi::LodSelection s = ngi::selectLod(pyramid.levelCount(), pyramid.fullSize(), lod);
        const ngi::LodMesh drawn = ngi::buildLodMesh(pyramid, lod);
        SCOPED_TRACE("lod " + std::to_string(lod));
        EXPECT_EQ(m.levelCount, 7u);
        EXPECT_EQ(m.selection.level, s.level);
        EXPECT_EQ(m.selection.gridSize, s.gridSize);
        EXPECT_EQ(m.mesh.triangles.size(), ngi::gridTriangleCount(s.gridSize));
        ASSERT_EQ(m.mesh.triangles, drawn.triangles);  // same grid, same diagonals
        ASSERT_EQ(m.mesh.positions.size(), drawn.positions.size());
        for (size_t i = 0; i < drawn.positions.size(); ++i) {
            const glm::dvec3 expected =
                glm::dvec3(asset.offset) + glm::dvec3(asset.scale) * glm::dvec3(drawn.positions[i]);
            ASSERT_EQ(m.mesh.positions[i], expected);
        }
    }
    ngi::AssetMeshOptions grid;
    grid.gridSize = 20;
    EXPECT_EQ(ngi::assetMesh(asset, grid).mesh.triangles.size(), ngi::gridTriangleCount(20));
}

TEST(AssetMesh, atTheStoredLevelGivesTheStoredSamplesInOriginalCoordinates)
{
    const ngi::Asset asset = ngi::test::rippleAsset();
    ngi::AssetMeshOptions o;
    o.lod = float(asset.charts[0].storedLevel);
    const ngi::AssetMesh m = ngi::assetMesh(asset, o);
    const ngi::GeometryImage stored = ngi::storedPositions(asset.charts[0]);
    ASSERT_EQ(m.selection.gridSize, stored.size);
    for (uint32_t y = 0; y < stored.size; ++y)
        for (uint32_t x = 0; x < stored.size; ++x) {
            const glm::dvec3 p = m.mesh.positions[size_t(y) * stored.size + x];
            const glm::dvec3 q = glm::dvec3(asset.offset) + 4.0 * glm::dvec3(stored.at(x, y));
            ASSERT_NEAR(p.x, q.x, 1e-6);
            ASSERT_NEAR(p.y, q.y, 1e-6);
            ASSERT_NEAR(p.z, q.z, 1e-6);
        }
}

TEST(AssetMesh, rejectsLodOutOfRangeAndSuperResolutionWithoutANetwork)
{
    const ngi::Asset asset = ngi::test::rippleAsset();
    for (float lod : {-0.5f, 6.01f, NAN, INFINITY}) {
        ngi::AssetMeshOptions o;
        o.lod = lod;
        EXPECT_THROW(ngi::assetMesh(asset, o), ngi::Error) << lod;
    }
    ngi::AssetMeshOptions sr;
    sr.restore = ngi::AssetRestore::Network;  // no --weights, no WGHT chunk
    try {
        ngi::assetMesh(asset, sr);
        ADD_FAILURE() << "--sr without a network accepted";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("needs a network"), std::string::npos);
    }
    for (uint32_t n : {0u, 1u, 66u}) {
        ngi::AssetMeshOptions o;
        o.gridSize = n;
        EXPECT_THROW(ngi::assetMesh(asset, o), ngi::Error) << n;
    }
}

TEST(AssetMesh, bicubicRestoreKeepsTheStoredSamplesAndFitsTheRippleBetterInside)
{
    // The ripple is smooth: inside (away from the clamped border) cubic convolution is closer to
    // the analytic surface than bilinear; both reproduce the stored samples exactly.
    const ngi::Asset asset = ngi::test::rippleAsset();
    const ngi::GeometryImage stored = ngi::storedPositions(asset.charts[0]);
    const auto bilinear = ngi::restoreFullResolution(asset, ngi::AssetRestore::Bilinear);
    const auto bicubic = ngi::restoreFullResolution(asset, ngi::AssetRestore::Bicubic);
    ASSERT_EQ(bicubic.positions.size, asset.charts[0].fullSize());
    const uint32_t f = 1u << asset.charts[0].storedLevel;
    for (uint32_t y = 0; y < stored.size; ++y)
        for (uint32_t x = 0; x < stored.size; ++x)
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(bicubic.positions.at(x * f, y * f)[c], stored.at(x, y)[c], 1e-6f);
    double errorBilinear = 0.0, errorBicubic = 0.0;
    const uint32_t n = bicubic.positions.size;
    for (uint32_t y = 2 * f; y + 2 * f < n; ++y)
        for (uint32_t x = 2 * f; x + 2 * f < n; ++x) {
            const float u = float(x) / float(n - 1), v = float(y) / float(n - 1);
            const float z = 0.5f + 0.2f * std::sin(7.0f * u) * std::cos(5.0f * v);
            errorBilinear += std::abs(bilinear.positions.at(x, y).z - z);
            errorBicubic += std::abs(bicubic.positions.at(x, y).z - z);
        }
    EXPECT_LT(errorBicubic, 0.5 * errorBilinear);
}

TEST(AssetMesh, networkRestoreRunsTheGivenWeightsAndChecksTheScale)
{
    const ngi::Asset asset = ngi::test::rippleAsset();  // stored level 2: needs x4
    const auto bilinear = ngi::restoreFullResolution(asset, ngi::AssetRestore::Bilinear);
    // All-zero residual: exactly the bilinear restore.
    const ngi::NetworkWeights zero = ngi::test::tinyNetwork(4, 0.0f);
    const auto same = ngi::restoreFullResolution(asset, ngi::AssetRestore::Network, &zero);
    for (size_t i = 0; i < same.positions.texels.size(); ++i)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(same.positions.texels[i][c], bilinear.positions.texels[i][c], 1e-6f);
    // A non-zero residual moves the surface: w * (x + y + z) added to every channel.
    const ngi::NetworkWeights shifted = ngi::test::tinyNetwork(4, 0.01f);
    ngi::AssetMeshOptions options;
    options.restore = ngi::AssetRestore::Network;
    options.network = &shifted;
    const ngi::AssetMesh moved = ngi::assetMesh(asset, options);
    options.restore = ngi::AssetRestore::Bilinear;
    const ngi::AssetMesh plain = ngi::assetMesh(asset, options);
    ASSERT_EQ(moved.mesh.positions.size(), plain.mesh.positions.size());
    double largest = 0.0;
    for (size_t i = 0; i < moved.mesh.positions.size(); ++i)
        largest = std::max(largest, glm::length(moved.mesh.positions[i] - plain.mesh.positions[i]));
    EXPECT_GT(largest, 0.01);
    // Wrong scale factor: one clear error naming both factors.
    const ngi::NetworkWeights x8 = ngi::test::tinyNetwork(8, 0.0f);
    try {
        ngi::restoreFullResolution(asset, ngi::AssetRestore::Network, &x8);
        ADD_FAILURE() << "x8 network accepted for a x4 asset";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("x8"), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("x4"), std::string::npos);
    }
}

TEST(AssetMesh, normalsAreTheStoredNormalsInterpolatedForEveryRestore)
{
    // asset_mesh.h's contract: normals are the stored normals upsampled bilinearly (renormalized)
    // whatever restores the positions, never derived from the restored positions: a network that
    // moves every position leaves them bit for bit unchanged.
    const ngi::Asset asset = ngi::test::rippleAsset();
    ngi::GeometryImage expected = ngi::storedNormals(asset.charts[0]);
    for (uint32_t level = asset.charts[0].storedLevel; level > 0; --level)
        expected = ngi::upsampleNested(expected, true);
    const ngi::NetworkWeights shifted = ngi::test::tinyNetwork(4, 0.01f);
    for (ngi::AssetRestore restore :
         {ngi::AssetRestore::Bilinear, ngi::AssetRestore::Bicubic, ngi::AssetRestore::Network}) {
        const auto restored = ngi::restoreFullResolution(asset, restore, &shifted);
        ASSERT_EQ(restored.normals.size, asset.charts[0].fullSize());
        for (size_t i = 0; i < expected.texels.size(); ++i)
            ASSERT_EQ(restored.normals.texels[i], expected.texels[i]) << "restore " << int(restore) << " texel " << i;
    }
}

}  // namespace

namespace {

// Three disjoint parts, one chart each: every part is drawn (nothing dropped), every chart at
// the same level index (the same density: a chart of half the resolution draws half the cells
// per side), clamped to its own coarsest level; a chart index the asset lacks is an error.
TEST(AssetMesh, everyChartIsDrawnAtOneLod)
{
    ngi::Asset asset = ngi::test::rippleAsset();  // one 64-cell chart stored at level 2
    ngi::AssetChart half = asset.charts[0], quarter = asset.charts[0];
    half.fullResolution = 32, half.storedLevel = 1;  // 17^2 stored samples, like chart 0
    quarter.fullResolution = 16, quarter.storedLevel = 0;
    asset.charts.push_back(half);
    asset.charts.push_back(quarter);
    for (float lod : {0.0f, 1.0f, 2.5f}) {
        ngi::AssetMeshOptions o;
        o.lod = lod;
        const ngi::AssetMesh m = ngi::assetMesh(asset, o);
        // Grid sizes per chart at level L: 64 >> L, 32 >> L, 16 >> L cells (each clamped to the
        // chart's coarsest drawn level).
        const uint32_t level = uint32_t(lod);
        uint64_t expected = 0;
        for (const ngi::AssetChart& c : asset.charts)
            expected += ngi::gridTriangleCount((c.fullResolution >> std::min(level, c.coarsestDrawnLevel())) + 1);
        EXPECT_EQ(m.mesh.triangles.size(), expected) << lod;
        EXPECT_EQ(m.levelCount, 7u);
    }
    EXPECT_THROW(ngi::restoreFullResolution(asset, ngi::AssetRestore::Bilinear, nullptr, 3), ngi::Error);
}

}  // namespace
