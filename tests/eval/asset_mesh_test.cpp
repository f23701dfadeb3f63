// The mesh ngi-eval exports for an asset is the one the renderer draws (core's lod_grid.h):
// same triangle count at every LoD, same vertices, in the original coordinates.
#include "ngi/error.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/mip_pyramid.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

TEST(AssetMesh, hasTheRenderersTriangleCountAtEveryLod)
{
    const ngi::Asset asset = ngi::test::rippleAsset();
    const ngi::SurfacePyramid pyramid = ngi::restoredPyramidWithoutSR(asset);
    ASSERT_EQ(pyramid.fullSize(), 65u);
    ASSERT_EQ(pyramid.levelCount(), 7u); // 65, 33, 17, 9, 5, 3, 2
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
        ASSERT_EQ(m.mesh.triangles, drawn.triangles); // same grid, same diagonals
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
    o.lod = float(asset.storedLevel);
    const ngi::AssetMesh m = ngi::assetMesh(asset, o);
    const ngi::GeometryImage stored = ngi::storedPositions(asset);
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

TEST(AssetMesh, rejectsLodOutOfRangeAndSuperResolution)
{
    const ngi::Asset asset = ngi::test::rippleAsset();
    for (float lod : {-0.5f, 6.01f, NAN, INFINITY}) {
        ngi::AssetMeshOptions o;
        o.lod = lod;
        EXPECT_THROW(ngi::assetMesh(asset, o), ngi::Error) << lod;
    }
    ngi::AssetMeshOptions sr;
    sr.superResolution = true;
    try {
        ngi::assetMesh(asset, sr);
        ADD_FAILURE() << "--sr accepted";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("super-resolution"), std::string::npos);
    }
    for (uint32_t n : {0u, 1u, 66u}) {
        ngi::AssetMeshOptions o;
        o.gridSize = n;
        EXPECT_THROW(ngi::assetMesh(asset, o), ngi::Error) << n;
    }
}

} // namespace
