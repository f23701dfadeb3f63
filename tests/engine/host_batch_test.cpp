// Batched drawing (DrawBatch): many instances of several surfaces in one draw per (chart,
// level) bucket, pixel-identical to one Renderer::recordDraw per instance.
#include "host_pass.h"
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/draw_batch.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include <set>
#include <span>
#include <utility>

namespace {

constexpr uint32_t kWidth = 128, kHeight = 96;

using HostBatchTest = VulkanTest;

struct Placed {
    bool torus;  // the torus asset, else the sphere chart
    glm::mat4 world;
    float lod;
};

// 15 instances on a 5 x 3 grid, overlapping in depth, each with its own rotation, scale and
// continuous LoD (fractional ones geomorph), alternating between the two surfaces, and three
// out of view.
std::vector<Placed> layout()
{
    std::vector<Placed> v;
    for (int i = 0; i < 15; ++i) {
        const float x = float(i % 5) - 2.0f, y = float(i / 5) - 1.0f, z = -0.35f * float(i % 4);
        glm::mat4 w = glm::translate(glm::mat4(1.0f), glm::vec3(0.62f * x, 0.62f * y, z));
        w = glm::rotate(w, glm::radians(23.0f * float(i)), glm::normalize(glm::vec3(1.0f, 0.4f, 0.2f)));
        w = glm::scale(w, glm::vec3(0.55f + 0.03f * float(i % 3)));
        v.push_back({i % 2 == 1, w, 0.37f * float(i % 7)});
    }
    // Three outside the view (behind the camera, far left, beyond the far plane): culled.
    for (const glm::vec3 p : {glm::vec3(0.0f, 0.0f, 8.0f), glm::vec3(-9.0f, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, -40.0f)})
        v.push_back({v.size() % 2 == 1, glm::scale(glm::translate(glm::mat4(1.0f), p), glm::vec3(0.5f)), 0.5f});
    return v;
}

glm::mat4 viewProjection()
{
    glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(45.0f), float(kWidth) / kHeight, 0.5f, 20.0f);
    proj[1][1] *= -1.0f;
    return proj * glm::lookAtRH(glm::vec3(0.3f, 0.4f, 4.0f), glm::vec3(0.0f), glm::vec3(0, 1, 0));
}

size_t covered(const std::vector<uint8_t>& rgba)
{
    size_t n = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) n += (rgba[i] | rgba[i + 1] | rgba[i + 2]) != 0;
    return n;
}

