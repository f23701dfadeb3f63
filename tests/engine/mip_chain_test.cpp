// The GPU mip chain, bilinear restoration and geomorph targets against their CPU references.
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/mip_pyramid.h"
#include "ngi/nn/feature_map.h"
#include "ngi/nn/reference_forward.h"
#include "ngi/octahedral.h"

#include <glm/geometric.hpp>

#include <cstring>

namespace {

glm::vec3 texelPosition(const glm::uvec4& t)
{
    glm::vec3 p;
    const uint32_t bits[3] = {t.x, t.y, t.z};
    std::memcpy(&p, bits, sizeof(p));
    return p;
}

// Built with a bilinear restore, which the CPU reference below mirrors level by level.
ngi::vk::GeometryImageSurface buildSurface(const ngi::vk::Renderer& renderer, const ngi::GeometryImage& positions,
                                           const ngi::GeometryImage& normals, uint32_t fullSize)
{
    ngi::vk::GeometryImageSurface s(renderer, positions, normals, fullSize);
    renderer.context().submitAndWait(
        [&](VkCommandBuffer cmd) { s.recordBuild(cmd, {.withoutNetwork = ngi::vk::Upsampling::bilinear}); });
    s.releaseUpload();
    return s;
}

using MipChain = VulkanTest;

TEST_F(MipChain, SubsampledLevelsMatchCpuReferenceExactly)
{
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(65);
    auto surface = buildSurface(renderer(), sphere.positions, sphere.normals, 65);
    const auto cpu = ngi::buildSurfacePyramid(sphere.positions, sphere.normals);
    ASSERT_EQ(surface.levelCount(), cpu.levelCount());
    for (uint32_t l = 0; l < surface.levelCount(); ++l) {
        const auto texels = surface.readLevel(l, false);
        ASSERT_EQ(texels.size(), cpu.positions[l].texels.size());
        for (size_t i = 0; i < texels.size(); ++i) {
            ASSERT_EQ(texelPosition(texels[i]), cpu.positions[l].texels[i]) << "level " << l << " texel " << i;
            // Normals pass through the 2 x 16-bit octahedral encoding: < 1e-4 rad.
            ASSERT_LT(glm::length(ngi::unpackNormalOctahedral(texels[i].w) - cpu.normals[l].texels[i]), 1e-4f);
        }
    }
}

TEST_F(MipChain, RestoredLevelsMatchBilinearCpuReference)
{
    // Upload the 17-sample level of a 65-sample sphere; levels 1 and 0 are restored.
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(65);
    const ngi::GeometryImage p2 = ngi::downsampleNested(sphere.positions, 2),
                             n2 = ngi::downsampleNested(sphere.normals, 2);
    auto surface = buildSurface(renderer(), p2, n2, 65);
    EXPECT_EQ(surface.storedLevel(), 2u);
    const ngi::GeometryImage p1 = ngi::upsampleNested(p2, false), p0 = ngi::upsampleNested(p1, false);
    const ngi::GeometryImage n1 = ngi::upsampleNested(n2, true), n0 = ngi::upsampleNested(n1, true);
    const ngi::GeometryImage* pos[2] = {&p0, &p1};
    const ngi::GeometryImage* nrm[2] = {&n0, &n1};
    for (uint32_t l = 0; l < 2; ++l) {
        const auto texels = surface.readLevel(l, false);
        for (size_t i = 0; i < texels.size(); ++i) {
            ASSERT_LT(glm::length(texelPosition(texels[i]) - pos[l]->texels[i]), 1e-6f)
                << "level " << l << " texel " << i;
            // GPU restores level 0 from the octahedral-encoded level 1: allow that quantization.
            ASSERT_LT(glm::length(ngi::unpackNormalOctahedral(texels[i].w) - nrm[l]->texels[i]), 2e-4f);
        }
    }
    // The uploaded level and everything coarser are untouched.
    const auto t2 = surface.readLevel(2, false);
    for (size_t i = 0; i < t2.size(); ++i) ASSERT_EQ(texelPosition(t2[i]), p2.texels[i]);
}

TEST_F(MipChain, BicubicRestoreMatchesTheCubicSkipCpuReference)
{
    // The 9-sample level of a 65-sample sphere restored by x8 Catmull-Rom in one pass.
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(65);
    const ngi::GeometryImage p3 = ngi::downsampleNested(sphere.positions, 3),
                             n3 = ngi::downsampleNested(sphere.normals, 3);
    ngi::vk::GeometryImageSurface surface(renderer(), p3, n3, 65);
    renderer().context().submitAndWait([&](VkCommandBuffer cmd) {
        surface.recordBuild(cmd, {nullptr, 1.0f, ngi::vk::Upsampling::bicubic});
    });
    surface.releaseUpload();
    ASSERT_EQ(surface.storedLevel(), 3u);
    const ngi::nn::FeatureMap zero(3, 65, 65);
    const ngi::GeometryImage cubic =
        ngi::nn::geometryImageFromFeatureMap(ngi::nn::cubicSkip(ngi::nn::featureMapFromGeometryImage(p3), zero, 8));
    const ngi::GeometryImage bilinear =
        ngi::upsampleNested(ngi::upsampleNested(ngi::upsampleNested(p3, false), false), false);
    const auto level0 = surface.readLevel(0, false);
    double cubicError = 0.0, bilinearError = 0.0;
    for (size_t i = 0; i < level0.size(); ++i) {
        const glm::vec3 p = texelPosition(level0[i]);
        // fp32 sums of 16 products in another order: well below 1e-6 of the unit box.
        ASSERT_LT(glm::length(p - cubic.texels[i]), 1e-6f) << "texel " << i;
        const glm::vec3 n = ngi::unpackNormalOctahedral(level0[i].w);
        ASSERT_NEAR(glm::length(n), 1.0f, 1e-3f);
        // Interpolated stored normals: close to the sphere's own (9 samples over the sphere).
        ASSERT_GT(glm::dot(n, sphere.normals.texels[i]), 0.95f) << "texel " << i;
        cubicError += glm::length(p - sphere.positions.texels[i]);
        bilinearError += glm::length(bilinear.texels[i] - sphere.positions.texels[i]);
    }
    // Measured 0.55 (the sphere image has creases along its octahedral folds, where both err).
    EXPECT_LT(cubicError, 0.75 * bilinearError) << "the bicubic restore is the closer one on a smooth surface";
    // Levels 1 and 2 are nested subsamples of level 0; the stored level is untouched.
    for (uint32_t l = 1; l <= 3; ++l) {
        const auto texels = surface.readLevel(l, false);
        const uint32_t size = surface.levelSize(l), step = 1u << l;
        for (uint32_t y = 0; y < size; ++y)
            for (uint32_t x = 0; x < size; ++x)
                ASSERT_EQ(texels[size_t(y) * size + x], level0[size_t(y) * step * 65 + x * step]) << "level " << l;
    }
    const auto t3 = surface.readLevel(3, false);
    for (size_t i = 0; i < t3.size(); ++i) ASSERT_EQ(texelPosition(t3[i]), p3.texels[i]);
}

TEST_F(MipChain, GeomorphTargetsMatchCpuReference)
{
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(33, 0.1f);
    auto surface = buildSurface(renderer(), torus.positions, torus.normals, 33);
    const auto cpu = ngi::buildSurfacePyramid(torus.positions, torus.normals);
    // Levels of 9+ samples: on coarser torus grids neighbouring samples can face exactly
    // opposite ways (outer and inner equator), where the averaged normal is undefined.
    for (uint32_t l = 0; surface.levelSize(l) >= 9; ++l) {
        const auto texels = surface.readLevel(l, true);
        const uint32_t n = cpu.positions[l].size;
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const auto [p, nn] = ngi::morphTarget(cpu.positions[l], cpu.normals[l], x, y);
                const glm::uvec4 t = texels[size_t(y) * n + x];
                ASSERT_LT(glm::length(texelPosition(t) - p), 1e-6f) << "level " << l << " (" << x << ", " << y << ")";
                ASSERT_LT(glm::length(ngi::unpackNormalOctahedral(t.w) - nn), 2e-4f)
                    << "level " << l << " (" << x << ", " << y << ")";
            }
    }
    EXPECT_THROW(surface.readLevel(surface.levelCount() - 1, true), ngi::Error);
}

