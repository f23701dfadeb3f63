// Drawing into a host engine's own passes (PassDescription, SurfacePipeline): reverse-Z,
// stencil formats, classic render passes, depth-only passes, several colour attachments,
// the host's viewport, and per-instance world matrices with the asset's de-normalization.
#include "host_pass.h"
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/surface.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <cstring>

namespace {

constexpr uint32_t kSize = 96;

using HostPassTest = VulkanTest;

ngi::vk::GeometryImageSurface sphere(const ngi::vk::Renderer& r)
{
    const ngi::AnalyticSurface s = ngi::sphereGeometryImage(33);
    ngi::vk::GeometryImageSurface surface(r, s.positions, s.normals, s.positions.size);
    r.context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd); });
    surface.releaseUpload();
    return surface;
}

struct Coverage {
    size_t pixels = 0;
    double x = 0.0, y = 0.0;  // centroid of the covered pixels
};

Coverage coverage(const std::vector<uint8_t>& rgba, uint32_t width)
{
    Coverage c;
    for (size_t i = 0; i < rgba.size() / 4; ++i)
        if (rgba[4 * i] | rgba[4 * i + 1] | rgba[4 * i + 2]) {
            ++c.pixels;
            c.x += double(i % width);
            c.y += double(i / width);
        }
    if (c.pixels) {
        c.x /= double(c.pixels);
        c.y /= double(c.pixels);
    }
    return c;
}

ngi::vk::OrbitCamera frontCamera()
{
    ngi::vk::OrbitCamera camera;
    camera.target = glm::vec3(0.5f);
    camera.distance = 2.5f;
    camera.yawDegrees = 0.0f;
    camera.pitchDegrees = 0.0f;
    camera.nearPlane = 0.5f;
    camera.farPlane = 10.0f;
    return camera;
}

// Reverse-Z: depth 1 at the near plane, 0 at the far plane (clear to 0, GREATER_OR_EQUAL).
glm::mat4 reverseZProjection(const ngi::vk::OrbitCamera& c)
{
    glm::mat4 p = glm::perspectiveRH_ZO(glm::radians(c.fovYDegrees), 1.0f, c.farPlane, c.nearPlane);
    p[1][1] *= -1.0f;
    return p;
}

TEST_F(HostPassTest, DefaultPassMatchesTheRenderersOwnPipeline)
{
    const auto surface = sphere(renderer());
    const auto camera = frontCamera();
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const auto own = target.render(
        [&](VkCommandBuffer cmd) { renderer().recordDraw(cmd, surface, p, target.extent()); }, {0, 0, 0, 1});
    ngi::test::HostPass pass(context(), renderer().options().pass(), kSize, kSize);
    const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass());
    p.pipeline = &pipeline;
    const auto host =
        pass.render([&](VkCommandBuffer cmd) { renderer().recordDraw(cmd, surface, p, pass.extent()); }, 1.0f);
    EXPECT_EQ(own, host);
    EXPECT_GT(coverage(own, kSize).pixels, kSize * kSize / 8);
}

TEST_F(HostPassTest, ReverseZDrawsTheNearerInstance)
{
    // Two instances overlap in the image: a near one at LoD 0 and a far one at LoD 4, told
    // apart by their LoD colours. Reverse-Z keeps the near one; the same pipeline with the
    // classic compare op would keep the far one (what the fixed LESS_OR_EQUAL did).
    const auto surface = sphere(renderer());
    const auto camera = frontCamera();
    ngi::vk::PassDescription desc = renderer().options().pass();
    desc.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
    ngi::test::HostPass pass(context(), desc, kSize, kSize);
    const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass());
    auto frame = [&](bool nearOnly, bool farOnly) {
        return pass.render(
            [&](VkCommandBuffer cmd) {
                ngi::vk::DrawParams p;
                p.pipeline = &pipeline;
                p.viewProjection = reverseZProjection(camera) * camera.view();
                p.eye = camera.eye();
                p.mode = ngi::vk::ShadingMode::Lod;
                if (!farOnly) {
                    p.world = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, 0.6f));  // towards the camera
                    p.lod = 0.0f;
                    renderer().recordDraw(cmd, surface, p, pass.extent());
                }
                if (!nearOnly) {
                    p.world = glm::translate(glm::mat4(1.0f), glm::vec3(0.2f, 0.0f, -0.6f));
                    p.lod = 4.0f;
                    renderer().recordDraw(cmd, surface, p, pass.extent());
                }
            },
            0.0f);
    };
    const auto both = frame(false, false), nearOnly = frame(true, false), farOnly = frame(false, true);
    // The image centre is covered by both spheres: it shows the near one's colour.
    const size_t centre = 4 * (size_t(kSize / 2) * kSize + kSize / 2);
    ASSERT_NE(std::memcmp(&nearOnly[centre], &farOnly[centre], 3), 0);
    EXPECT_EQ(std::memcmp(&both[centre], &nearOnly[centre], 3), 0);
    EXPECT_GT(coverage(farOnly, kSize).pixels, 100u);
}

