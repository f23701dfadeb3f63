// ngi-host-demo: a host engine's frames with ngi as a library.
//
// The host creates its own VkInstance and VkDevice (host_device.h; not Context::create) and
// hands them to ngi with Context::adopt. Per frame, into its own command buffer: a shadow
// pass (depth-only, the sun's orthographic view, depth bias) and a main pass (reverse-Z
// depth, 4x MSAA resolved into the output image), each drawing the host's own ground and
// prop pipelines and >= 100 ngi instances of two assets, drawn adaptively (adaptive_draw.h:
// per instance and pass, each tile of each chart at the coarsest level within --max-error
// pixels, tiles outside the view or facing away culled), the tiles selected on the GPU
// (gpu_tile_selection.h: compute passes before the shadow pass, one indirect draw per chart
// and level and pass for all instances) or on the CPU (a few draws per instance): --select
// gpu or cpu; auto (the default) selects on the GPU unless the device is a CPU (lavapipe),
// where the CPU's own code is faster than the compute passes run on it),
// or with --uniform one LoD per instance in one DrawBatch::record (lod.h). ngi's surfaces are
// shaded by the host's own material (ngi_lit.frag, written against ngi's public vertex
// stage, which the adaptive vertex stage writes too; the host's shadow map in set 2). The
// camera moves over --frames N; the last frame is written to a PNG; per-frame CPU and GPU
// times (timestamp queries), `instances: N`, the LoD histogram and the levels expanded for
// shared vertices (DrawBatch::recordGridExpansion before the passes) are printed; an asset no
// instance draws finer than LoD 1 gives its level 0's memory back. --check
// verifies the last frame's pixels: shadows on the ground, a prop hiding an ngi instance and
// an ngi instance hiding a prop. Any validation message fails the run.
//
// usage: ngi-host-demo [-o OUT.png] [--asset A.ngi] [--frames N] [--size WxH] [--shadow-size N]
//                      [--max-error PX] [--uniform [--single] | --select auto|gpu|cpu] [--validation] [--check]
// --uniform draws one LoD per instance (the chart's worst spot sets its level) through
// DrawBatch; --single then draws each instance with its own draw calls (a batch of one per
// instance), to compare frame times with the batched draws (same pixels).
#include "host_device.h"
#include "scene.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/engine/gpu_tile_selection.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/context.h"
#include "ngi/engine/draw_batch.h"
#include "ngi/engine/lod.h"
#include "ngi/engine/pipelines.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/resources.h"
#include "ngi/png_io.h"

#include "host_shaders/ground_frag.h"
#include "host_shaders/ground_vert.h"
#include "host_shaders/ngi_lit_frag.h"
#include "host_shaders/prop_frag.h"
#include "host_shaders/prop_vert.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <tuple>

