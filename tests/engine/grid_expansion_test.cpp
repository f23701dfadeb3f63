// The grid expansion (Renderer::recordGridExpansion): shared-vertex draws through a level's
// run-time index buffer give exactly the pixels of the per-quad draw, integer and fractional
// LoDs alike; the index buffer follows the quad diagonal rule; what is cached and when a
// draw falls back to a per-quad way.
#include "host_pass.h"
#include "host_uniform_set.h"
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/draw_batch.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/pipelines.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi_shared.h"

#include "host_test_shaders/host_world_frag.h"
#include "ngi_shaders/indexed_mesh_vert.h"
#include "ngi_shaders/surface_frag.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <span>

namespace {

constexpr uint32_t kSize = 128;
const glm::vec4 kClear{0.0f, 0.0f, 0.0f, 1.0f};

using GridExpansion = VulkanTest;

ngi::vk::GeometryImageSurface build(const ngi::vk::Renderer& r, const ngi::AnalyticSurface& s)
{
    ngi::vk::GeometryImageSurface surface(r, s.positions, s.normals, s.positions.size);
    r.context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd); });
    surface.releaseUpload();
    return surface;
}

size_t covered(const std::vector<uint8_t>& rgba)
{
    size_t n = 0;
    for (size_t i = 0; i < rgba.size(); i += 4) n += (rgba[i] | rgba[i + 1] | rgba[i + 2]) != 0;
    return n;
}

// One frame of `surface` drawn with `p`: per quad (nothing expanded), or shared vertices
// (the expansion recorded before the pass). `stats` gets the draw's.
std::vector<uint8_t> frame(const ngi::vk::Renderer& r, ngi::vk::OffscreenTarget& target,
                           const ngi::vk::GeometryImageSurface& surface, const ngi::vk::DrawParams& p, bool expand,
                           ngi::vk::DrawStats& stats, uint32_t& expanded)
{
    surface.releaseGridExpansions();
    expanded = 0;
    return target.render([&](VkCommandBuffer cmd) { stats = r.recordDraw(cmd, surface, p, target.extent()); }, kClear,
                         [&](VkCommandBuffer cmd) {
                             if (expand) expanded = r.recordGridExpansion(cmd, surface, p);
                         });
}

ngi::vk::DrawParams framing(const ngi::vk::GeometryImageSurface& surface, float lod)
{
    const auto camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 30.0f, 25.0f, 1.0f);
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    p.lod = lod;
    return p;
}

TEST_F(GridExpansion, SharedVerticesDrawThePerQuadPixelsAtIntegerAndFractionalLods)
{
    // A rippled torus (129^2: diagonals of both kinds, geomorphs that flip some of them).
    auto surface = build(renderer(), ngi::rippledTorusGeometryImage(129));
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    for (const float lod : {0.0f, 0.5f, 1.3f, 2.75f, 4.0f})
        for (const ngi::vk::ShadingMode mode :
             {ngi::vk::ShadingMode::Shaded, ngi::vk::ShadingMode::Normals, ngi::vk::ShadingMode::Lod}) {
            ngi::vk::DrawParams p = framing(surface, lod);
            p.mode = mode;
            ngi::vk::DrawStats perQuadStats, sharedStats;
            uint32_t expanded = 0;
            const auto perQuad = frame(renderer(), target, surface, p, false, perQuadStats, expanded);
            const auto shared = frame(renderer(), target, surface, p, true, sharedStats, expanded);
            EXPECT_EQ(expanded, 1u);
            EXPECT_FALSE(perQuadStats.sharedVertices);
            EXPECT_TRUE(sharedStats.sharedVertices);
            EXPECT_EQ(perQuadStats.triangles, sharedStats.triangles);
            EXPECT_EQ(sharedStats.vertexInvocations, uint64_t(sharedStats.gridSize) * sharedStats.gridSize);
            EXPECT_GT(covered(shared), size_t(kSize) * kSize / 8) << "lod " << lod;
            EXPECT_EQ(perQuad, shared) << "lod " << lod << " mode " << int(mode);
        }
}

