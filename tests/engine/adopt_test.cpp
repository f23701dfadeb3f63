// Context::adopt checks what the host enabled (missingDeviceRequirements).
#include "vulkan_fixture.h"

#include "ngi/engine/renderer.h"
#include "ngi/error.h"

namespace {

VkPhysicalDeviceProperties goodProperties()
{
    VkPhysicalDeviceProperties p{};
    p.apiVersion = VK_API_VERSION_1_3;
    p.limits.maxPushConstantsSize = 128;
    p.limits.maxImageDimension2D = 4096;
    return p;
}

constexpr VkQueueFlags kGraphicsCompute = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;

TEST(DeviceRequirements, DynamicRenderingFromEitherFeatureStruct)
{
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    const auto none = ngi::vk::missingDeviceRequirements(goodProperties(), kGraphicsCompute, info);
    ASSERT_EQ(none.size(), 1u);
    EXPECT_NE(none[0].find("dynamicRendering"), std::string::npos) << none[0];

    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    f2.pNext = &f13;
    info.pNext = &f2;
    EXPECT_EQ(ngi::vk::missingDeviceRequirements(goodProperties(), kGraphicsCompute, info).size(), 1u);  // present, off
    f13.dynamicRendering = VK_TRUE;
    EXPECT_TRUE(ngi::vk::missingDeviceRequirements(goodProperties(), kGraphicsCompute, info).empty());

    VkPhysicalDeviceDynamicRenderingFeatures khr{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DYNAMIC_RENDERING_FEATURES};
    khr.dynamicRendering = VK_TRUE;
    info.pNext = &khr;
    EXPECT_TRUE(ngi::vk::missingDeviceRequirements(goodProperties(), kGraphicsCompute, info).empty());
}

TEST(DeviceRequirements, EverythingMissingIsListed)
{
    VkPhysicalDeviceProperties p = goodProperties();
    p.apiVersion = VK_API_VERSION_1_2;
    p.limits.maxPushConstantsSize = 64;
    p.limits.maxImageDimension2D = 512;
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    const auto missing = ngi::vk::missingDeviceRequirements(p, VK_QUEUE_GRAPHICS_BIT, info);
    ASSERT_EQ(missing.size(), 5u);
    EXPECT_NE(missing[0].find("Vulkan 1.3 (the device reports 1.2)"), std::string::npos) << missing[0];
    EXPECT_NE(missing[1].find("lacks compute"), std::string::npos) << missing[1];
    EXPECT_NE(missing[3].find("maxPushConstantsSize"), std::string::npos) << missing[3];
    EXPECT_NE(missing[4].find("maxImageDimension2D"), std::string::npos) << missing[4];
}

using Adopt = VulkanTest;

TEST_F(Adopt, RefusesADeviceWithoutDynamicRenderingAndWrapsOneWithIt)
{
    const ngi::vk::Context& c = context();
    VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    try {
        ngi::vk::Context::adopt(c.instance, c.physicalDevice, c.device, c.queue, c.queueFamily, info);
        FAIL() << "adopt accepted a device without dynamicRendering";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("lacks what ngi needs: the dynamicRendering feature"), std::string::npos)
            << e.what();
    }
    VkPhysicalDeviceVulkan13Features f13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    f13.dynamicRendering = VK_TRUE;
    info.pNext = &f13;
    auto adopted = ngi::vk::Context::adopt(c.instance, c.physicalDevice, c.device, c.queue, c.queueFamily, info);
    EXPECT_FALSE(adopted->independentBlend);  // not in this create info
    ngi::vk::Renderer renderer(*adopted);     // works on the adopted handles
    EXPECT_THROW(ngi::vk::Context::adopt(c.instance, c.physicalDevice, c.device, c.queue, 99, info), ngi::Error);
}

}  // namespace