namespace {

using ngi::vk::UniqueImage;

struct Options {
    std::string output = "host_demo.png", asset = NGI_DEFAULT_ASSET;
    uint32_t frames = 30, width = 960, height = 540, shadowSize = 2048;
    float maxErrorPixels = 1.0f;
    bool validation = false, check = false;
    bool uniform = false;         // one LoD per instance (DrawBatch) instead of the adaptive draw
    bool single = false;          // with uniform: one batch of one per instance instead of one batch per pass
    std::string select = "auto";  // adaptive: where tiles are selected (gpu, cpu; auto: gpu unless a CPU device)
};

constexpr const char* kUsage =
    "usage: ngi-host-demo [-o OUT.png] [--asset A.ngi] [--frames N] [--size WxH] [--shadow-size N] [--max-error PX]\n"
    "                     [--uniform [--single] | --select auto|gpu|cpu] [--validation] [--check]\n"
    "  A host engine's frames (shadow map, 4x MSAA main pass, props) with 120 instances of two\n"
    "  assets drawn by ngi: adaptively (each tile within PX pixels, default 1; its tiles selected\n"
    "  on the GPU or the CPU: --select, auto by default, the GPU unless the device is a CPU),\n"
    "  or one LoD per instance with --uniform\n"
    "  (--single: one draw batch per instance). N frames (default 30),\n"
    "  W x H pixels (16-8192, default 960x540), a shadow map of N texels (64-8192, default\n"
    "  2048). Prints a table per frame and the GPU memory per asset; -o writes the last frame.\n";

Options parse(int argc, char** argv)
{
    Options o;
    bool selectGiven = false;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        if (args.is("-o"))
            o.output = ngi::parseOutputPathOption(args.flag(), args.value());
        else if (args.is("--asset"))
            o.asset = args.value();
        else if (args.is("--frames"))
            o.frames = uint32_t(ngi::parseIntegerOptionInRange(args.flag(), args.value(), 1, 1000000));
        else if (args.is("--shadow-size"))
            o.shadowSize = uint32_t(ngi::parseIntegerOptionInRange(args.flag(), args.value(), 64, 8192));
        else if (args.is("--max-error"))
            o.maxErrorPixels = ngi::parseFloatOptionInRange(args.flag(), args.value(), 0.05, 1e4, "pixels");
        else if (args.is("--size")) {
            const std::string flag = args.flag(), value = args.value();
            std::tie(o.width, o.height) = ngi::parseSizeOption(flag, value);
            if (o.width < 16 || o.height < 16 || o.width > 8192 || o.height > 8192)
                throw ngi::UsageError(flag + " expects WxH of 16 to 8192 pixels each, got '" + value + "'");
        } else if (args.is("--validation"))
            o.validation = true;
        else if (args.is("--check"))
            o.check = true;
        else if (args.is("--single"))
            o.single = true;
        else if (args.is("--uniform"))
            o.uniform = true;
        else if (args.is("--select")) {
            const std::string flag = args.flag();
            o.select = args.value();
            if (o.select != "auto" && o.select != "gpu" && o.select != "cpu")
                throw ngi::UsageError(flag + " expects auto, gpu or cpu, got '" + o.select + "'");
            selectGiven = true;
        } else if (args.is("--help", "-h")) {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else
            throw args.unknown();
    }
    if (o.single && !o.uniform) throw ngi::UsageError("--single needs --uniform (adaptive draws are per instance)");
    if (selectGiven && o.uniform) throw ngi::UsageError("--select is for the adaptive draw, not --uniform");
    return o;
}

// The host's light: set HOST_LIGHT_SET of lighting.glsl.
struct LightBlock {
    glm::mat4 lightViewProjection;
    glm::vec4 toLight, sun, ambient, shadowTexel;
};
struct GroundPush {
    glm::mat4 viewProjection;
    glm::vec4 colour;
    float halfSize;
};
struct PropPush {
    glm::mat4 viewProjection;
    glm::vec4 centre, halfExtent, colour;
};

void depthBarrier(VkCommandBuffer cmd, VkImage image, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                  VkImageLayout from, VkPipelineStageFlags dstStage, VkAccessFlags dstAccess, VkImageLayout to)
{
    ngi::vk::imageBarrier(cmd, image, VK_IMAGE_ASPECT_DEPTH_BIT, srcStage, srcAccess, dstStage, dstAccess, from, to);
}

constexpr VkPipelineStageFlags kDepthStages =
    VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
constexpr VkAccessFlags kDepthAccess =
    VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;

int run(const Options& o)
{
    host::HostDevice host(o.validation);
    // ngi checks what the host enabled (ngi::Error listing anything missing).
    auto context =
        ngi::vk::Context::adopt(host.instance, host.physical, host.device, host.queue, host.family, host.createInfo);
    const ngi::vk::Context& c = *context;
    ngi::vk::Renderer renderer(c);  // records nothing, waits for nothing

    // The host's formats: a sampled depth format for the shadow map, a depth format and 4x
    // MSAA (guaranteed for colour and depth attachments) for the main pass.
    const VkFormat shadowFormat =
        host.pickFormat({VK_FORMAT_D32_SFLOAT, VK_FORMAT_D16_UNORM},
                        VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT);
    const VkFormat depthFormat = host.pickFormat({VK_FORMAT_D32_SFLOAT, VK_FORMAT_X8_D24_UNORM_PACK32},
                                                 VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT);
    const VkSampleCountFlagBits samples = (host.properties.limits.framebufferColorSampleCounts &
                                           host.properties.limits.framebufferDepthSampleCounts & VK_SAMPLE_COUNT_4_BIT)
        ? VK_SAMPLE_COUNT_4_BIT
        : VK_SAMPLE_COUNT_1_BIT;
    ngi::vk::PassDescription shadowPass;
    shadowPass.colorFormats = {};
    shadowPass.depthFormat = shadowFormat;
    shadowPass.dynamicDepthBias = true;
    ngi::vk::PassDescription mainPass;
    mainPass.colorFormats = {VK_FORMAT_R8G8B8A8_UNORM};
    mainPass.depthFormat = depthFormat;
    mainPass.depthCompare = VK_COMPARE_OP_GREATER_OR_EQUAL;  // reverse-Z
    mainPass.samples = samples;

    // The host's light set (shadow map + light block), shared by its pipelines and its ngi material.
    const VkDescriptorSetLayoutBinding lightBindings[2] = {
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
        {1, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
    VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    setInfo.bindingCount = 2;
    setInfo.pBindings = lightBindings;
    ngi::vk::UniqueDescriptorSetLayout lightLayout(c.device);
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(c.device, &setInfo, nullptr, lightLayout.out()));
    const VkDescriptorSetLayout lightLayoutHandle = lightLayout.get();

    // ngi's pipelines for the host's two passes: depth-only (ngi's vertex stage alone) and
    // the main pass with the host's material and its light set as set 2.
    const ngi::vk::SurfacePipeline ngiShadow(renderer, shadowPass);
    const ngi::vk::SurfacePipeline ngiMain(renderer, mainPass, ngi_lit_frag_spv, {&lightLayoutHandle, 1});
    // The same two for the adaptive draw, with the same material: its vertex stage writes the
    // same outputs and its set 0 binds the chart's base colour where the uniform draw's does.
    const ngi::vk::AdaptivePipeline adaptiveShadow(renderer, shadowPass);
    const ngi::vk::AdaptivePipeline adaptiveMain(renderer, mainPass, ngi_lit_frag_spv, {&lightLayoutHandle, 1});

    // The host's own pipelines: ground and props, lit in the main pass, props cast shadows.
    auto hostLayout = [&](uint32_t pushBytes) {
        const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT, 0, pushBytes};
        VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        info.setLayoutCount = 1;
        info.pSetLayouts = &lightLayoutHandle;
        info.pushConstantRangeCount = 1;
        info.pPushConstantRanges = &range;
        ngi::vk::UniquePipelineLayout layout(c.device);
        NGI_VK_CHECK(vkCreatePipelineLayout(c.device, &info, nullptr, layout.out()));
        return layout;
    };
    // One layout for both (one push range): the light set bound once serves both pipelines.
    const ngi::vk::UniquePipelineLayout hostPipelineLayout = hostLayout(std::max(sizeof(GroundPush), sizeof(PropPush)));
    const VkPipelineLayout groundLayout = hostPipelineLayout.get(), propLayout = hostPipelineLayout.get();
    auto hostPipeline = [&](std::span<const uint32_t> vert, std::span<const uint32_t> frag, VkPipelineLayout layout,
                            const ngi::vk::PassDescription& pass) {
        ngi::vk::GraphicsPipelineDesc d;
        d.vertexSpirv = vert;
        d.fragmentSpirv = frag;
        d.layout = layout;
        d.pass = pass;
        return ngi::vk::UniquePipeline(c.device, ngi::vk::createGraphicsPipeline(c.device, d));
    };
    const auto groundPipeline = hostPipeline(ground_vert_spv, ground_frag_spv, groundLayout, mainPass);
    const auto propPipeline = hostPipeline(prop_vert_spv, prop_frag_spv, propLayout, mainPass);
    const auto propShadowPipeline = hostPipeline(prop_vert_spv, {}, propLayout, shadowPass);

    // Two assets: the baked default asset and an analytic rippled torus, painted with stripes
    // over its chart's square (a base colour: the adaptive draw's material shows it).
    std::vector<ngi::Asset> assets;
    assets.push_back(ngi::readAsset(o.asset));
    assets.push_back(ngi::makeAnalyticAsset("rippled torus", ngi::rippledTorusGeometryImage(257), 2));
    {
        ngi::AssetChart& torus = assets.back().charts[0];
        torus.baseColorLevel = 1;
        const uint32_t n = torus.baseColorSize();
        torus.baseColor.resize(size_t(n) * n * 4);
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const bool stripe = ((x * 12 / (n - 1)) + (y * 4 / (n - 1))) % 2 == 0;
                uint8_t* t = &torus.baseColor[(size_t(y) * n + x) * 4];
                t[0] = stripe ? 214 : 60, t[1] = stripe ? 96 : 120, t[2] = stripe ? 40 : 200, t[3] = 255;
            }
    }
    std::vector<std::unique_ptr<ngi::vk::AssetSurface>> surfaces;
    std::vector<ngi::AssetLodMetrics> metrics;
    for (const ngi::Asset& a : assets) {
        // The default restore: the network the asset carries or names when it is found, else bicubic.
        surfaces.push_back(std::make_unique<ngi::vk::AssetSurface>(renderer, a, ngi::vk::RestoreOptions{},
                                                                   o.uniform ? ngi::vk::SurfaceDraws::uniformAndAdaptive
                                                                             : ngi::vk::SurfaceDraws::adaptiveOnly));
        metrics.push_back(ngi::measureLodMetrics(a));
    }
    const host::Scene scene = host::makeScene(metrics, o.frames);