TEST_F(GridExpansion, AnAssetDrawsItsChartsWithSharedVerticesPixelIdentically)
{
    // The shipped asset (restored to 1025^2) at a fractional LoD (257^2 grid, geomorphing) and
    // an integer one, through AssetSurface::recordDraw; restored bicubically (the draw, not the
    // network, is under test).
    const ngi::Asset asset = ngi::readAsset(NGI_SOURCE_DIR "/assets/default.ngi");
    ngi::vk::AssetSurface surface(renderer(), asset, {.findNetwork = false});
    surface.build();
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const auto camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 30.0f, 25.0f, 1.0f);
    for (const float lod : {2.4f, 3.0f}) {
        ngi::vk::DrawParams p;
        p.viewProjection = camera.viewProjection(1.0f);
        p.eye = camera.eye();
        p.lod = lod;
        for (size_t c = 0; c < surface.chartCount(); ++c) surface.chart(c).releaseGridExpansions();
        const auto perQuad =
            target.render([&](VkCommandBuffer cmd) { surface.recordDraw(cmd, p, target.extent()); }, kClear);
        uint32_t expanded = 0;
        const auto shared =
            target.render([&](VkCommandBuffer cmd) { surface.recordDraw(cmd, p, target.extent()); }, kClear,
                          [&](VkCommandBuffer cmd) { expanded = renderer().recordGridExpansion(cmd, surface, p); });
        EXPECT_EQ(expanded, surface.chartCount());
        EXPECT_GT(covered(shared), size_t(kSize) * kSize / 16);
        EXPECT_EQ(perQuad, shared) << "lod " << lod;
    }
    for (size_t c = 0; c < surface.chartCount(); ++c) surface.chart(c).releaseGridExpansions();
}

TEST_F(GridExpansion, IndicesFollowTheDiagonalRuleAcrossGeomorphFactors)
{
    // Level 0 (257^2: two chunks of 16-bit indices) expanded at geomorph 0.37, then into the
    // same buffer at 0.81 and 0.05: after each, quad
    // (i, j)'s six indices are its two triangles along the diagonal splitsAlongAC picks from
    // the quad's (C, B, A) for that factor, in the per-quad draw's order, as vertex numbers
    // j * N + i.
    auto surface = build(renderer(), ngi::rippledTorusGeometryImage(257));
    const uint32_t n = surface.levelSize(0);
    ASSERT_LT(ngi::vk::GeometryImageSurface::gridChunkRows(n), n - 1);  // more than one chunk
    const std::vector<glm::vec4> f = surface.readQuadDiagonals(0);
    std::vector<uint8_t> previous;  // the split of each quad at the previous factor
    for (const float morph : {0.37f, 0.81f, 0.05f}) {
        ngi::vk::DrawParams p = framing(surface, morph);
        context().submitAndWait(
            [&](VkCommandBuffer cmd) { EXPECT_EQ(renderer().recordGridExpansion(cmd, surface, p), 1u); });
        const std::vector<uint32_t> indices = surface.readGridIndices(0);
        ASSERT_EQ(indices.size(), size_t(6) * (n - 1) * (n - 1));
        size_t alongAC = 0, mismatches = 0, flipped = 0;
        std::vector<uint8_t> split(size_t(n - 1) * (n - 1));
        for (uint32_t j = 0; j + 1 < n; ++j)
            for (uint32_t i = 0; i + 1 < n; ++i) {
                const uint32_t q = j * (n - 1) + i, a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
                const bool ac = ngi::splitsAlongAC(glm::vec3(f[q]), morph);
                alongAC += ac;
                split[q] = ac;
                flipped += !previous.empty() && previous[q] != split[q];
                const uint32_t expected[6] = {ac ? a : b, ac ? b : c, ac ? c : d, ac ? a : b, ac ? c : d, ac ? d : a};
                for (int k = 0; k < 6; ++k) mismatches += indices[6 * q + k] != expected[k];
            }
        EXPECT_EQ(mismatches, 0u) << "morph " << morph;
        // Both diagonals occur (the test would not see a swapped rule otherwise), and after the
        // first factor some quads flipped (a buffer left as it was would not pass).
        EXPECT_GT(alongAC, 0u);
        EXPECT_LT(alongAC, size_t(n - 1) * (n - 1));
        if (!previous.empty()) {
            EXPECT_GT(flipped, 0u) << "morph " << morph;
        }
        previous = split;
    }

    // The 16-bit index buffer (no vertices: the vertex shader geomorphs), which the device may pad a little.
    const size_t data = size_t(12) * (n - 1) * (n - 1);
    EXPECT_GE(surface.gridExpansionBytes(), data);
    EXPECT_LE(surface.gridExpansionBytes(), data + data / 8);
    surface.releaseGridExpansions();
    EXPECT_EQ(surface.gridExpansionBytes(), 0u);
    EXPECT_THROW(surface.readGridIndices(0), ngi::Error);
}