TEST_F(HostBatchTest, BatchedInstancesArePixelIdenticalToSingleDraws)
{
    // A one-chart surface (the sphere, translated to the origin: world matrices centre it)
    // and a two-level-shifted asset surface (the torus asset, de-normalized by ngi).
    const ngi::AnalyticSurface s = ngi::sphereGeometryImage(33);
    ngi::vk::GeometryImageSurface sphere(renderer(), s.positions, s.normals, s.positions.size);
    const ngi::Asset torusAsset = ngi::makeAnalyticAsset("torus", ngi::rippledTorusGeometryImage(65), 2);
    ngi::vk::AssetSurface torus(renderer(), torusAsset);
    context().submitAndWait([&](VkCommandBuffer cmd) {
        sphere.recordBuild(cmd);
        torus.recordBuild(cmd);
    });
    sphere.releaseUpload();
    torus.releaseUploads();
    const glm::mat4 centreSphere = glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f));

    const glm::vec3 eye(0.3f, 0.4f, 4.0f);
    ngi::vk::DrawBatch batch(renderer(), 64);
    for (ngi::vk::ShadingMode mode : {ngi::vk::ShadingMode::Shaded, ngi::vk::ShadingMode::Lod}) {
        for (ngi::vk::PassDescription desc : {renderer().options().pass(), [&] {
                                                  ngi::vk::PassDescription d = renderer().options().pass();
                                                  d.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
                                                  return d;
                                              }()}) {
            const bool reverseZ = desc.depthCompare == VK_COMPARE_OP_GREATER_OR_EQUAL;
            ngi::test::HostPass pass(context(), desc, kWidth, kHeight);
            const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass());
            glm::mat4 vp = viewProjection();
            if (reverseZ) {  // depth 1 - z: the same image with the opposite compare
                glm::mat4 flip(1.0f);
                flip[2][2] = -1.0f;
                flip[3][2] = 1.0f;
                vp = flip * vp;
            }
            const auto instances = layout();
            const auto single = pass.render(
                [&](VkCommandBuffer cmd) {
                    for (const Placed& i : instances) {
                        ngi::vk::DrawParams p;
                        p.pipeline = &pipeline;
                        p.viewProjection = vp;
                        p.eye = eye;
                        p.mode = mode;
                        p.lod = i.lod;
                        if (i.torus) {
                            p.world = i.world;
                            torus.recordDraw(cmd, p, pass.extent());
                        } else {
                            p.world = i.world * centreSphere;
                            renderer().recordDraw(cmd, sphere, p, pass.extent());
                        }
                    }
                },
                reverseZ ? 0.0f : 1.0f);
            batch.clear();
            for (const Placed& i : instances) {
                if (i.torus)
                    batch.add(torus, i.world, i.lod);
                else
                    batch.add(sphere, i.world * centreSphere, i.lod);
            }
            ngi::vk::BatchStats stats;
            const auto batched = pass.render(
                [&](VkCommandBuffer cmd) {
                    ngi::vk::BatchParams bp;
                    bp.pipeline = &pipeline;
                    bp.viewProjection = vp;
                    bp.eye = eye;
                    bp.mode = mode;
                    stats = batch.record(cmd, bp, pass.extent());
                },
                reverseZ ? 0.0f : 1.0f);
            EXPECT_EQ(single, batched) << "mode " << int(mode) << (reverseZ ? ", reverse-Z" : "");
            EXPECT_GT(covered(batched), size_t(kWidth) * kHeight / 8);
            // One draw per distinct (chart, level): at most the torus's charts x levels plus
            // the sphere's levels, fewer than the 15 single draws (and their charts).
            std::set<std::pair<int, uint32_t>> buckets;
            for (const Placed& i : std::span(instances).first(15))
                for (size_t c = 0; c < (i.torus ? torus.chartCount() : 1); ++c) {
                    const float lod = i.torus ? torus.chartLod(c, i.lod) : i.lod;
                    const uint32_t levels = i.torus ? torus.chart(c).drawnLevelCount() : sphere.drawnLevelCount();
                    buckets.insert({i.torus ? int(c) : -1, std::min(uint32_t(lod), levels - 1)});
                }
            EXPECT_EQ(stats.instances, 18u);
            EXPECT_EQ(stats.culled, 3u);  // the torus asset has one chart
            EXPECT_EQ(stats.buckets, buckets.size());
            EXPECT_EQ(stats.drawCalls, stats.buckets);  // every grid here fits one 16384-quad chunk
            EXPECT_LT(stats.drawCalls, 15u);
            EXPECT_EQ(stats.records, 15u);
        }
    }
}

TEST_F(HostBatchTest, SeveralPassesShareOneBatchUntilItsCapacity)
{
    const ngi::AnalyticSurface s = ngi::sphereGeometryImage(17);
    ngi::vk::GeometryImageSurface sphere(renderer(), s.positions, s.normals, s.positions.size);
    context().submitAndWait([&](VkCommandBuffer cmd) { sphere.recordBuild(cmd); });
    sphere.releaseUpload();
    ngi::vk::DrawBatch batch(renderer(), 6);
    for (int i = 0; i < 3; ++i)
        batch.add(sphere, glm::translate(glm::mat4(1.0f), glm::vec3(float(i), 0.0f, 0.0f)), 0.5f);
    ngi::test::HostPass pass(context(), renderer().options().pass(), 32, 32);
    const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass());
    ngi::vk::BatchParams bp;
    bp.pipeline = &pipeline;
    bp.frustumCull = false;  // every record is written (the identity clip transform sees x in [-1, 1] only)
    // Two passes fit (2 x 3 records); a third does not until clear().
    pass.render(
        [&](VkCommandBuffer cmd) {
            EXPECT_EQ(batch.record(cmd, bp, pass.extent()).records, 3u);
            EXPECT_EQ(batch.record(cmd, bp, pass.extent()).records, 3u);
        },
        1.0f);
    EXPECT_THROW(pass.render([&](VkCommandBuffer cmd) { batch.record(cmd, bp, pass.extent()); }, 1.0f), ngi::Error);
    batch.clear();
    EXPECT_EQ(batch.instanceCount(), 0u);
    EXPECT_THROW(ngi::vk::DrawBatch(renderer(), 0), ngi::Error);
}

}  // namespace