    // Images: the shadow map, the MSAA colour and depth, the resolved output, its read-back.
    UniqueImage shadowMap(c, o.shadowSize, o.shadowSize, shadowFormat,
                          VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT,
                          VK_IMAGE_ASPECT_DEPTH_BIT);
    UniqueImage msaaColour(c, o.width, o.height, VK_FORMAT_R8G8B8A8_UNORM,
                           VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSIENT_ATTACHMENT_BIT,
                           VK_IMAGE_ASPECT_COLOR_BIT, samples);
    UniqueImage depth(c, o.width, o.height, depthFormat, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                      VK_IMAGE_ASPECT_DEPTH_BIT, samples);
    UniqueImage resolved(c, o.width, o.height, VK_FORMAT_R8G8B8A8_UNORM,
                         VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                         VK_IMAGE_ASPECT_COLOR_BIT);
    ngi::vk::UniqueBuffer readback(c, VkDeviceSize(o.width) * o.height * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                   VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);

    // The light set's contents.
    ngi::vk::UniqueBuffer lightBuffer(c, sizeof(LightBlock), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    const LightBlock light{scene.lightViewProjection, glm::vec4(scene.toLight, 0.0f),
                           glm::vec4(0.95f, 0.90f, 0.80f, 0.0f), glm::vec4(0.22f, 0.25f, 0.32f, 0.0015f),
                           glm::vec4(1.0f / float(o.shadowSize))};
    std::memcpy(lightBuffer->mapped, &light, sizeof(light));
    VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    samplerInfo.magFilter = samplerInfo.minFilter = VK_FILTER_NEAREST;
    samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW =
        VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    ngi::vk::UniqueSampler sampler(c.device);
    NGI_VK_CHECK(vkCreateSampler(c.device, &samplerInfo, nullptr, sampler.out()));
    const VkDescriptorPoolSize poolSizes[2] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1},
                                               {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1}};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 2;
    poolInfo.pPoolSizes = poolSizes;
    ngi::vk::UniqueDescriptorPool descriptorPool(c.device);
    NGI_VK_CHECK(vkCreateDescriptorPool(c.device, &poolInfo, nullptr, descriptorPool.out()));
    VkDescriptorSetAllocateInfo allocInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocInfo.descriptorPool = descriptorPool.get();
    allocInfo.descriptorSetCount = 1;
    allocInfo.pSetLayouts = &lightLayoutHandle;
    VkDescriptorSet lightSet = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkAllocateDescriptorSets(c.device, &allocInfo, &lightSet));
    const VkDescriptorImageInfo shadowInfo{sampler.get(), shadowMap->view, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
    const VkDescriptorBufferInfo lightInfo{lightBuffer->buffer, 0, sizeof(LightBlock)};
    VkWriteDescriptorSet writes[2]{{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}, {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
    writes[0].dstSet = writes[1].dstSet = lightSet;
    writes[0].descriptorCount = writes[1].descriptorCount = 1;
    writes[0].descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    writes[0].pImageInfo = &shadowInfo;
    writes[1].dstBinding = 1;
    writes[1].descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    writes[1].pBufferInfo = &lightInfo;
    vkUpdateDescriptorSets(c.device, 2, writes, 0, nullptr);

    // The host's command buffer, fence and timestamps (start, after the shadow pass, end).
    VkCommandPoolCreateInfo cmdPoolInfo{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    cmdPoolInfo.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    cmdPoolInfo.queueFamilyIndex = host.family;
    ngi::vk::UniqueHandle<VkCommandPool, vkDestroyCommandPool> cmdPool(c.device);
    NGI_VK_CHECK(vkCreateCommandPool(c.device, &cmdPoolInfo, nullptr, cmdPool.out()));
    VkCommandBufferAllocateInfo cmdAlloc{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cmdAlloc.commandPool = cmdPool.get();
    cmdAlloc.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cmdAlloc.commandBufferCount = 1;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkAllocateCommandBuffers(c.device, &cmdAlloc, &cmd));
    ngi::vk::UniqueFence fence(c.device);
    VkFenceCreateInfo fenceInfo{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    NGI_VK_CHECK(vkCreateFence(c.device, &fenceInfo, nullptr, fence.out()));
    ngi::vk::UniqueQueryPool queries(c.device);
    VkQueryPoolCreateInfo queryInfo{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    queryInfo.queryType = VK_QUERY_TYPE_TIMESTAMP;
    queryInfo.queryCount = 3;
    NGI_VK_CHECK(vkCreateQueryPool(c.device, &queryInfo, nullptr, queries.out()));
    const bool timestamps = host.timestampValidBits > 0;
    auto submit = [&]() {
        VkSubmitInfo info{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        info.commandBufferCount = 1;
        info.pCommandBuffers = &cmd;
        const VkFence f = fence.get();
        NGI_VK_CHECK(vkResetFences(c.device, 1, &f));
        NGI_VK_CHECK(vkQueueSubmit(host.queue, 1, &info, f));
        NGI_VK_CHECK(vkWaitForFences(c.device, 1, &f, VK_TRUE, UINT64_MAX));
    };
    auto gpuMs = [&](double* shadowMs, double* mainMs) {
        uint64_t t[3] = {};
        NGI_VK_CHECK(vkGetQueryPoolResults(c.device, queries.get(), 0, 3, sizeof(t), t, sizeof(uint64_t),
                                           VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
        const double period = host.properties.limits.timestampPeriod * 1e-6;
        *shadowMs = double(t[1] - t[0]) * period;
        *mainMs = double(t[2] - t[1]) * period;
    };
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;

    // Load: ngi's builds recorded into the host's command buffer, one submission by the host;
    // ngi submits and waits for nothing itself (releaseUploads checks the network's restores).
    const auto loadStart = std::chrono::steady_clock::now();
    NGI_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
    for (auto& s : surfaces) s->recordBuild(cmd);
    NGI_VK_CHECK(vkEndCommandBuffer(cmd));
    submit();
    for (auto& s : surfaces) s->releaseUploads();
    const double loadMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - loadStart).count();

    std::printf("device: %s\n", host.properties.deviceName);
    for (size_t a = 0; a < assets.size(); ++a)
        std::printf("asset %zu: %s, %zu chart(s), LoD 0..%u, %.1f MiB GPU in %u allocations\n", a,
                    assets[a].sourceName.c_str(), surfaces[a]->chartCount(), surfaces[a]->levelCount() - 1,
                    surfaces[a]->gpuBytes() / 1048576.0, [&] {
                        uint32_t n = 0;
                        for (size_t k = 0; k < surfaces[a]->chartCount(); ++k)
                            n += surfaces[a]->chart(k).deviceAllocationCount();
                        return n;
                    }());
    std::printf("load: builds recorded into the host's command buffer, %.1f ms\n", loadMs);
    std::printf("instances: %zu (%zu of asset 0, %zu of asset 1), %zu host props, %ux%u, %ux MSAA, shadow map %u^2\n",
                scene.instances.size(), scene.countOf(0), scene.countOf(1), scene.props.size(), o.width, o.height,
                uint32_t(samples), o.shadowSize);

    size_t records = 0;
    for (const host::Instance& i : scene.instances) records += assets[i.asset].charts.size();
    // One batch per pass: the shadow map gets its own LoDs (error in shadow-map texels).
    ngi::vk::DrawBatch shadowBatch(renderer, uint32_t(records)), mainBatch(renderer, uint32_t(records));
    std::vector<float> shadowLods(scene.instances.size()), mainLods(scene.instances.size());
    std::vector<std::unique_ptr<ngi::vk::DrawBatch>> singles, singleShadows;  // --single: one batch per instance
    for (size_t k = 0; o.single && k < scene.instances.size(); ++k) {
        const uint32_t charts = uint32_t(assets[scene.instances[k].asset].charts.size());
        singles.push_back(std::make_unique<ngi::vk::DrawBatch>(renderer, charts));
        singleShadows.push_back(std::make_unique<ngi::vk::DrawBatch>(renderer, charts));
    }
    const glm::vec4 groundColour(0.30f, 0.52f, 0.24f, 1.0f);
    const VkClearColorValue sky{{0.46f, 0.62f, 0.85f, 1.0f}};

    // Adaptive: one AdaptiveSurface per asset (tile bounds measured once, on the CPU), one
    // selection per instance per pass every frame.
    std::vector<std::unique_ptr<ngi::vk::AdaptiveSurface>> adaptives;
    const auto adaptiveStart = std::chrono::steady_clock::now();
    // The adaptive draw keeps its own compact copy of the levels: the restored surface, no
    // longer read, is given back. Level 0 stays on the host until a tile draws it.
    for (size_t a = 0; !o.uniform && a < surfaces.size(); ++a) {
        adaptives.push_back(
            std::make_unique<ngi::vk::AdaptiveSurface>(renderer, *surfaces[a], assets[a], 1u << 12, 1, false));
        surfaces[a].reset();
    }
    if (!o.uniform) {
        std::printf(
            "adaptive: levels fitted and tile bounds measured for %zu assets in %.0f ms (read back + CPU, once)\n",
            adaptives.size(),
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - adaptiveStart).count());
        for (size_t a = 0; a < adaptives.size(); ++a)
            std::printf(
                "asset %zu: %.1f MiB GPU (compact levels %.1f + base colour %.1f + tile and instance records %.1f)\n",
                a, adaptives[a]->gpuBytes() / 1048576.0, adaptives[a]->levelBytes() / 1048576.0,
                adaptives[a]->colorBytes() / 1048576.0, adaptives[a]->recordBytes() / 1048576.0);
    }
    // The selection on the GPU: one GpuTileSelection per asset, every instance of it in both
    // passes (group 0 the main pass, 1 the shadow pass).
    bool gpuSelect = !o.uniform &&
        (o.select == "gpu" || (o.select == "auto" && c.properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU));
    if (gpuSelect && !context->drawIndirectFirstInstance) {
        if (o.select == "gpu") throw ngi::Error("--select gpu: the device lacks the drawIndirectFirstInstance feature");
        std::printf("adaptive selection on the CPU: the device lacks drawIndirectFirstInstance\n");
        gpuSelect = false;
    }
    std::vector<std::unique_ptr<ngi::vk::GpuTileSelection>> gpuSelections;
    std::vector<std::vector<size_t>> finestCharts(adaptives.size());  // the GPU's report of the last frame
    for (size_t a = 0; gpuSelect && a < adaptives.size(); ++a) {
        uint32_t jobs = 0;
        for (const host::Instance& i : scene.instances) jobs += i.asset == a ? 2 : 0;
        // Records for 32,768 drawn tiles a frame (1.5 MiB; a frame that draws more grows them).
        gpuSelections.push_back(
            std::make_unique<ngi::vk::GpuTileSelection>(renderer, *adaptives[a], std::max(jobs, 1u), 2, 1u << 15));
        std::printf(
            "asset %zu: %.1f MiB GPU for the selection on the GPU (tile bounds %.1f + per-frame buffers %.1f)\n", a,
            (gpuSelections[a]->staticBytes() + gpuSelections[a]->frameBytes()) / 1048576.0,
            gpuSelections[a]->staticBytes() / 1048576.0, gpuSelections[a]->frameBytes() / 1048576.0);
    }
    std::vector<ngi::TileSelection> shadowTiles(scene.instances.size()), mainTiles(scene.instances.size());
    double selectMs = 0.0;  // all frames
    std::printf(
        "ngi draws: %s\n",
        gpuSelect
            ? "adaptive, tiles selected on the GPU (GpuTileSelection), one indirect draw per chart, level and pass"
            : !o.uniform ? "adaptive, per instance and pass, tiles selected on the CPU (AdaptiveSurface)"
            : o.single   ? "one LoD per instance, one batch of one per instance (--single)"
                         : "one LoD per instance, one DrawBatch per pass");
    std::printf("\n%5s %9s %9s %10s %9s %10s %11s %11s %6s %7s\n", "frame", "cpu ms", "gpu ms", "shadow ms", "main ms",
                "wait ms", "shadow tris", "main tris", "draws", "culled");
    std::map<int, size_t> lastHistogram, allHistogram;
    double sumCpu = 0, sumGpu = 0;
    uint64_t expansions = 0;  // levels expanded for shared vertices, all frames (cached ones not counted)
    std::vector<std::string> released;
    uint32_t finestUploads = 0;                                     // adaptive: level-0 uploads after the load
    std::vector<VkDeviceSize> peakAdaptiveBytes(adaptives.size());  // adaptive: the most GPU memory in a frame
    glm::mat4 viewProjection(1.0f);
    for (uint32_t frame = 0; frame < o.frames; ++frame) {
        const auto cpuStart = std::chrono::steady_clock::now();
        const host::Camera camera = scene.camera(frame, float(o.width) / float(o.height));
        viewProjection = camera.viewProjection;
        // LoD per instance per pass from its projected geometric error (pixels; shadow-map texels).
        shadowBatch.clear();
        mainBatch.clear();
        lastHistogram.clear();
        for (size_t k = 0; k < scene.instances.size(); ++k) {
            const host::Instance& i = scene.instances[k];
            const ngi::AssetLodMetrics& m = metrics[i.asset];
            mainLods[k] =
                ngi::instanceLod(m, m.geometricError, viewProjection, i.world, float(o.height), o.maxErrorPixels);
            shadowLods[k] = ngi::instanceLod(m, m.geometricError, scene.lightViewProjection, i.world,
                                             float(o.shadowSize), o.maxErrorPixels);
            if (o.uniform) {
                mainBatch.add(*surfaces[i.asset], i.world, mainLods[k]);
                shadowBatch.add(*surfaces[i.asset], i.world, shadowLods[k]);
            }
            ++lastHistogram[int(mainLods[k])];
            ++allHistogram[int(mainLods[k])];
        }
        // Adaptive: every instance's tiles for each pass (the shadow map's budget in texels).
        const auto selectStart = std::chrono::steady_clock::now();
        for (auto& a : adaptives) a->clear();
        std::vector<std::vector<ngi::vk::GpuSelectionJob>> gpuJobs(gpuSelections.size());
        for (size_t k = 0; gpuSelect && k < scene.instances.size(); ++k) {
            const host::Instance& i = scene.instances[k];
            const ngi::vk::AdaptiveSurface& a = *adaptives[i.asset];
            gpuJobs[i.asset].push_back(
                {a.view(viewProjection, i.world, camera.eye, float(o.height), o.maxErrorPixels), i.world, 0});
            gpuJobs[i.asset].push_back(
                {a.view(scene.lightViewProjection, i.world, scene.lightEye, float(o.shadowSize), o.maxErrorPixels),
                 i.world, 1});
        }
        if (!o.uniform && !gpuSelect) {
            // Both passes of every instance selected at once, over the machine's cores.
            std::vector<ngi::SelectionRequest> requests;
            for (const host::Instance& i : scene.instances) {
                const ngi::vk::AdaptiveSurface& a = *adaptives[i.asset];
                requests.push_back({&a.charts(), &a.mates(),
                                    a.view(viewProjection, i.world, camera.eye, float(o.height), o.maxErrorPixels)});
                // The sun's camera is orthographic: no facing test from an eye point, frustum only.
                requests.push_back({&a.charts(), &a.mates(),
                                    a.view(scene.lightViewProjection, i.world, scene.lightEye, float(o.shadowSize),
                                           o.maxErrorPixels)});
            }
            std::vector<ngi::TileSelection> selections = ngi::selectTilesInParallel(requests);
            for (size_t k = 0; k < scene.instances.size(); ++k) {
                mainTiles[k] = std::move(selections[2 * k]);
                shadowTiles[k] = std::move(selections[2 * k + 1]);
            }
        }
        selectMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - selectStart).count();
        auto drawAdaptive = [&](const std::vector<ngi::TileSelection>& tiles, const ngi::vk::AdaptivePipeline& pipeline,
                                const glm::mat4& passViewProjection, glm::vec3 eye) {
            ngi::vk::BatchStats stats;
            if (gpuSelect) {  // triangles and culled tiles are read back after the frame
                ngi::vk::DrawParams p;
                p.viewProjection = passViewProjection;
                p.eye = eye;
                for (size_t a = 0; a < gpuSelections.size(); ++a)
                    if (!gpuJobs[a].empty())  // an asset with no instance selected nothing this frame
                        stats.drawCalls +=
                            gpuSelections[a]->recordDraw(cmd, &tiles == &mainTiles ? 0 : 1, p, std::nullopt, &pipeline);
                return stats;
            }
            for (size_t k = 0; k < scene.instances.size(); ++k) {
                const host::Instance& i = scene.instances[k];
                ngi::vk::DrawParams p;
                p.viewProjection = passViewProjection;
                p.world = i.world;
                p.eye = eye;
                const ngi::vk::AdaptiveDrawStats one =
                    adaptives[i.asset]->recordDraw(cmd, tiles[k], p, std::nullopt, &pipeline);
                stats.triangles += one.triangles;
                stats.drawCalls += one.drawCalls;
                stats.culled += one.culled;
            }
            return stats;
        };
        // --single: one draw call sequence per instance (a batch of one each: every instance
        // rebinds pipeline, sets and push constants), what a host without batching records.
        // (Renderer::recordDraw would do the same but has no world matrix on the GPU for the
        // host's material, which needs world-space positions.)
        for (size_t k = 0; o.single && k < scene.instances.size(); ++k) {
            singles[k]->clear();
            singles[k]->add(*surfaces[scene.instances[k].asset], scene.instances[k].world, mainLods[k]);
            singleShadows[k]->clear();
            singleShadows[k]->add(*surfaces[scene.instances[k].asset], scene.instances[k].world, shadowLods[k]);
        }
        auto drawEach = [&](std::vector<std::unique_ptr<ngi::vk::DrawBatch>>& batches, const ngi::vk::BatchParams& p) {
            ngi::vk::BatchStats stats;
            for (auto& b : batches) {
                const ngi::vk::BatchStats one = b->record(cmd, p);
                stats.triangles += one.triangles;
                stats.drawCalls += one.drawCalls;
                stats.culled += one.culled;
            }
            return stats;
        };

        NGI_VK_CHECK(vkBeginCommandBuffer(cmd, &begin));
        vkCmdResetQueryPool(cmd, queries.get(), 0, 3);
        if (timestamps) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries.get(), 0);
        // The grid expansions, outside the passes (compute, timed with the shadow pass): ngi's
        // draws then share vertices. The main batch's last: where both passes draw a level at
        // different geomorph factors the main pass (the larger one) keeps its expansion and the
        // shadow pass draws that level per quad. --single's batches of one draw from the same
        // expansions (they are the surfaces' own), so both ways expand the same levels.
        if (o.uniform) {
            expansions += shadowBatch.recordGridExpansion(cmd);
            expansions += mainBatch.recordGridExpansion(cmd);
        }
        // Adaptive residency, outside the passes: each chart's level 0 is uploaded when a tile of
        // this frame draws it and given back after 2 frames without one (each frame is waited for).
        // On the GPU: from the charts the previous frame drew (or wanted) at level 0; the
        // selection, recorded next, draws level 1 where a level 0 is not resident yet.
        for (size_t a = 0; a < adaptives.size(); ++a) {
            if (gpuSelect) {
                finestUploads += adaptives[a]->recordResidency(cmd, std::span<const size_t>(finestCharts[a]), frame, 2);
                if (!gpuJobs[a].empty()) gpuSelections[a]->recordSelect(cmd, gpuJobs[a]);
            } else {
                std::vector<const ngi::TileSelection*> drawn;
                for (size_t k = 0; k < scene.instances.size(); ++k)
                    if (scene.instances[k].asset == a) drawn.insert(drawn.end(), {&mainTiles[k], &shadowTiles[k]});
                finestUploads += adaptives[a]->recordResidency(cmd, drawn, frame, 2);
            }
            peakAdaptiveBytes[a] = std::max(peakAdaptiveBytes[a], adaptives[a]->gpuBytes());
        }

        // Shadow pass: depth only, from the sun; the props and ngi's instances cast.
        depthBarrier(cmd, shadowMap->image, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, VK_IMAGE_LAYOUT_UNDEFINED,
                     kDepthStages, kDepthAccess, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
        VkRenderingAttachmentInfo shadowDepth{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        shadowDepth.imageView = shadowMap->view;
        shadowDepth.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        shadowDepth.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        shadowDepth.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        shadowDepth.clearValue.depthStencil = {1.0f, 0};
        VkRenderingInfo shadowRendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        shadowRendering.renderArea = {{0, 0}, {o.shadowSize, o.shadowSize}};
        shadowRendering.layerCount = 1;
        shadowRendering.pDepthAttachment = &shadowDepth;
        vkCmdBeginRendering(cmd, &shadowRendering);
        const VkViewport shadowViewport{0, 0, float(o.shadowSize), float(o.shadowSize), 0, 1};
        const VkRect2D shadowScissor{{0, 0}, {o.shadowSize, o.shadowSize}};
        vkCmdSetViewport(cmd, 0, 1, &shadowViewport);
        vkCmdSetScissor(cmd, 0, 1, &shadowScissor);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, propShadowPipeline.get());
        // Both shadow pipelines take the depth bias as dynamic state: set once, it stays.
        vkCmdSetDepthBias(cmd, 1.25f, 0.0f, 1.75f);
        for (const host::Prop& p : scene.props) {
            const PropPush push{scene.lightViewProjection, glm::vec4(p.centre, 1), glm::vec4(p.halfExtent, 0),
                                p.colour};
            vkCmdPushConstants(cmd, propLayout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
            vkCmdDraw(cmd, 36, 1, 0, 0);
        }
        ngi::vk::BatchParams shadowParams;
        shadowParams.pipeline = &ngiShadow;
        shadowParams.viewProjection = scene.lightViewProjection;
        shadowParams.eye = scene.lightEye;
        ngi::vk::BatchStats shadowStats =  // the host's viewport stays
            !o.uniform ? drawAdaptive(shadowTiles, adaptiveShadow, scene.lightViewProjection, scene.lightEye)
            : o.single ? drawEach(singleShadows, shadowParams)
                       : shadowBatch.record(cmd, shadowParams);
        vkCmdEndRendering(cmd);
        depthBarrier(cmd, shadowMap->image, VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT,
                     VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                     VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT,
                     VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        if (timestamps) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries.get(), 1);

        // Main pass: reverse-Z, MSAA colour resolved into `resolved`.
        ngi::vk::imageBarrier(cmd, msaaColour->image, VK_IMAGE_ASPECT_COLOR_BIT,
                              VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, 0,
                              VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                              VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        ngi::vk::imageBarrier(cmd, resolved->image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                              VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                              VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        depthBarrier(cmd, depth->image, kDepthStages, 0, VK_IMAGE_LAYOUT_UNDEFINED, kDepthStages, kDepthAccess,
                     VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL);
        VkRenderingAttachmentInfo colourInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        colourInfo.imageView = msaaColour->view;
        colourInfo.imageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        colourInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        colourInfo.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        colourInfo.clearValue.color = sky;
        if (samples != VK_SAMPLE_COUNT_1_BIT) {
            colourInfo.resolveMode = VK_RESOLVE_MODE_AVERAGE_BIT;
            colourInfo.resolveImageView = resolved->view;
            colourInfo.resolveImageLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        } else {
            colourInfo.imageView = resolved->view;
            colourInfo.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
        }
        VkRenderingAttachmentInfo depthInfo{VK_STRUCTURE_TYPE_RENDERING_ATTACHMENT_INFO};
        depthInfo.imageView = depth->view;
        depthInfo.imageLayout = VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL;
        depthInfo.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
        depthInfo.storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
        depthInfo.clearValue.depthStencil = {0.0f, 0};  // reverse-Z: 0 is the far plane
        VkRenderingInfo rendering{VK_STRUCTURE_TYPE_RENDERING_INFO};
        rendering.renderArea = {{0, 0}, {o.width, o.height}};
        rendering.layerCount = 1;
        rendering.colorAttachmentCount = 1;
        rendering.pColorAttachments = &colourInfo;
        rendering.pDepthAttachment = &depthInfo;
        vkCmdBeginRendering(cmd, &rendering);
        const VkViewport viewport{0, 0, float(o.width), float(o.height), 0, 1};
        const VkRect2D scissor{{0, 0}, {o.width, o.height}};
        vkCmdSetViewport(cmd, 0, 1, &viewport);
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, groundLayout, 0, 1, &lightSet, 0, nullptr);
        const GroundPush ground{viewProjection, groundColour, scene.groundHalfSize};
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, groundPipeline.get());
        vkCmdPushConstants(cmd, groundLayout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(ground), &ground);
        vkCmdDraw(cmd, 6, 1, 0, 0);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, propPipeline.get());
        for (const host::Prop& p : scene.props) {
            const PropPush push{viewProjection, glm::vec4(p.centre, 1), glm::vec4(p.halfExtent, 0), p.colour};
            vkCmdPushConstants(cmd, propLayout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
            vkCmdDraw(cmd, 36, 1, 0, 0);
        }
        // The host's light set as set 2 of ngi's material pipeline (its own layout).
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                                o.uniform ? ngiMain.layout() : adaptiveMain.layout(),
                                ngi::vk::SurfacePipeline::firstHostSet, 1, &lightSet, 0, nullptr);
        ngi::vk::BatchParams mainParams;
        mainParams.pipeline = &ngiMain;
        mainParams.viewProjection = viewProjection;
        mainParams.eye = camera.eye;
        ngi::vk::BatchStats mainStats = !o.uniform ? drawAdaptive(mainTiles, adaptiveMain, viewProjection, camera.eye)
            : o.single                             ? drawEach(singles, mainParams)
                                                   : mainBatch.record(cmd, mainParams);
        vkCmdEndRendering(cmd);
        if (timestamps) vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries.get(), 2);

        const bool last = frame + 1 == o.frames;
        if (last) {
            ngi::vk::imageBarrier(cmd, resolved->image, VK_IMAGE_ASPECT_COLOR_BIT,
                                  VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                                  VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                                  VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
            VkBufferImageCopy copy{};
            copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            copy.imageExtent = {o.width, o.height, 1};
            vkCmdCopyImageToBuffer(cmd, resolved->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback->buffer, 1,
                                   &copy);
            ngi::vk::memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                                   VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
        }
        NGI_VK_CHECK(vkEndCommandBuffer(cmd));
        const double cpuMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - cpuStart).count();
        const auto waitStart = std::chrono::steady_clock::now();
        submit();
        const double waitMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - waitStart).count();
        double shadowMs = 0, mainMs = 0;
        if (timestamps) gpuMs(&shadowMs, &mainMs);
        for (size_t a = 0; a < gpuSelections.size(); ++a) {  // the frame has finished: what the GPU selected
            if (gpuJobs[a].empty()) continue;
            const ngi::vk::GpuTileSelection::Frame selected = gpuSelections[a]->readFrame();
            for (size_t j = 0; j < selected.jobs.size(); ++j) {
                ngi::vk::BatchStats& stats = gpuJobs[a][j].group == 0 ? mainStats : shadowStats;
                stats.triangles += selected.jobs[j].triangles;
                stats.culled += selected.jobs[j].culledFrustum + selected.jobs[j].culledBackface;
            }
            if (selected.overflow > 0)
                std::printf("asset %zu: %u tiles past the records' capacity (grown for the next frame)\n", a,
                            selected.overflow);
            finestCharts[a] = selected.finestCharts;
        }
        sumCpu += cpuMs;
        sumGpu += shadowMs + mainMs;
        std::printf("%5u %9.3f %9.2f %10.2f %9.2f %10.2f %11llu %11llu %6u %7u\n", frame, cpuMs, shadowMs + mainMs,
                    shadowMs, mainMs, waitMs, (unsigned long long)shadowStats.triangles,
                    (unsigned long long)mainStats.triangles, shadowStats.drawCalls + mainStats.drawCalls,
                    shadowStats.culled + mainStats.culled);
        // Streaming-style memory policy: an asset no instance drew finer than LoD 1 this frame
        // (in either pass) gives its level 0 back (the GPU is idle here: the frame was waited
        // for). A host that comes closer again builds the asset anew.
        // (The adaptive draw reads every level: nothing is released.)
        for (size_t a = 0; o.uniform && a < surfaces.size(); ++a) {
            bool fine = surfaces[a]->chart(0).finestLevel() == 0;
            for (size_t k = 0; fine && k < scene.instances.size(); ++k)
                fine = scene.instances[k].asset != a || (mainLods[k] >= 1.0f && shadowLods[k] >= 1.0f);
            if (!fine) continue;
            const double before = surfaces[a]->gpuBytes() / 1048576.0;
            surfaces[a]->releaseFinestLevels();
            released.push_back("asset " + std::to_string(a) + " after frame " + std::to_string(frame) + ": " +
                               std::to_string(before).substr(0, 4) + " -> " +
                               std::to_string(surfaces[a]->gpuBytes() / 1048576.0).substr(0, 4) + " MiB");
        }
    }
    for (const std::string& r : released) std::printf("level 0 released (every instance at LoD >= 1): %s\n", r.c_str());
    for (size_t a = 0; a < adaptives.size(); ++a)
        std::printf(
            "asset %zu: %.1f MiB GPU at most in a frame, %.1f at the end (level 0 of %u of %zu chart(s) resident)\n", a,
            peakAdaptiveBytes[a] / 1048576.0, adaptives[a]->gpuBytes() / 1048576.0, adaptives[a]->residentFinestCount(),
            assets[a].charts.size());
    if (!adaptives.empty()) std::printf("level-0 uploads after the load: %u\n", finestUploads);
    std::printf("%5s %9.3f %9.2f   (per frame; cpu = LoD + batch + recording, gpu = timestamps%s)\n", "mean",
                sumCpu / o.frames, sumGpu / o.frames, timestamps ? "" : ": not supported by this queue");
    std::printf("instances: %zu\n", scene.instances.size());
    if (!o.uniform)
        std::printf("adaptive selection (%s, both passes, all instances): %.2f ms per frame\n",
                    gpuSelect ? "CPU part: the jobs' views" : "CPU", selectMs / o.frames);
    std::printf("grid expansions (shared vertices): %llu levels in %u frames\n", (unsigned long long)expansions,
                o.frames);
    auto histogram = [](const char* what, const std::map<int, size_t>& h) {
        std::printf("LoD histogram (%s, instances per integer LoD):", what);
        for (const auto& [level, n] : h) std::printf("  %d: %zu", level, n);
        std::printf("\n");
    };
    if (o.uniform) {
        histogram("last frame, main pass", lastHistogram);
        histogram("all frames, main pass", allHistogram);
    }

    std::vector<uint8_t> pixels(size_t(o.width) * o.height * 4);
    std::memcpy(pixels.data(), readback->mapped, pixels.size());
    ngi::writePng8(o.output, o.width, o.height, 4, pixels.data());
    std::printf("wrote %s\n", o.output.c_str());

    int failures = 0;
    if (o.check) failures = host::checkFrame(scene, viewProjection, pixels, o.width, o.height);
    std::printf("validation messages: %d\n", host::gValidationMessages);
    // ngi's objects (declared after `host`) go before the host destroys its device.
    return failures || host::gValidationMessages ? 2 : 0;
}

}  // namespace

int main(int argc, char** argv)
{
    try {
        return run(parse(argc, argv));
    } catch (const ngi::UsageError& e) {
        std::fprintf(stderr, "ngi-host-demo: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-host-demo: %s\n", e.what());
        return 1;
    }
}