TEST_F(GridExpansion, ExpansionsAreCachedPerLevelAndADrawOfAnotherMorphFallsBack)
{
    auto surface = build(renderer(), ngi::sphereGeometryImage(33));
    const ngi::vk::DrawParams a = framing(surface, 1.25f), b = framing(surface, 1.5f), coarse = framing(surface, 2.0f);
    std::vector<uint32_t> counts;
    ngi::vk::DrawStats drawA{}, drawB{}, drawCoarse{};
    ngi::vk::OffscreenTarget target(renderer(), 32, 32);
    target.render(
        [&](VkCommandBuffer cmd) {
            drawA = renderer().recordDraw(cmd, surface, a, target.extent());
            drawB = renderer().recordDraw(cmd, surface, b, target.extent());
            drawCoarse = renderer().recordDraw(cmd, surface, coarse, target.extent());
        },
        kClear,
        [&](VkCommandBuffer cmd) {
            counts.push_back(renderer().recordGridExpansion(cmd, surface, a));
            counts.push_back(renderer().recordGridExpansion(cmd, surface, a));       // cached
            counts.push_back(renderer().recordGridExpansion(cmd, surface, b));       // same level, another morph
            counts.push_back(renderer().recordGridExpansion(cmd, surface, coarse));  // another level
        });
    EXPECT_EQ(counts, (std::vector<uint32_t>{1, 0, 1, 1}));
    // The level's buffer holds b's diagonals when a is drawn: a falls back to per quad.
    EXPECT_FALSE(drawA.sharedVertices);
    EXPECT_TRUE(drawB.sharedVertices);
    EXPECT_TRUE(drawCoarse.sharedVertices);
    EXPECT_EQ(surface.deviceAllocationCount(), 2u + 2u);  // the images' two pools, two expanded levels' index buffers
    surface.releaseGridExpansions();
    EXPECT_EQ(surface.deviceAllocationCount(), 2u);
}

TEST_F(GridExpansion, PerQuadWaysWhereSharedVerticesCannotDraw)
{
    auto surface = build(renderer(), ngi::sphereGeometryImage(33));
    ngi::vk::OffscreenTarget target(renderer(), 32, 32);
    ngi::vk::DrawStats stats{};
    uint32_t expanded = 0;
    // Wireframe reads the barycentrics; a grid size between nested sizes samples bilinearly.
    ngi::vk::DrawParams wire = framing(surface, 1.0f);
    wire.mode = ngi::vk::ShadingMode::Wireframe;
    frame(renderer(), target, surface, wire, true, stats, expanded);
    EXPECT_EQ(expanded, 0u);
    EXPECT_FALSE(stats.sharedVertices);
    EXPECT_EQ(stats.vertexInvocations, 4u * (stats.gridSize - 1) * (stats.gridSize - 1));
    ngi::vk::DrawParams between = framing(surface, 0.0f);
    between.gridSize = 24;
    frame(renderer(), target, surface, between, true, stats, expanded);
    EXPECT_EQ(expanded, 0u);
    EXPECT_FALSE(stats.sharedVertices);
    ngi::vk::DrawParams nested = between;
    nested.gridSize = 17;
    frame(renderer(), target, surface, nested, true, stats, expanded);
    EXPECT_EQ(expanded, 1u);
    EXPECT_TRUE(stats.sharedVertices);
    // The option off: never expanded.
    ngi::vk::RendererOptions off;
    off.gridExpansion = false;
    const ngi::vk::Renderer perQuad(context(), off);
    frame(perQuad, target, surface, nested, true, stats, expanded);
    EXPECT_EQ(expanded, 0u);
    EXPECT_FALSE(stats.sharedVertices);
    surface.releaseGridExpansions();
}

