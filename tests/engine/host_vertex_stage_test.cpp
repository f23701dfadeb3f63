// ngi's public vertex stage under a host's own fragment shader (tests/engine/shaders/
// host_world.frag) with a host descriptor set (set 2): the world-space position and normal
// outputs of a batched draw are those of the instance's world matrix, non-uniform scale
// included (normals by the cofactor matrix).
#include "host_pass.h"
#include "host_uniform_set.h"
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/draw_batch.h"
#include "ngi/engine/surface.h"

#include "host_test_shaders/host_world_frag.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <span>

namespace {

constexpr uint32_t kSize = 96;

using HostVertexStageTest = VulkanTest;

TEST_F(HostVertexStageTest, HostFragmentShaderGetsWorldSpacePositionAndNormal)
{
    const ngi::vk::Context& c = context();
    const ngi::AnalyticSurface s = ngi::sphereGeometryImage(33);
    ngi::vk::GeometryImageSurface sphere(renderer(), s.positions, s.normals, s.positions.size);
    c.submitAndWait([&](VkCommandBuffer cmd) { sphere.recordBuild(cmd); });
    sphere.releaseUpload();

    // The host's set 2: one uniform block.
    const float scale[4] = {1.0f, 0.0f, 0.0f, 0.0f};
    const ngi::test::HostUniformSet host(c, std::as_bytes(std::span(scale)), VK_SHADER_STAGE_FRAGMENT_BIT);

    ngi::vk::PassDescription desc = renderer().options().pass();
    desc.colorFormats = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM};
    ngi::test::HostPass pass(c, desc, kSize, kSize);
    const ngi::vk::SurfacePipeline pipeline(renderer(), pass.pass(), host_world_frag_spv, host.layouts());

    // An ellipsoid: the unit-diameter sphere centred at the origin, scaled non-uniformly, turned, moved.
    const glm::vec3 centre(0.2f, -0.1f, 0.3f), axes(0.4f, 0.25f, 0.35f);
    const glm::mat4 rotation = glm::rotate(glm::mat4(1.0f), glm::radians(30.0f), glm::vec3(0, 1, 0));
    const glm::mat4 world = glm::translate(glm::mat4(1.0f), centre) * rotation * glm::scale(glm::mat4(1.0f), axes) *
        glm::scale(glm::mat4(1.0f), glm::vec3(2.0f)) * glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f));
    glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(40.0f), 1.0f, 0.5f, 10.0f);
    proj[1][1] *= -1.0f;
    ngi::vk::BatchParams params;
    params.pipeline = &pipeline;
    params.viewProjection = proj * glm::lookAtRH(centre + glm::vec3(0.3f, 0.5f, 2.2f), centre, glm::vec3(0, 1, 0));
    params.eye = centre + glm::vec3(0.3f, 0.5f, 2.2f);
    ngi::vk::DrawBatch batch(renderer(), 4);
    std::vector<uint8_t> attachments[2];
    for (size_t a = 0; a < 2; ++a) {
        batch.clear();
        batch.add(sphere, world, 0.0f);
        attachments[a] = pass.render(
            [&](VkCommandBuffer cmd) {
                // The host's set first: ngi's binds of sets 0 and 1 with the same layout keep it.
                vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(),
                                        ngi::vk::SurfacePipeline::firstHostSet, 1, &host.set, 0, nullptr);
                batch.record(cmd, params, pass.extent());
            },
            1.0f, {{0.0f, 0.0f, 0.0f, 0.0f}}, a);
    }
    // Object-space point of the ellipsoid (rotation undone), its implicit value and gradient.
    const glm::mat3 unrotate = glm::transpose(glm::mat3(rotation));
    size_t covered = 0, offSurface = 0, wrongNormal = 0;
    for (size_t i = 0; i < size_t(kSize) * kSize; ++i) {
        const uint8_t* p = &attachments[0][4 * i];
        const uint8_t* n = &attachments[1][4 * i];
        if (p[3] != 255) continue;
        ++covered;
        const glm::vec3 position = (glm::vec3(p[0], p[1], p[2]) / 255.0f - 0.5f) * 2.0f;
        const glm::vec3 normal = glm::normalize((glm::vec3(n[0], n[1], n[2]) / 255.0f - 0.5f) * 2.0f);
        const glm::vec3 q = unrotate * (position - centre);
        const float f = glm::length(q / axes);
        offSurface += std::abs(f - 1.0f) > 0.05f;
        const glm::vec3 gradient = glm::mat3(rotation) * (q / (axes * axes));
        wrongNormal += glm::dot(normal, glm::normalize(gradient)) < 0.97f;
    }
    EXPECT_GT(covered, size_t(kSize) * kSize / 10);
    EXPECT_EQ(offSurface, 0u) << "of " << covered << " pixels";
    EXPECT_EQ(wrongNormal, 0u) << "of " << covered << " pixels";
}

}  // namespace
