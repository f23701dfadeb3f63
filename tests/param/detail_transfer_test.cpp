// ngi tests: detail transfer moves geometry-image samples onto the input surface, never onto
// another sheet or further than allowed.
#include "ngi/error.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/param/detail_transfer.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace ngi {
namespace {

// A geometry image of `count` samples on the coarse icosphere (flat triangles inside the unit
// sphere, up to its chord error), with radial normals.
void coarseSphereSamples(uint32_t count, GeometryImage& positions, GeometryImage& normals)
{
    const TriangleMesh coarse = makeSphere(1);
    positions = GeometryImage(count);
    normals = GeometryImage(count);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (size_t i = 0; i < positions.texels.size(); ++i) {
        const glm::uvec3 t = coarse.triangles[i % coarse.triangles.size()];
        double a = unit(rng), b = unit(rng);
        if (a + b > 1.0) a = 1.0 - a, b = 1.0 - b;
        const glm::dvec3 p = coarse.positions[t.x] + a * (coarse.positions[t.y] - coarse.positions[t.x]) +
            b * (coarse.positions[t.z] - coarse.positions[t.x]);
        positions.texels[i] = glm::vec3(p);
        normals.texels[i] = glm::vec3(glm::normalize(p));
    }
}

TEST(DetailTransfer, samplesOfACoarseSphereLandOnTheFineOne)
{
    GeometryImage positions, normals;
    coarseSphereSamples(33, positions, normals);
    double worstBefore = 0.0;
    for (const glm::vec3& p : positions.texels)
        worstBefore = std::max(worstBefore, std::abs(double(glm::length(p)) - 1.0));
    ASSERT_GT(worstBefore, 0.05);  // the coarse sphere cuts well inside the unit sphere

    const TriangleMesh fine = makeSphere(5);  // chord error of its 20480 triangles ~ 1.3e-3
    const DetailTransferReport report = transferDetail(fine, positions, normals, {.maxDistance = 0.3});
    EXPECT_EQ(report.projected, positions.texels.size());
    EXPECT_EQ(report.kept, 0u);
    EXPECT_NEAR(report.maxDistance, worstBefore, 0.01);
    for (size_t i = 0; i < positions.texels.size(); ++i) {
        const glm::dvec3 p(positions.texels[i]);
        EXPECT_NEAR(glm::length(p), 1.0, 2e-3);  // on the fine sphere, within its chord error
        EXPECT_GT(glm::dot(glm::dvec3(normals.texels[i]), glm::normalize(p)), 0.999);
        EXPECT_NEAR(glm::length(glm::dvec3(normals.texels[i])), 1.0, 1e-5);
    }
}

TEST(DetailTransfer, aSampleNeverTakesTheOtherSideOfAThinSheetNorMovesBeyondTheLimit)
{
    // A thin slab: two facing planes 0.02 apart (top faces +z, bottom faces -z).
    TriangleMesh slab;
    slab.positions = {{0, 0, 0},    {1, 0, 0},    {1, 1, 0},    {0, 1, 0},
                      {0, 0, 0.02}, {1, 0, 0.02}, {1, 1, 0.02}, {0, 1, 0.02}};
    slab.triangles = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}};
    GeometryImage positions(2), normals(2);
    positions.texels = {{0.5f, 0.5f, 0.018f}, {0.5f, 0.5f, 0.004f}, {0.5f, 0.5f, 0.5f}, {0.2f, 0.7f, 0.021f}};
    normals.texels = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};  // every sample belongs to the top sheet
    const GeometryImage before = positions;
    const DetailTransferReport report = transferDetail(slab, positions, normals, {.maxDistance = 0.1});
    EXPECT_EQ(report.projected, 2u);
    EXPECT_EQ(report.kept, 2u);
    EXPECT_FLOAT_EQ(positions.texels[0].z, 0.02f);     // onto the top sheet
    EXPECT_EQ(positions.texels[1], before.texels[1]);  // closest is the bottom sheet, facing away: kept
    EXPECT_EQ(positions.texels[2], before.texels[2]);  // 0.48 away: beyond the limit, kept
    EXPECT_FLOAT_EQ(positions.texels[3].z, 0.02f);
    EXPECT_FLOAT_EQ(positions.texels[3].x, 0.2f);
    EXPECT_NEAR(report.maxDistance, 0.002, 1e-6);
}

TEST(DetailTransfer, rejectsAnInputWithoutSurfaceAndMismatchedImages)
{
    GeometryImage positions(3), normals(3), small(2);
    TriangleMesh degenerate;
    degenerate.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    degenerate.triangles = {{0, 1, 2}};
    EXPECT_THROW(transferDetail(degenerate, positions, normals), Error);
    EXPECT_THROW(transferDetail(makeSphere(1), positions, small), Error);
}

}  // namespace
}  // namespace ngi
