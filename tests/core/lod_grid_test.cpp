// The CPU definition of the drawn LoD surface: LoD selection, triangle counts, geomorphing
// that lands exactly on the coarser surface, shorter-diagonal splits.
#include "ngi/analytic_surfaces.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/octahedral.h"

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

// Distance from p to triangle abc (Ericson, Real-Time Collision Detection, 5.1.5).
float pointTriangleDistance(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c)
{
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return glm::length(p - a);
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return glm::length(p - b);
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return glm::length(p - c);
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const float denom = 1.0f / (va + vb + vc);
    return glm::length(p - (a + ab * (vb * denom) + ac * (vc * denom)));
}

TEST(LodGrid, SelectionAndCounts)
{
    const auto s = ngi::selectLod(11, 1025, 2.25f);
    EXPECT_EQ(s.level, 2u);
    EXPECT_FLOAT_EQ(s.morph, 0.25f);
    EXPECT_EQ(s.gridSize, 257u);
    EXPECT_EQ(ngi::selectLod(11, 1025, 99.0f).level, 10u);
    EXPECT_EQ(ngi::selectLod(11, 1025, 99.0f).morph, 0.0f);
    EXPECT_EQ(ngi::selectLod(11, 1025, -3.0f).level, 0u);
    EXPECT_EQ(ngi::selectLod(11, 1025, NAN).level, 0u);
    EXPECT_EQ(ngi::gridTriangleCount(1025), 2097152u);
    EXPECT_EQ(ngi::gridTriangleCount(2), 2u);
    EXPECT_EQ(ngi::levelForGridSize(1025, 1025), 0u);
    EXPECT_EQ(ngi::levelForGridSize(1025, 1000), 0u);
    EXPECT_EQ(ngi::levelForGridSize(1025, 513), 1u);
    EXPECT_EQ(ngi::levelForGridSize(1025, 100), 3u);
    EXPECT_EQ(ngi::levelForGridSize(1025, 2), 10u);
    EXPECT_THROW(ngi::levelForGridSize(1025, 1), ngi::Error);
    EXPECT_THROW(ngi::levelForGridSize(1025, 1026), ngi::Error);
}

TEST(LodGrid, MeshHasTheDrawnTriangleCount)
{
    const auto torus = ngi::rippledTorusGeometryImage(33);
    const auto pyramid = ngi::buildSurfacePyramid(torus.positions, torus.normals);
    for (float lod : {0.0f, 0.5f, 1.0f, 3.7f, 5.0f}) {
        const ngi::LodMesh m = ngi::buildLodMesh(pyramid, lod);
        const auto s = ngi::selectLod(pyramid.levelCount(), 33, lod);
        EXPECT_EQ(m.triangles.size(), ngi::gridTriangleCount(s.gridSize));
        EXPECT_EQ(m.positions.size(), size_t(s.gridSize) * s.gridSize);
    }
    for (uint32_t n : {2u, 5u, 20u, 33u})
        EXPECT_EQ(ngi::buildGridMesh(pyramid, n).triangles.size(), ngi::gridTriangleCount(n));
}

TEST(LodGrid, FullyMorphedGridLiesOnTheCoarserSurface)
{
    const auto torus = ngi::rippledTorusGeometryImage(33, 0.1f);
    const auto pyramid = ngi::buildSurfacePyramid(torus.positions, torus.normals);
    for (uint32_t level = 0; level + 2 < pyramid.levelCount(); ++level) {
        const ngi::LodMesh fine = ngi::buildLodMesh(pyramid, float(level) + 0.99999f);
        const ngi::LodMesh coarse = ngi::buildLodMesh(pyramid, float(level + 1));
        float worst = 0.0f;
        for (const glm::vec3& p : fine.positions) {
            float best = std::numeric_limits<float>::max();
            for (const auto& t : coarse.triangles)
                best = std::min(
                    best,
                    pointTriangleDistance(p, coarse.positions[t.x], coarse.positions[t.y], coarse.positions[t.z]));
            worst = std::max(worst, best);
        }
        // 1e-5 of the morph left plus float rounding; a bilinear (not diagonal-aware) target
        // would be off by the quads' non-planarity, ~1e-3 here.
        EXPECT_LT(worst, 2e-5f) << "level " << level;
    }
}

TEST(LodGrid, QuadsSplitAlongTheShorterDiagonal)
{
    const auto torus = ngi::rippledTorusGeometryImage(17, 0.1f);
    const auto pyramid = ngi::buildSurfacePyramid(torus.positions, torus.normals);
    const ngi::LodMesh m = ngi::buildLodMesh(pyramid, 0.0f);
    for (size_t t = 0; t < m.triangles.size(); t += 2) {
        // The shared edge of a quad's two triangles is its diagonal.
        const glm::uvec3 a = m.triangles[t], b = m.triangles[t + 1];
        std::vector<uint32_t> shared;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j)
                if (a[i] == b[j]) shared.push_back(a[i]);
        ASSERT_EQ(shared.size(), 2u);
        uint32_t others[2] = {0, 0};
        for (int i = 0; i < 3; ++i)
            if (a[i] != shared[0] && a[i] != shared[1]) others[0] = a[i];
        for (int j = 0; j < 3; ++j)
            if (b[j] != shared[0] && b[j] != shared[1]) others[1] = b[j];
        const float diagonal = glm::length(m.positions[shared[0]] - m.positions[shared[1]]);
        const float other = glm::length(m.positions[others[0]] - m.positions[others[1]]);
        EXPECT_LE(diagonal, other * (1.0f + 1e-6f));
    }
}

TEST(Octahedral, RoundTripIsWithinQuantization)
{
    float worst = 0.0f;
    for (int i = 0; i < 2000; ++i) {
        const float z = -1.0f + 2.0f * (i + 0.5f) / 2000.0f, phi = 2.39996323f * i;
        const float r = std::sqrt(1.0f - z * z);
        const glm::vec3 n(r * std::cos(phi), r * std::sin(phi), z);
        worst = std::max(worst, glm::length(ngi::unpackNormalOctahedral(ngi::packNormalOctahedral(n)) - n));
    }
    EXPECT_LT(worst, 1e-4f);
    EXPECT_LT(glm::length(ngi::unpackNormalOctahedral(ngi::packNormalOctahedral(glm::vec3(0.0f))) - glm::vec3(0, 0, 1)),
              1e-4f);
}

}  // namespace