TEST_F(MipChain, QuadDiagonalsMatchCpuReference)
{
    const ngi::AnalyticSurface torus = ngi::rippledTorusGeometryImage(33, 0.1f);
    auto surface = buildSurface(renderer(), torus.positions, torus.normals, 33);
    const auto cpu = ngi::buildSurfacePyramid(torus.positions, torus.normals);
    size_t decisions = 0, agree = 0;
    for (uint32_t l = 0; l < surface.levelCount(); ++l) {
        const auto texels = surface.readQuadDiagonals(l);
        const uint32_t n = cpu.positions[l].size;
        ASSERT_EQ(texels.size(), size_t(n - 1) * (n - 1));
        const bool last = l + 1 == surface.levelCount();
        auto target = [&](uint32_t x, uint32_t y) {
            return last ? cpu.positions[l].at(x, y) : ngi::morphTarget(cpu.positions[l], cpu.normals[l], x, y).first;
        };
        for (uint32_t y = 0; y + 1 < n; ++y)
            for (uint32_t x = 0; x + 1 < n; ++x) {
                const auto& p = cpu.positions[l];
                const glm::vec3 p0[4] = {p.at(x, y), p.at(x + 1, y), p.at(x + 1, y + 1), p.at(x, y + 1)};
                const glm::vec3 p1[4] = {target(x, y), target(x + 1, y), target(x + 1, y + 1), target(x, y + 1)};
                const glm::vec3 f = ngi::quadDiagonal(p0, p1);
                const glm::vec4 g = texels[size_t(y) * (n - 1) + x];
                const float scale = 1e-5f * (1.0f + std::abs(f.x) + std::abs(f.y) + std::abs(f.z));
                ASSERT_NEAR(g.x, f.x, scale) << "level " << l;
                ASSERT_NEAR(g.y, f.y, scale) << "level " << l;
                ASSERT_NEAR(g.z, f.z, scale) << "level " << l;
                for (float t : {0.0f, 0.5f, 1.0f}) {
                    ++decisions;
                    agree += ngi::splitsAlongAC(glm::vec3(g), t) == ngi::splitsAlongAC(f, t);
                }
            }
    }
    // Exact ties (symmetric quads) may round either way; everything else must agree.
    EXPECT_GE(double(agree), 0.999 * double(decisions));
}

