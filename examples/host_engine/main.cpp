// ngi-host-demo: a host engine's frame with ngi as a library.
//
// The host creates its own VkInstance and VkDevice (not ngi::vk::Context::create), hands them
// to ngi with Context::adopt, and records one frame into its own command buffer: its own
// reverse-Z colour + depth/stencil dynamic-rendering pass, its own ground pipeline (which
// writes stencil 1), and two ngi instances placed by world matrices, each at the LoD of a
// one-pixel screen-space geometric error (ngi/engine/lod.h). The frame is read back and
// written to a PNG. --check verifies the pixels (both instances drawn where they project, the
// half-sunk one cut by the ground); any validation message fails the run.
//
// usage: ngi-host-demo [-o OUT.png] [--asset A.ngi] [--validation] [--check]
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/context.h"
#include "ngi/engine/lod.h"
#include "ngi/engine/pipelines.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/png_io.h"

#include "host_shaders/ground_frag.h"
#include "host_shaders/ground_vert.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

constexpr uint32_t kWidth = 512, kHeight = 320;
constexpr VkClearColorValue kSky{{0.10f, 0.12f, 0.30f, 1.0f}};
const glm::vec4 kGround{0.20f, 0.55f, 0.22f, 1.0f};

int gValidationMessages = 0;

VKAPI_ATTR VkBool32 VKAPI_CALL onMessage(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void*)
{
    ++gValidationMessages;
    std::fprintf(stderr, "validation: %s\n", data->pMessage ? data->pMessage : "");
    return VK_FALSE;
}

struct GroundPush {
    glm::mat4 viewProjection;
    glm::vec4 colour;
    float halfSize;
};

