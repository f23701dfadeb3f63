// The move-only owners of buffers, images and device handles (resources.h): each frees its
// object exactly once, on scope exit, reset or move-assignment, and on a creation that throws
// half-way. The fixture's validation layer turns a double destroy or a use after free into a
// test failure.
#include "vulkan_fixture.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/resources.h"
#include "ngi/engine/surface.h"
#include "ngi/error.h"

#include <optional>
#include <utility>

namespace {

using Resources = VulkanTest;

constexpr VkMemoryPropertyFlags kHostMemory =
    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;

TEST_F(Resources, UniqueBufferMovesOwnershipAndFreesOnce)
{
    ngi::vk::UniqueBuffer a(context(), 256, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, kHostMemory);
    ASSERT_TRUE(a);
    ASSERT_NE(a->mapped, nullptr);
    const VkBuffer handle = a->buffer;

    ngi::vk::UniqueBuffer b(std::move(a));
    EXPECT_FALSE(a);  // NOLINT(bugprone-use-after-move): a moved-from owner is empty by contract
    EXPECT_EQ(b->buffer, handle);
    EXPECT_EQ(b->size, 256u);

    // Move-assignment onto a live owner frees the buffer it held.
    ngi::vk::UniqueBuffer c(context(), 64, VK_BUFFER_USAGE_TRANSFER_DST_BIT, kHostMemory);
    c = std::move(b);
    EXPECT_FALSE(b);  // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(c->buffer, handle);

    // release() gives the buffer up; the caller destroys it with the free function.
    ngi::vk::Buffer raw = c.release();
    EXPECT_FALSE(c);
    ngi::vk::destroyBuffer(context(), raw);
    c.reset();  // resetting an empty owner does nothing
}

TEST_F(Resources, UniqueImageMovesOwnershipAndFreesOnce)
{
    std::optional<ngi::vk::UniqueImage> a;
    a.emplace(context(), 8, 4, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT, VK_IMAGE_ASPECT_COLOR_BIT);
    ASSERT_TRUE(*a);
    EXPECT_EQ((*a)->width, 8u);
    EXPECT_EQ((*a)->height, 4u);
    EXPECT_NE((*a)->view, VK_NULL_HANDLE);
    ngi::vk::UniqueImage b = std::move(*a);
    a.reset();  // destroying the moved-from owner must not touch the image
    EXPECT_TRUE(b);
    b.reset();
    EXPECT_FALSE(b);
    EXPECT_EQ(b->image, VK_NULL_HANDLE);
}

TEST_F(Resources, BufferCreationThatFailsHalfWayThrowsAndCleansUp)
{
    // vkCreateBuffer succeeds, then no memory type is protected + host-visible: the buffer
    // already made must be freed by its owner inside createBuffer, and the error reported.
    const VkMemoryPropertyFlags impossible = VK_MEMORY_PROPERTY_PROTECTED_BIT | VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT;
    try {
        ngi::vk::UniqueBuffer b(context(), 256, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, impossible);
        FAIL() << "a buffer in protected host-visible memory was created";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("memory type"), std::string::npos) << e.what();
    }
}

TEST_F(Resources, UniqueHandleMovesOwnershipAndFreesOnce)
{
    ngi::vk::UniqueFence a(context().device);
    EXPECT_FALSE(a);
    VkFenceCreateInfo info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    ASSERT_EQ(vkCreateFence(context().device, &info, nullptr, a.out()), VK_SUCCESS);
    const VkFence handle = a.get();
    ngi::vk::UniqueFence b(std::move(a));
    EXPECT_FALSE(a);  // NOLINT(bugprone-use-after-move)
    EXPECT_EQ(b.get(), handle);
    b = ngi::vk::UniqueFence(context().device);  // frees the fence
    EXPECT_FALSE(b);
}

TEST_F(Resources, MovedSurfaceKeepsItsImagesAndTheSourceHoldsNone)
{
    // The surface is moved twice (as fromAsset and the viewer do); each moved-from surface
    // is destroyed first. Before the owners, the hand-written move and destructor had to
    // stay in step by hand, and a throwing constructor ran the destructor explicitly.
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(17);
    std::optional<ngi::vk::GeometryImageSurface> first;
    first.emplace(renderer(), sphere.positions, sphere.normals, 17u);
    const VkDeviceSize bytes = first->gpuBytes();
    ASSERT_GT(bytes, 0u);
    std::optional<ngi::vk::GeometryImageSurface> second(std::move(*first));
    EXPECT_EQ(first->gpuBytes(), 0u);  // moved-from: holds no image
    first.reset();
    ngi::vk::GeometryImageSurface surface(std::move(*second));
    second.reset();
    EXPECT_EQ(surface.gpuBytes(), bytes);
    context().submitAndWait([&](VkCommandBuffer cmd) { surface.recordBuild(cmd); });
    surface.releaseUpload();
    surface.releaseUpload();  // a second release is a no-op
    EXPECT_EQ(surface.readLevel(0, false).size(), size_t(17) * 17);
}

TEST_F(Resources, SubmitThatThrowsWhileRecordingFreesItsCommandBuffer)
{
    // The exception leaves submitAndWait through the command buffer's owner; the next submit
    // must still work (the pool is not left with a half-recorded buffer).
    EXPECT_THROW(context().submitAndWait([](VkCommandBuffer) { throw ngi::Error("recording failed"); }), ngi::Error);
    bool recorded = false;
    context().submitAndWait([&](VkCommandBuffer) { recorded = true; });
    EXPECT_TRUE(recorded);
}

TEST_F(Resources, OffscreenTargetFreesItsImages)
{
    for (int i = 0; i < 2; ++i) {
        ngi::vk::OffscreenTarget target(renderer(), 16, 8);
        const auto pixels = target.render([](VkCommandBuffer) {}, {0.25f, 0.5f, 0.75f, 1.0f});
        ASSERT_EQ(pixels.size(), size_t(16) * 8 * 4);
        EXPECT_NEAR(pixels[0], 64, 1);  // 0.25 in UNORM8
    }
}

}  // namespace