TEST_F(MipChain, EveryLevelTouchesTheSquaresBorder)
{
    // Positions = the sample's own uv: each level's border texels must sit at u, v in {0, 1}.
    ngi::GeometryImage uv(33), normals(33);
    for (uint32_t y = 0; y < 33; ++y)
        for (uint32_t x = 0; x < 33; ++x) {
            uv.at(x, y) = {x / 32.0f, y / 32.0f, 0.0f};
            normals.at(x, y) = {0.0f, 0.0f, 1.0f};
        }
    // Upload a middle level so that restoration and subsampling are both exercised.
    auto surface = buildSurface(renderer(), ngi::downsampleNested(uv, 2), ngi::downsampleNested(normals, 2), 33);
    for (uint32_t l = 0; l < surface.levelCount(); ++l) {
        const auto texels = surface.readLevel(l, false);
        const uint32_t n = surface.levelSize(l), last = n - 1;
        for (uint32_t i = 0; i < n; ++i) {
            EXPECT_EQ(texelPosition(texels[i]).y, 0.0f) << "level " << l;                     // bottom row
            EXPECT_EQ(texelPosition(texels[size_t(last) * n + i]).y, 1.0f) << "level " << l;  // top row
            EXPECT_EQ(texelPosition(texels[size_t(i) * n]).x, 0.0f) << "level " << l;         // left column
            EXPECT_EQ(texelPosition(texels[size_t(i) * n + last]).x, 1.0f) << "level " << l;  // right column
            EXPECT_NEAR(texelPosition(texels[i]).x, float(i) / last, 1e-6f) << "no drift at level " << l;
        }
    }
}

TEST_F(MipChain, RejectsSizesThatAreNotNestedLevels)
{
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(33);
    EXPECT_THROW(ngi::vk::GeometryImageSurface(renderer(), sphere.positions, sphere.normals, 64), ngi::Error);
    EXPECT_THROW(ngi::vk::GeometryImageSurface(renderer(), sphere.positions, sphere.normals, 129 + 2), ngi::Error);
    const ngi::AnalyticSurface small = ngi::sphereGeometryImage(9);
    EXPECT_THROW(ngi::vk::GeometryImageSurface(renderer(), sphere.positions, small.normals, 33), ngi::Error);
}

}  // namespace