TEST_F(GridExpansion, HostFragmentShadersAreReadForTheBarycentrics)
{
    // surface.frag loads location 2 (wireframe); the host test shader declares it and never
    // reads it; indexed_mesh.vert reads its inputs 0 and 1 only.
    EXPECT_TRUE(ngi::vk::shaderReadsInput(surface_frag_spv, 2));
    EXPECT_FALSE(ngi::vk::shaderReadsInput(host_world_frag_spv, 2));
    EXPECT_TRUE(ngi::vk::shaderReadsInput(host_world_frag_spv, 4));
    EXPECT_TRUE(ngi::vk::shaderReadsInput(indexed_mesh_vert_spv, 1));
    EXPECT_FALSE(ngi::vk::shaderReadsInput(indexed_mesh_vert_spv, 2));
    EXPECT_FALSE(ngi::vk::shaderReadsInput({}, 2));
    // A host pipeline with ngi's own fragment shader given explicitly reads it in every mode.
    ngi::test::HostPass pass(context(), renderer().options().pass(), 16, 16);
    const ngi::vk::SurfacePipeline own(renderer(), pass.pass());
    const ngi::vk::SurfacePipeline explicitFrag(renderer(), pass.pass(), surface_frag_spv);
    ngi::vk::PassDescription depthOnly = pass.pass();
    depthOnly.colorFormats.clear();
    const ngi::vk::SurfacePipeline depth(renderer(), depthOnly);
    EXPECT_FALSE(own.readsBarycentrics(ngi::vk::ShadingMode::Shaded));
    EXPECT_TRUE(own.readsBarycentrics(ngi::vk::ShadingMode::Wireframe));
    EXPECT_TRUE(explicitFrag.readsBarycentrics(ngi::vk::ShadingMode::Shaded));
    EXPECT_FALSE(depth.readsBarycentrics(ngi::vk::ShadingMode::Wireframe));
}

TEST_F(GridExpansion, BatchedBucketsOfOneMorphDrawSharedVerticesPixelIdentically)
{
    auto surface = build(renderer(), ngi::sphereGeometryImage(33));
    ngi::test::HostPass pass(context(), renderer().options().pass(), 96, 64);
    const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass());
    ngi::vk::DrawBatch batch(renderer(), 64);
    // Three instances at LoD 1.5 (one bucket, one morph) and two at 0.25 and 0.75 (one
    // bucket, two morphs: drawn per quad).
    const float lods[5] = {1.5f, 0.25f, 1.5f, 0.75f, 1.5f};
    for (int i = 0; i < 5; ++i) {
        glm::mat4 w =
            glm::translate(glm::mat4(1.0f), glm::vec3(0.45f * float(i - 2), 0.1f * float(i % 2), -0.2f * float(i)));
        batch.add(surface, glm::scale(w, glm::vec3(0.4f)) * glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f)), lods[i]);
    }
    ngi::vk::BatchParams bp;
    bp.pipeline = &pipeline;
    bp.viewProjection = glm::mat4(1.0f);
    bp.viewProjection[2][2] = 0.5f;  // z in [-1, 1] -> [0, 1]
    bp.viewProjection[3][2] = 0.5f;
    bp.eye = glm::vec3(0.0f, 0.0f, -3.0f);
    ngi::vk::BatchStats perQuadStats, sharedStats;
    surface.releaseGridExpansions();
    const auto perQuad =
        pass.render([&](VkCommandBuffer cmd) { perQuadStats = batch.record(cmd, bp, pass.extent()); }, 1.0f);
    // The expansion in its own submission before the pass's (the same queue orders them).
    uint32_t expanded = 0;
    context().submitAndWait([&](VkCommandBuffer cmd) { expanded = batch.recordGridExpansion(cmd); });
    const auto shared =
        pass.render([&](VkCommandBuffer cmd) { sharedStats = batch.record(cmd, bp, pass.extent()); }, 1.0f);
    EXPECT_EQ(expanded, 1u);
    EXPECT_EQ(perQuadStats.buckets, 2u);
    EXPECT_EQ(perQuadStats.sharedBuckets, 0u);
    EXPECT_EQ(sharedStats.buckets, 2u);
    EXPECT_EQ(sharedStats.sharedBuckets, 1u);
    EXPECT_LT(sharedStats.vertexInvocations, perQuadStats.vertexInvocations);
    EXPECT_GT(covered(shared), size_t(96) * 64 / 16);
    EXPECT_EQ(perQuad, shared);
    surface.releaseGridExpansions();
}