TEST_F(HostPassTest, StencilFormatsAndStencilTest)
{
    const auto surface = sphere(renderer());
    const auto camera = frontCamera();
    int tested = 0;
    for (VkFormat format : {VK_FORMAT_D32_SFLOAT_S8_UINT, VK_FORMAT_D24_UNORM_S8_UINT}) {
        VkFormatProperties props;
        vkGetPhysicalDeviceFormatProperties(context().physicalDevice, format, &props);
        if (!(props.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT)) continue;
        ++tested;
        ngi::vk::PassDescription desc = renderer().options().pass();
        desc.depthFormat = desc.stencilFormat = format;
        ngi::test::HostPass pass(context(), desc, kSize, kSize);
        const ngi::vk::SurfacePipeline plain(renderer(), pass.pass());
        // A stencil test that never passes (stencil cleared to 0, reference 1, EQUAL).
        desc = pass.pass();
        desc.stencil = VkStencilOpState{
            VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_STENCIL_OP_KEEP, VK_COMPARE_OP_EQUAL, 0xff, 0xff, 1};
        const ngi::vk::SurfacePipeline masked(renderer(), desc);
        for (const ngi::vk::SurfacePipeline* pipeline : {&plain, &masked}) {
            ngi::vk::DrawParams p;
            p.pipeline = pipeline;
            p.viewProjection = camera.viewProjection(1.0f);
            p.eye = camera.eye();
            const auto rgba =
                pass.render([&](VkCommandBuffer cmd) { renderer().recordDraw(cmd, surface, p, pass.extent()); }, 1.0f);
            if (pipeline == &plain)
                EXPECT_GT(coverage(rgba, kSize).pixels, kSize * kSize / 8) << format;
            else
                EXPECT_EQ(coverage(rgba, kSize).pixels, 0u) << format;
        }
    }
    EXPECT_GT(tested, 0) << "no depth/stencil format to test";
}

TEST_F(HostPassTest, ClassicRenderPassMatchesDynamicRendering)
{
    const auto surface = sphere(renderer());
    const auto camera = frontCamera();
    ngi::vk::DrawParams p;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    std::vector<uint8_t> frames[2];
    for (bool renderPass : {false, true}) {
        ngi::test::HostPass pass(context(), renderer().options().pass(), kSize, kSize, renderPass);
        const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass());
        p.pipeline = &pipeline;
        frames[renderPass] =
            pass.render([&](VkCommandBuffer cmd) { renderer().recordDraw(cmd, surface, p, pass.extent()); }, 1.0f);
    }
    EXPECT_EQ(frames[0], frames[1]);
    EXPECT_GT(coverage(frames[1], kSize).pixels, kSize * kSize / 8);
}

TEST_F(HostPassTest, DepthOnlyPassWritesTheSilhouette)
{
    const auto surface = sphere(renderer());
    const auto camera = frontCamera();
    ngi::vk::PassDescription desc;
    desc.colorFormats = {};
    desc.depthFormat = VK_FORMAT_D32_SFLOAT;
    desc.dynamicDepthBias = true;
    ngi::test::HostPass shadow(context(), desc, kSize, kSize);
    const ngi::vk::SurfacePipeline pipeline(renderer(), shadow.pass());
    ngi::vk::DrawParams p;
    p.pipeline = &pipeline;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    const auto bytes = shadow.render(
        [&](VkCommandBuffer cmd) {
            vkCmdSetDepthBias(cmd, 0.0f, 0.0f, 0.0f);
            renderer().recordDraw(cmd, surface, p, shadow.extent());
        },
        1.0f);
    std::vector<float> depth(kSize * kSize);
    std::memcpy(depth.data(), bytes.data(), depth.size() * sizeof(float));
    size_t written = 0;
    for (float d : depth) written += d < 1.0f;
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    p.pipeline = nullptr;
    const size_t shaded =
        coverage(target.render([&](VkCommandBuffer cmd) { renderer().recordDraw(cmd, surface, p, target.extent()); },
                               {0, 0, 0, 1}),
                 kSize)
            .pixels;
    EXPECT_EQ(written, shaded);
    EXPECT_GT(written, kSize * kSize / 8);
}

TEST_F(HostPassTest, TwoColourAttachmentsDrawAttachmentZero)
{
    // Attachment 1 is masked (write mask 0): valid without undefined-value warnings.
    const auto surface = sphere(renderer());
    const auto camera = frontCamera();
    ngi::vk::PassDescription desc = renderer().options().pass();
    desc.colorFormats = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R16G16B16A16_SFLOAT};
    ngi::test::HostPass pass(context(), desc, kSize, kSize);
    const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass());
    ngi::vk::DrawParams p;
    p.pipeline = &pipeline;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    const auto rgba =
        pass.render([&](VkCommandBuffer cmd) { renderer().recordDraw(cmd, surface, p, pass.extent()); }, 1.0f);
    EXPECT_GT(coverage(rgba, kSize).pixels, kSize * kSize / 8);
}