// The host's device: the first Vulkan 1.3 device with a graphics + compute queue family.
struct HostDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t family = 0;
    VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    VkDeviceQueueCreateInfo queueInfo{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    VkDeviceCreateInfo createInfo{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    float priority = 1.0f;

    explicit HostDevice(bool validation)
    {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "ngi-host-demo";
        app.apiVersion = VK_API_VERSION_1_3;
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const char* debugExtension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        info.pApplicationInfo = &app;
        info.enabledLayerCount = validation ? 1 : 0;
        info.ppEnabledLayerNames = &layer;
        info.enabledExtensionCount = validation ? 1 : 0;
        info.ppEnabledExtensionNames = &debugExtension;
        NGI_VK_CHECK(vkCreateInstance(&info, nullptr, &instance));
        if (validation) {
            VkDebugUtilsMessengerCreateInfoEXT m{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            m.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            m.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
            m.pfnUserCallback = onMessage;
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
            NGI_VK_CHECK(create(instance, &m, nullptr, &messenger));
        }
        uint32_t count = 0;
        vkEnumeratePhysicalDevices(instance, &count, nullptr);
        std::vector<VkPhysicalDevice> devices(count);
        vkEnumeratePhysicalDevices(instance, &count, devices.data());
        for (VkPhysicalDevice pd : devices) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(pd, &p);
            if (p.apiVersion < VK_API_VERSION_1_3) continue;
            uint32_t n = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
            std::vector<VkQueueFamilyProperties> families(n);
            vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
            for (uint32_t f = 0; f < n && !physical; ++f)
                if ((families[f].queueFlags & (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) ==
                    (VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT)) {
                    physical = pd;
                    family = f;
                }
            if (physical) break;
        }
        if (!physical) throw ngi::Error("ngi-host-demo: no Vulkan 1.3 device with a graphics+compute queue");
        features13.dynamicRendering = VK_TRUE;
        features.pNext = &features13;
        queueInfo.queueFamilyIndex = family;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;
        createInfo.pNext = &features;
        createInfo.queueCreateInfoCount = 1;
        createInfo.pQueueCreateInfos = &queueInfo;
        NGI_VK_CHECK(vkCreateDevice(physical, &createInfo, nullptr, &device));
        vkGetDeviceQueue(device, family, 0, &queue);
    }
    ~HostDevice()
    {
        if (device) vkDestroyDevice(device, nullptr);
        if (messenger) {
            auto destroy = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
            destroy(instance, messenger, nullptr);
        }
        if (instance) vkDestroyInstance(instance, nullptr);
    }
    HostDevice(const HostDevice&) = delete;
    HostDevice& operator=(const HostDevice&) = delete;
};

VkFormat depthStencilFormat(VkPhysicalDevice pd)
{
    for (VkFormat f : {VK_FORMAT_D32_SFLOAT_S8_UINT, VK_FORMAT_D24_UNORM_S8_UINT}) {
        VkFormatProperties p;
        vkGetPhysicalDeviceFormatProperties(pd, f, &p);
        if (p.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) return f;
    }
    throw ngi::Error("ngi-host-demo: no depth/stencil attachment format");
}

// World matrix that fits the asset's object-space bounds into a box of `size` (largest side)
// centred at `centre`.
glm::mat4 placeInstance(const ngi::vk::AssetLodMetrics& m, glm::vec3 centre, float size)
{
    const glm::vec3 extent = m.boundsMax - m.boundsMin;
    const float s = size / std::max({extent.x, extent.y, extent.z});
    return glm::scale(glm::translate(glm::mat4(1.0f), centre), glm::vec3(s)) *
           glm::translate(glm::mat4(1.0f), -0.5f * (m.boundsMin + m.boundsMax));
}

glm::vec2 toPixel(const glm::mat4& viewProjection, glm::vec3 p)
{
    const glm::vec4 c = viewProjection * glm::vec4(p, 1.0f);
    return {(c.x / c.w * 0.5f + 0.5f) * kWidth, (c.y / c.w * 0.5f + 0.5f) * kHeight};
}

int run(int argc, char** argv)
{
    std::string output = "host_demo.png", assetPath;
    bool validation = false, check = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-o" && i + 1 < argc) output = argv[++i];
        else if (a == "--asset" && i + 1 < argc) assetPath = argv[++i];
        else if (a == "--validation") validation = true;
        else if (a == "--check") check = true;
        else {
            std::fprintf(stderr, "usage: ngi-host-demo [-o OUT.png] [--asset A.ngi] [--validation] [--check]\n");
            return 1;
        }
    }

    HostDevice host(validation);
    // ngi checks what the host enabled (ngi::Error listing anything missing).
    auto context = ngi::vk::Context::adopt(host.instance, host.physical, host.device, host.queue, host.family,
                                           host.createInfo);
    const ngi::vk::Context& c = *context;
    ngi::vk::Renderer renderer(c);

    // The host's pass: RGBA8 + depth/stencil, reverse-Z (clear depth 0, GREATER_OR_EQUAL).
    ngi::vk::PassDescription pass;
    pass.colorFormats = {VK_FORMAT_R8G8B8A8_UNORM};
    pass.depthFormat = pass.stencilFormat = depthStencilFormat(host.physical);
    pass.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;
    const ngi::vk::SurfacePipeline ngiPipeline(renderer, pass);

    // The host's own ground pipeline and layout (stencil: writes 1 where the ground is).
    VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(GroundPush)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    ngi::vk::UniquePipelineLayout groundLayout(c.device);
    NGI_VK_CHECK(vkCreatePipelineLayout(c.device, &layoutInfo, nullptr, groundLayout.out()));
    ngi::vk::GraphicsPipelineDesc groundDesc;
    groundDesc.vertexSpirv = ground_vert_spv;
    groundDesc.fragmentSpirv = ground_frag_spv;
    groundDesc.layout = groundLayout.get();
    groundDesc.pass = pass;
    groundDesc.pass.stencil = VkStencilOpState{VK_STENCIL_OP_KEEP, VK_STENCIL_OP_REPLACE, VK_STENCIL_OP_KEEP,
                                               VK_COMPARE_OP_ALWAYS, 0xff, 0xff, 1};
    ngi::vk::UniquePipeline groundPipeline(c.device, ngi::vk::createGraphicsPipeline(c.device, groundDesc));

    // Two assets: the given one (or an analytic rippled torus) and an analytic sphere.
    std::vector<ngi::Asset> assets;
    assets.push_back(assetPath.empty() ? ngi::makeAnalyticAsset("torus", ngi::rippledTorusGeometryImage(257), 2)
                                       : ngi::readAsset(assetPath));
    assets.push_back(ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(257), 2));
    std::vector<std::unique_ptr<ngi::vk::AssetSurface>> surfaces;
    std::vector<ngi::vk::AssetLodMetrics> metrics;
    for (const ngi::Asset& a : assets) {
        surfaces.push_back(std::make_unique<ngi::vk::AssetSurface>(renderer, a));
        surfaces.back()->build();  // at load time: one submission per chart, waited for
        metrics.push_back(ngi::vk::measureLodMetrics(a));
    }
    // Instance 0 rests on the ground at x = -1; instance 1 is half sunk into it at x = +1.
    struct Instance {
        size_t asset;
        glm::vec3 centre;
        glm::mat4 world;
        float lod = 0.0f;
    };
    std::vector<Instance> instances = {{0, {-1.0f, 0.5f, 0.0f}, {}}, {1, {1.0f, 0.0f, 0.0f}, {}}};
    for (Instance& i : instances) i.world = placeInstance(metrics[i.asset], i.centre, 1.0f);

    const glm::vec3 eye(0.0f, 1.6f, 4.2f);
    const glm::mat4 view = glm::lookAtRH(eye, glm::vec3(0.0f, 0.3f, 0.0f), glm::vec3(0, 1, 0));
    glm::mat4 proj = glm::perspectiveRH_ZO(glm::radians(40.0f), float(kWidth) / kHeight, 100.0f, 0.1f);  // reverse-Z
    proj[1][1] *= -1.0f;
    const glm::mat4 viewProjection = proj * view;

    // Attachments and read-back.
    ngi::vk::UniqueImage colour(c, kWidth, kHeight, pass.colorFormats[0],
                                VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                VK_IMAGE_ASPECT_COLOR_BIT);
    ngi::vk::UniqueImage depth(c, kWidth, kHeight, pass.depthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                               VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT);
    ngi::vk::UniqueBuffer readback(c, VkDeviceSize(kWidth) * kHeight * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                   VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);

    // The host's command buffer.
    VkCommandPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    poolInfo.queueFamilyIndex = host.family;
    ngi::vk::UniqueHandle<VkCommandPool, vkDestroyCommandPool> pool(c.device);
    NGI_VK_CHECK(vkCreateCommandPool(c.device, &poolInfo, nullptr, pool.out()));
    VkCommandBufferAllocateInfo alloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    alloc.commandPool = pool.get();
    alloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    alloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkAllocateCommandBuffers(c.device, &alloc, &cmd));

    const auto cpuStart = std::chrono::steady_clock::now();
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    NGI_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    ngi::vk::imageBarrier(cmd, colour->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                          VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                          VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
    ngi::vk::imageBarrier(cmd, depth->image, VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT,
                          VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                          VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
                          VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
                          VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL);
    VkRenderingAttachmentInfo colourInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    colourInfo.imageView = colour->view;
    colourInfo.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    colourInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    colourInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    colourInfo.clearValue.color = kSky;
    VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
    depthInfo.imageView = depth->view;
    depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    depthInfo.clearValue.depthStencil = {0.0f, 0};  // reverse-Z: 0 is the far plane
    VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
    rendering.renderArea = {{0, 0}, {kWidth, kHeight}};
    rendering.layerCount = 1;
    rendering.colorAttachmentCount = 1;
    rendering.pColorAttachments = &colourInfo;
    rendering.pDepthAttachment = &depthInfo;
    rendering.pStencilAttachment = &depthInfo;
    vkCmdBeginRendering(cmd, &rendering);
    const VkViewport viewport{0.0f, 0.0f, float(kWidth), float(kHeight), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, {kWidth, kHeight}};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    const GroundPush ground{viewProjection, kGround, 3.0f};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, groundPipeline.get());
    vkCmdPushConstants(cmd, groundLayout.get(), VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(ground), &ground);
    vkCmdDraw(cmd, 6, 1, 0, 0);
    uint64_t triangles = 0;
    for (Instance& i : instances) {
        const ngi::vk::AssetLodMetrics& m = metrics[i.asset];
        i.lod = ngi::vk::instanceLod(m, m.geometricError, viewProjection, i.world, float(kHeight), 1.0f);
        ngi::vk::DrawParams p;
        p.pipeline = &ngiPipeline;
        p.viewProjection = viewProjection;
        p.world = i.world;
        p.eye = eye;
        p.lod = i.lod;
        triangles += surfaces[i.asset]->recordDraw(cmd, p).triangles;  // the host's viewport stays
    }
    vkCmdEndRendering(cmd);
    ngi::vk::imageBarrier(cmd, colour->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                          VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                          VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {kWidth, kHeight, 1};
    vkCmdCopyImageToBuffer(cmd, colour->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback->buffer, 1, &copy);
    ngi::vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                           VK_ACCESS_HOST_READ_BIT);
    NGI_VK_CHECK(vkEndCommandBuffer(cmd));
    const double cpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpuStart).count();

    ngi::vk::UniqueFence fence(c.device);
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    NGI_VK_CHECK(vkCreateFence(c.device, &fenceInfo, nullptr, fence.out()));
    VkSubmitInfo submit{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    submit.commandBufferCount = 1;
    submit.pCommandBuffers = &cmd;
    const auto gpuStart = std::chrono::steady_clock::now();
    NGI_VK_CHECK(vkQueueSubmit(host.queue, 1, &submit, fence.get()));
    const VkFence fences[] = {fence.get()};
    NGI_VK_CHECK(vkWaitForFences(c.device, 1, fences, VK_TRUE, UINT64_MAX));
    const double frameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - gpuStart).count();

    std::vector<uint8_t> pixels(size_t(kWidth) * kHeight * 4);
    std::memcpy(pixels.data(), readback->mapped, pixels.size());
    ngi::writePng8(output, kWidth, kHeight, 4, pixels.data());
    std::printf("device: %s\ninstances: %zu\n", c.properties.deviceName, instances.size());
    for (size_t k = 0; k < instances.size(); ++k)
        std::printf("instance %zu: %s at (%.1f, %.1f, %.1f), LoD %.2f (1 px geometric error)\n", k,
                    assets[instances[k].asset].sourceName.c_str(), instances[k].centre.x, instances[k].centre.y,
                    instances[k].centre.z, instances[k].lod);
    std::printf("frame: %llu ngi triangles, CPU record %.3f ms, submit-to-fence %.2f ms\nwrote %s\n",
                (unsigned long long)triangles, cpuMs, frameMs, output.c_str());

    int failures = 0;
    if (check) {
        // ngi's headlight shading is grey (r ~ g ~ b); the host's ground is green, the sky blue.
        auto at = [&](int x, int y) { return &pixels[(size_t(y) * kWidth + size_t(x)) * 4]; };
        auto isNgi = [&](const uint8_t* p) {
            return std::abs(int(p[0]) - int(p[1])) < 24 && std::abs(int(p[1]) - int(p[2])) < 24 && p[0] > 30;
        };
        auto isGround = [&](const uint8_t* p) { return p[1] > p[0] + 40 && p[1] > p[2] + 40; };
        size_t left = 0, right = 0, groundPixels = 0;
        for (int y = 0; y < int(kHeight); ++y)
            for (int x = 0; x < int(kWidth); ++x) {
                if (isNgi(at(x, y))) (x < int(kWidth) / 2 ? left : right)++;
                groundPixels += isGround(at(x, y));
            }
        auto expect = [&](bool ok, const std::string& what) {
            if (!ok) {
                std::fprintf(stderr, "check failed: %s\n", what.c_str());
                ++failures;
            }
        };
        expect(groundPixels > kWidth * kHeight / 10, "the host's ground covers " + std::to_string(groundPixels) + " pixels");
        expect(left > 2000, "instance 0 covers " + std::to_string(left) + " pixels");
        // The sphere's lower half is below the ground (reverse-Z depth test against the host's
        // depth). Seen from elevation e, the visible part is half its disc plus half the
        // ground circle's ellipse: (1 + sin e) / 2 of the whole sphere's disc (~0.68 here).
        const glm::vec2 top = toPixel(viewProjection, {1.0f, 0.45f, 0.0f});
        const glm::vec2 below = toPixel(viewProjection, {1.0f, -0.45f, 0.0f});
        expect(isNgi(at(int(top.x), int(top.y))), "the sphere's top is drawn at its projected position");
        expect(isGround(at(int(below.x), int(below.y))), "the sphere's sunk bottom is hidden by the ground");
        const float radiusPx =
            (toPixel(viewProjection, {1.5f, 0.0f, 0.0f}).x - toPixel(viewProjection, {0.5f, 0.0f, 0.0f}).x) / 2.0f;
        const double disc = 3.14159265 * radiusPx * radiusPx;
        expect(right > 0.5 * disc && right < 0.85 * disc,
               "the half-sunk sphere covers " + std::to_string(right) + " pixels (a whole one about " +
                   std::to_string(size_t(disc)) + ")");
        const glm::vec2 c0 = toPixel(viewProjection, instances[0].centre);
        expect(isNgi(at(int(c0.x), int(c0.y))), "instance 0 is drawn at its projected centre");
        std::printf("check: ground %zu px, instance 0 %zu px, instance 1 %zu px, %s\n", groundPixels, left, right,
                    failures ? "FAILED" : "ok");
    }
    std::printf("validation messages: %d\n", gValidationMessages);
    // ngi's objects (declared after `host`) go before the host destroys its device.
    return failures || gValidationMessages ? 2 : 0;
}

} // namespace

int main(int argc, char** argv)
{
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-host-demo: %s\n", e.what());
        return 1;
    }
}