TEST_F(GridExpansion, WorldSpaceOutputsAreThePerQuadOnesInSingleAndBatchedDraws)
{
    // A host fragment shader (host_world.frag, which never reads the barycentrics) writes the
    // world-space position and normal outputs to two attachments; shared and per-quad draws
    // write the same bytes, in a single draw (world = normalized space) and in a batched one
    // (a non-uniform scale, a turn and a move: normals through the cofactor matrix).
    const ngi::vk::Context& c = context();
    auto surface = build(renderer(), ngi::rippledTorusGeometryImage(65));
    const float scale[4] = {1.0f, 0.0f, 0.0f, 0.0f};
    const ngi::test::HostUniformSet host(c, std::as_bytes(std::span(scale)), VK_SHADER_STAGE_FRAGMENT_BIT);

    ngi::vk::PassDescription desc = renderer().options().pass();
    desc.colorFormats = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM};
    ngi::test::HostPass pass(c, desc, 80, 80);
    const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass(), host_world_frag_spv, host.layouts());
    ASSERT_FALSE(pipeline.readsBarycentrics(ngi::vk::ShadingMode::Shaded));

    const glm::mat4 world = glm::translate(glm::mat4(1.0f), glm::vec3(0.1f, -0.1f, 0.2f)) *
        glm::rotate(glm::mat4(1.0f), glm::radians(35.0f), glm::vec3(0.3f, 1.0f, 0.0f)) *
        glm::scale(glm::mat4(1.0f), glm::vec3(0.9f, 0.6f, 0.75f)) * glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f));
    glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(40.0f), 1.0f, 0.5f, 10.0f);
    proj[1][1] *= -1.0f;
    const glm::vec3 eye(0.4f, 0.6f, 2.0f);
    const glm::mat4 viewProjection = proj * glm::lookAtRH(eye, glm::vec3(0.0f), glm::vec3(0, 1, 0));
    const float lod = 1.4f;  // level 1, geomorphing
    ngi::vk::DrawBatch batch(renderer(), 8);
    for (const bool batched : {false, true}) {
        std::vector<uint8_t> frames[2][2];  // [shared][attachment]
        for (const bool shared : {false, true}) {
            surface.releaseGridExpansions();
            batch.clear();
            batch.add(surface, world, lod);
            ngi::vk::DrawParams p;
            p.pipeline = &pipeline;
            p.viewProjection = viewProjection * world;  // a single draw: normalized -> clip
            p.eye = glm::vec3(glm::inverse(world) * glm::vec4(eye, 1.0f));
            p.lod = lod;
            if (shared)
                c.submitAndWait([&](VkCommandBuffer cmd) {
                    EXPECT_EQ(
                        batched ? batch.recordGridExpansion(cmd) : renderer().recordGridExpansion(cmd, surface, p), 1u);
                });
            for (size_t a = 0; a < 2; ++a)
                frames[shared][a] = pass.render(
                    [&](VkCommandBuffer cmd) {
                        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(),
                                                ngi::vk::SurfacePipeline::firstHostSet, 1, &host.set, 0, nullptr);
                        if (batched) {
                            ngi::vk::BatchParams bp;
                            bp.pipeline = &pipeline;
                            bp.viewProjection = viewProjection;
                            bp.eye = eye;
                            EXPECT_EQ(batch.record(cmd, bp, pass.extent()).sharedBuckets, shared ? 1u : 0u);
                        } else {
                            EXPECT_EQ(renderer().recordDraw(cmd, surface, p, pass.extent()).sharedVertices, shared);
                        }
                    },
                    1.0f, {{0.0f, 0.0f, 0.0f, 0.0f}}, a);
        }
        for (size_t a = 0; a < 2; ++a) {
            EXPECT_GT(covered(frames[1][a]), size_t(80) * 80 / 10) << (batched ? "batched" : "single");
            EXPECT_EQ(frames[0][a], frames[1][a]) << (batched ? "batched" : "single") << ", attachment " << a;
        }
        batch.clear();  // before the next round's records: the GPU has finished (render waits)
    }
    surface.releaseGridExpansions();
}

}  // namespace