TEST_F(HostPassTest, ViewportIsTheCallersOrTheHosts)
{
    // Split screen: the same view drawn into the left half (params.viewport) and the right
    // half (the host's own vkCmdSetViewport, no extent given: ngi leaves it alone).
    const auto surface = sphere(renderer());
    const auto camera = frontCamera();
    ngi::test::HostPass pass(context(), renderer().options().pass(), 2 * kSize, kSize);
    const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass());
    ngi::vk::DrawParams p;
    p.pipeline = &pipeline;
    p.viewProjection = camera.viewProjection(1.0f);
    p.eye = camera.eye();
    auto frame = [&](bool left, bool right) {
        return pass.render(
            [&](VkCommandBuffer cmd) {
                if (left) {
                    ngi::vk::DrawParams l = p;
                    l.viewport = VkViewport{0, 0, float(kSize), float(kSize), 0, 1};
                    l.scissor = VkRect2D{{0, 0}, {kSize, kSize}};
                    renderer().recordDraw(cmd, surface, l);
                }
                if (right) {
                    const VkViewport v{float(kSize), 0, float(kSize), float(kSize), 0, 1};
                    const VkRect2D s{{int32_t(kSize), 0}, {kSize, kSize}};
                    vkCmdSetViewport(cmd, 0, 1, &v);
                    vkCmdSetScissor(cmd, 0, 1, &s);
                    renderer().recordDraw(cmd, surface, p);
                }
            },
            1.0f);
    };
    const Coverage l = coverage(frame(true, false), 2 * kSize), r = coverage(frame(false, true), 2 * kSize);
    const Coverage both = coverage(frame(true, true), 2 * kSize);
    EXPECT_GT(l.pixels, kSize * kSize / 8);
    EXPECT_EQ(l.pixels, r.pixels);
    EXPECT_EQ(both.pixels, l.pixels + r.pixels);
    EXPECT_NEAR(l.x, kSize / 2.0, 1.0);
    EXPECT_NEAR(r.x, kSize * 1.5, 1.0);
    EXPECT_NEAR(l.y, r.y, 1e-9);
}

TEST_F(HostPassTest, WorldMatrixAppliesTheAssetsDenormalization)
{
    // An asset whose object space is a sphere of radius 2 around (10, 0, 0) (offset/scale of
    // the normalized unit sphere); the world matrix moves that centre to `centre`.
    ngi::Asset asset = ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(33), 2);
    asset.scale = glm::vec3(4.0f);
    asset.offset = glm::vec3(10.0f, 0.0f, 0.0f) - 0.5f * asset.scale;  // object-space centre (10, 0, 0), radius 2
    ngi::vk::AssetSurface surface(renderer(), asset);
    surface.build();
    // A camera at the origin looking down -z; the instance's centre at (1.5, 1, -12) in world.
    const glm::mat4 view = glm::lookAtRH(glm::vec3(0.0f), glm::vec3(0, 0, -1), glm::vec3(0, 1, 0));
    glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(40.0f), 1.0f, 1.0f, 100.0f);
    proj[1][1] *= -1.0f;
    const glm::vec3 centre(1.5f, 1.0f, -12.0f);
    ngi::vk::DrawParams p;
    p.viewProjection = proj * view;
    p.eye = glm::vec3(0.0f);
    p.world = glm::translate(glm::mat4(1.0f), centre - glm::vec3(10.0f, 0.0f, 0.0f));
    ngi::vk::OffscreenTarget target(renderer(), kSize, kSize);
    const Coverage c = coverage(
        target.render([&](VkCommandBuffer cmd) { surface.recordDraw(cmd, p, target.extent()); }, {0, 0, 0, 1}), kSize);
    const glm::vec4 clip = p.viewProjection * glm::vec4(centre, 1.0f);
    const double px = (clip.x / clip.w * 0.5 + 0.5) * kSize - 0.5, py = (clip.y / clip.w * 0.5 + 0.5) * kSize - 0.5;
    EXPECT_NEAR(c.x, px, 0.6);
    EXPECT_NEAR(c.y, py, 0.6);
    // Radius 2 at distance ~12.1: the silhouette's area (a sphere's projection is close to a
    // circle near the image centre).
    const double rPix = std::tan(std::asin(2.0 / glm::length(centre))) / std::tan(glm::radians(20.0)) * (kSize / 2.0);
    EXPECT_NEAR(double(c.pixels) / (M_PI * rPix * rPix), 1.0, 0.06);
}

}  // namespace
