// The any-LoD grid draw (the mip chain's pipelines are mip_chain.cpp's).
#include "ngi/engine/renderer.h"

#include "ngi/engine/asset_surface.h"
#include "ngi/engine/mip_chain.h"
#include "ngi/engine/pipelines.h"
#include "ngi/engine/surface.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/network_weights.h"
#include "ngi_shared.h"

#include "ngi_shaders/grid_expansion_comp.h"
#include "ngi_shaders/surface_frag.h"
#include "ngi_shaders/surface_vert.h"

#include <glm/matrix.hpp>

#include <algorithm>
#include <cstring>
#include <span>

namespace ngi::vk {

// C++ enums whose values the shaders read as NGI_* constants (push constants hold
// uint32_t(enum)): one definition each, so a value changed on one side fails the build.
static_assert(uint32_t(ShadingMode::Shaded) == NGI_MODE_SHADED);
static_assert(uint32_t(ShadingMode::Normals) == NGI_MODE_NORMALS);
static_assert(uint32_t(ShadingMode::Wireframe) == NGI_MODE_WIREFRAME);
static_assert(uint32_t(ShadingMode::Lod) == NGI_MODE_LOD);
static_assert(SurfacePipeline::firstHostSet == NGI_DRAW_HOST_SET);
// The network's activations (ngi/network_weights.h), which SuperResolution writes into
// SrPushConstants::activation.
static_assert(uint32_t(Activation::None) == NGI_SR_ACT_NONE);
static_assert(uint32_t(Activation::ReLU) == NGI_SR_ACT_RELU);
static_assert(uint32_t(Activation::LeakyReLU) == NGI_SR_ACT_LEAKY);

ShadingMode parseShadingMode(const std::string& name)
{
    if (name == "shaded") return ShadingMode::Shaded;
    if (name == "normals") return ShadingMode::Normals;
    if (name == "wireframe") return ShadingMode::Wireframe;
    if (name == "lod") return ShadingMode::Lod;
    if (name == "colour" || name == "color") return ShadingMode::BaseColour;
    throw Error("unknown shading mode '" + name + "' (valid: shaded, normals, wireframe, lod, colour)");
}

PassDescription RendererOptions::pass() const
{
    PassDescription p;
    p.colorFormats = {colorFormat};
    p.depthFormat = depthFormat;
    p.samples = samples;
    return p;
}

namespace {

// A pipeline layout of `sets` and DrawPushConstants for the vertex and fragment stages.
VkPipelineLayout createDrawLayout(VkDevice device, std::span<const VkDescriptorSetLayout> sets)
{
    const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                    sizeof(gpu::DrawPushConstants)};
    VkPipelineLayoutCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    info.setLayoutCount = uint32_t(sets.size());
    info.pSetLayouts = sets.data();
    info.pushConstantRangeCount = 1;
    info.pPushConstantRanges = &range;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkCreatePipelineLayout(device, &info, nullptr, &layout));
    return layout;
}

}  // namespace

SurfacePipeline::SurfacePipeline(const Renderer& renderer, const PassDescription& pass,
                                 std::span<const uint32_t> fragmentSpirv,
                                 std::span<const VkDescriptorSetLayout> hostSetLayouts)
    : pass_(pass), ownLayout_(renderer.context().device), layout_(renderer.drawLayout()), pipelines_{}
{
    static_assert(NGI_WAY_COUNT == wayCount && NGI_WAY_PER_QUAD == 0 && NGI_SPEC_VERTEX_WAY == 0 &&
                  NGI_SPEC_INSTANCED == 1 && NGI_SPEC_CUT_OUT == 0);
    if (!hostSetLayouts.empty()) {
        std::vector<VkDescriptorSetLayout> sets{renderer.drawSetLayout(), renderer.instanceSetLayout()};
        sets.insert(sets.end(), hostSetLayouts.begin(), hostSetLayouts.end());
        *ownLayout_.out() = createDrawLayout(renderer.context().device, sets);
        layout_ = ownLayout_.get();
    }
    GraphicsPipelineDesc desc;
    desc.vertexSpirv = surface_vert_spv;
    desc.fragmentSpirv = !fragmentSpirv.empty() ? fragmentSpirv
        : pass.colorFormats.empty()             ? std::span<const uint32_t>{}
                                                : std::span<const uint32_t>(surface_frag_spv);
    ownShading_ = fragmentSpirv.empty() && !pass.colorFormats.empty();
    hostReadsBarycentrics_ = !fragmentSpirv.empty() && shaderReadsInput(fragmentSpirv, 2);
    desc.layout = layout_;
    desc.pass = pass;
    desc.writeFirstAttachmentOnly = fragmentSpirv.empty();
    if (desc.writeFirstAttachmentOnly && pass.colorFormats.size() > 1 && !renderer.context().independentBlend)
        throw Error("surface pipeline: ngi's fragment shader writes colour attachment 0 only; a pass of " +
                    std::to_string(pass.colorFormats.size()) +
                    " colour attachments needs the independentBlend device feature (or your own fragment shader)");
    try {
        for (uint32_t cutOut = 0; cutOut < (ownShading_ ? 2u : 1u); ++cutOut)
            for (uint32_t instanced = 0; instanced < 2; ++instanced)
                for (uint32_t way = 0; way < wayCount; ++way) {
                    desc.vertexConstants = {way, instanced};             // NGI_SPEC_VERTEX_WAY, NGI_SPEC_INSTANCED
                    if (ownShading_) desc.fragmentConstants = {cutOut};  // NGI_SPEC_CUT_OUT
                    pipelines_[cutOut][instanced][way] = UniquePipeline(
                        renderer.context().device, createGraphicsPipeline(renderer.context().device, desc));
                }
    } catch (const Error& e) {
        throw Error(std::string("surface pipeline for a pass of ") + std::to_string(pass.colorFormats.size()) +
                    " colour attachment(s)" + (pass.renderPass ? " (render pass)" : " (dynamic rendering)") + ": " +
                    e.what());
    }
}

Renderer::Renderer(const Context& context, const RendererOptions& options)
    : context_(context), options_(options), mipChain_(context), instanceSetLayout_(context.device),
      instancePool_(context.device), expansionSetLayout_(context.device), expansionLayout_(context.device),
      expansion_(context.device)
{
    const VkDevice device = context.device;
    try {
        // Set 0: a level, its geomorph targets, its quad diagonals (vertex stage), the chart's
        // base colour (fragment stage), all samplers.
        constexpr VkShaderStageFlags vertex = VK_SHADER_STAGE_VERTEX_BIT;
        const VkDescriptorSetLayoutBinding level[4] = {
            {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, vertex, nullptr},
            {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, vertex, nullptr},
            {2, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, vertex, nullptr},
            {NGI_DRAW_BINDING_BASE_COLOUR, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_FRAGMENT_BIT,
             nullptr}};
        VkDescriptorSetLayoutCreateInfo setInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        setInfo.bindingCount = 4;
        setInfo.pBindings = level;
        NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, &drawSetLayout_));
        const VkDescriptorSetLayoutBinding instances{0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, vertex, nullptr};
        setInfo.bindingCount = 1;
        setInfo.pBindings = &instances;
        NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, instanceSetLayout_.out()));
        const VkDescriptorSetLayout sets[2] = {drawSetLayout_, instanceSetLayout_.get()};
        drawLayout_ = createDrawLayout(device, sets);

        // Set 1 of single draws (never read: DrawPushConstants::instanced = 0).
        unusedInstances_ = createBuffer(context, sizeof(gpu::DrawInstance), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        std::memset(unusedInstances_.mapped, 0, sizeof(gpu::DrawInstance));
        const VkDescriptorPoolSize poolSize{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1};
        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.maxSets = 1;
        poolInfo.poolSizeCount = 1;
        poolInfo.pPoolSizes = &poolSize;
        NGI_VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, instancePool_.out()));
        unusedInstanceSet_ = allocateInstanceSet(instancePool_.get(), unusedInstances_.buffer);

        VkSamplerCreateInfo samplerInfo{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
        samplerInfo.magFilter = samplerInfo.minFilter = VK_FILTER_NEAREST;
        samplerInfo.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
        samplerInfo.addressModeU = samplerInfo.addressModeV = samplerInfo.addressModeW =
            VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
        NGI_VK_CHECK(vkCreateSampler(device, &samplerInfo, nullptr, &sampler_));

        // The grid expansion: a level's quad diagonals in, its index buffer out.
        constexpr VkShaderStageFlags compute = VK_SHADER_STAGE_COMPUTE_BIT;
        const VkDescriptorSetLayoutBinding expansion[2] = {
            {NGI_EXPANSION_BINDING_DIAGONALS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, compute, nullptr},
            {NGI_EXPANSION_BINDING_INDICES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, compute, nullptr}};
        setInfo.bindingCount = 2;
        setInfo.pBindings = expansion;
        NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &setInfo, nullptr, expansionSetLayout_.out()));
        *expansionLayout_.out() = createPipelineLayout(device, expansionSetLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT,
                                                       sizeof(gpu::GridExpansionPushConstants));
        *expansion_.out() = createComputePipeline(device, expansionLayout_.get(), grid_expansion_comp_spv);

        draw_.emplace(*this, options.pass());
        if (options.quadIndexBuffer) createQuadIndices();
    } catch (...) {
        destroy();
        throw;
    }
}

VkDescriptorSet Renderer::allocateInstanceSet(VkDescriptorPool pool, VkBuffer buffer) const
{
    const VkDevice device = context_.device;
    const VkDescriptorSetLayout layout = instanceSetLayout_.get();
    VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    info.descriptorPool = pool;
    info.descriptorSetCount = 1;
    info.pSetLayouts = &layout;
    VkDescriptorSet set = VK_NULL_HANDLE;
    NGI_VK_CHECK(vkAllocateDescriptorSets(device, &info, &set));
    const VkDescriptorBufferInfo bufferInfo{buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.dstBinding = 0;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w.pBufferInfo = &bufferInfo;
    vkUpdateDescriptorSets(device, 1, &w, 0, nullptr);
    return set;
}

Renderer::~Renderer() { destroy(); }

void Renderer::createQuadIndices()
{
    // Written by the CPU in host-visible memory (device-local too where the device has such
    // a type): no transfer, so no submission on the host's queue and no wait.
    const VkDeviceSize bytes = VkDeviceSize(NGI_QUADS_PER_CHUNK) * 6 * sizeof(uint16_t);
    quadIndices_ = createHostWrittenBuffer(context_, bytes, VK_BUFFER_USAGE_INDEX_BUFFER_BIT);
    auto* indices = static_cast<uint16_t*>(quadIndices_.mapped);
    for (uint32_t q = 0; q < NGI_QUADS_PER_CHUNK; ++q) {
        const uint16_t base = uint16_t(4 * q);
        const uint16_t quad[6] = {base, uint16_t(base + 1), uint16_t(base + 2),
                                  base, uint16_t(base + 2), uint16_t(base + 3)};
        std::copy(quad, quad + 6, indices + 6 * q);
    }
    // Host writes to coherent memory are visible to every later submission (vkQueueSubmit's
    // implicit host-write ordering): no barrier is needed.
}

void Renderer::destroy()
{
    const VkDevice device = context_.device;
    destroyBuffer(context_, quadIndices_);
    destroyBuffer(context_, unusedInstances_);
    draw_.reset();
    if (sampler_) vkDestroySampler(device, sampler_, nullptr);
    if (drawLayout_) vkDestroyPipelineLayout(device, drawLayout_, nullptr);
    if (drawSetLayout_) vkDestroyDescriptorSetLayout(device, drawSetLayout_, nullptr);
    sampler_ = VK_NULL_HANDLE;
    drawLayout_ = VK_NULL_HANDLE;
    drawSetLayout_ = VK_NULL_HANDLE;
}

namespace {

// The level, geomorph factor, grid size and triangles of a draw of `surface` with `params`,
// and the LoD it shows (LoD colouring).
DrawStats selectGrid(const GeometryImageSurface& surface, const DrawParams& params, float& lod)
{
    if (!surface.uniformDrawable())
        throw Error("a surface built for the adaptive draw only (SurfaceDraws::adaptiveOnly) has no uniform draw");
    DrawStats stats;
    // Never finer than the surface keeps (GeometryImageSurface::releaseFinestLevel).
    lod = std::max(params.lod, float(surface.finestLevel()));
    if (params.gridSize > 0) {
        stats.level = levelForGridSize(surface.fullSize(), params.gridSize);
        stats.gridSize = params.gridSize;
        if (stats.level < surface.finestLevel())
            throw Error("draw: a " + std::to_string(params.gridSize) + "-vertex grid needs level " +
                        std::to_string(stats.level) + ", which the surface released");
    } else {
        // Never coarser than the coarsest level whose seams stay closed (surface.h).
        const LodSelection s = selectLod(surface.drawnLevelCount(), surface.fullSize(), lod);
        stats.level = s.level;
        stats.morph = s.morph;
        stats.gridSize = s.gridSize;
    }
    stats.triangles = gridTriangleCount(stats.gridSize);
    return stats;
}

}  // namespace

uint32_t Renderer::perQuadTopology() const
{
    return quadIndices_.buffer != VK_NULL_HANDLE ? NGI_GRID_QUAD_INDEXED : NGI_GRID_NON_INDEXED;
}

bool Renderer::expandable(uint32_t levelSize) const
{
    // Only an index buffer of 12 (N - 1)^2 bytes, a storage buffer of that range, is made
    // (16-bit chunked indices fit any device).
    const uint64_t bytes = 12 * uint64_t(levelSize - 1) * (levelSize - 1);
    return options_.gridExpansion && bytes <= context_.properties.limits.maxStorageBufferRange;
}

bool Renderer::sharesVertices(const SurfacePipeline& pipeline, ShadingMode mode, uint32_t gridSize,
                              uint32_t levelSize) const
{
    return gridSize == levelSize && expandable(levelSize) && !pipeline.readsBarycentrics(mode);
}

uint32_t Renderer::recordGridExpansion(VkCommandBuffer cmd, const GeometryImageSurface& surface,
                                       const DrawParams& params) const
{
    float lod = 0.0f;
    const DrawStats s = selectGrid(surface, params, lod);
    if (!sharesVertices(pipelineFor(params.pipeline), params.mode, s.gridSize, surface.levelSize(s.level))) return 0;
    const Expansion e{&surface, s.level, s.morph};
    return recordExpansions(cmd, {&e, 1});
}

uint32_t Renderer::recordGridExpansion(VkCommandBuffer cmd, const AssetSurface& asset, const DrawParams& params) const
{
    // Each chart as AssetSurface::recordDraw draws it.
    std::vector<Expansion> expansions;
    for (size_t c = 0; c < asset.chartCount(); ++c) {
        const GeometryImageSurface& chart = asset.chart(c);
        DrawParams p = params;
        if (params.gridSize)
            p.gridSize = std::max(2u, ((params.gridSize - 1) >> asset.levelShift(c)) + 1);
        else
            p.lod = asset.chartLod(c, params.lod);
        float lod = 0.0f;
        const DrawStats s = selectGrid(chart, p, lod);
        if (sharesVertices(pipelineFor(params.pipeline), params.mode, s.gridSize, chart.levelSize(s.level)))
            expansions.push_back({&chart, s.level, s.morph});
    }
    return recordExpansions(cmd, expansions);
}

uint32_t Renderer::recordExpansions(VkCommandBuffer cmd, std::span<const Expansion> expansions) const
{
    std::vector<const Expansion*> todo;
    for (const Expansion& e : expansions)
        if (expandable(e.surface->levelSize(e.level)) && !e.surface->expandedGrid(e.level, e.morph)) todo.push_back(&e);
    if (todo.empty()) return 0;
    // The rewrite waits for every earlier draw's reads (same queue, submission order).
    constexpr VkPipelineStageFlags drawStages = VK_PIPELINE_STAGE_VERTEX_INPUT_BIT;
    constexpr VkAccessFlags drawReads = VK_ACCESS_INDEX_READ_BIT;
    memoryBarrier(cmd, drawStages, drawReads, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, expansion_.get());
    for (const Expansion* e : todo) {
        GeometryImageSurface::GridExpansion& slot = e->surface->allocateExpansion(e->level);
        const uint32_t n = e->surface->levelSize(e->level);
        const gpu::GridExpansionPushConstants pc{n, e->morph, GeometryImageSurface::gridChunkRows(n), 0};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, expansionLayout_.get(), 0, 1, &slot.computeSet, 0,
                                nullptr);
        vkCmdPushConstants(cmd, expansionLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(pc), &pc);
        const uint32_t groups = (n - 1 + NGI_TILE - 1) / NGI_TILE;  // one invocation per quad
        vkCmdDispatch(cmd, groups, groups, 1);
        slot.morph = e->morph;
        slot.recorded = true;
    }
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, drawStages, drawReads);
    return uint32_t(todo.size());
}

DrawStats Renderer::recordDraw(VkCommandBuffer cmd, const GeometryImageSurface& surface, const DrawParams& params,
                               std::optional<VkExtent2D> extent) const
{
    float lod = 0.0f;
    DrawStats stats = selectGrid(surface, params, lod);

    // The shaders work in the surface's normalized space: fold the instance's object -> world
    // and the asset's normalized -> object matrices into the clip transform, and take the
    // eye back into normalized space (exact for any invertible world matrix).
    gpu::DrawPushConstants pc{};
    if (params.world) {
        const glm::mat4 worldFromNormalized = *params.world * surface.objectFromNormalized();
        pc.viewProjection = params.viewProjection * worldFromNormalized;
        pc.eye = glm::inverse(worldFromNormalized) * glm::vec4(params.eye, 1.0f);
        pc.eye /= pc.eye.w;
    } else {
        pc.viewProjection = params.viewProjection;
        pc.eye = glm::vec4(params.eye, 1.0f);
    }
    pc.gridSize = stats.gridSize;
    pc.levelSize = surface.levelSize(stats.level);
    pc.morph = stats.morph;
    pc.mode = uint32_t(params.mode);
    pc.lod = params.gridSize > 0 ? float(stats.level) : lod;
    pc.wireWidth = params.wireWidth;
    pc.instanced = 0;

    const SurfacePipeline& pipeline = pipelineFor(params.pipeline);
    const std::optional<GeometryImageSurface::ExpandedGrid> expanded =
        sharesVertices(pipeline, params.mode, pc.gridSize, pc.levelSize)
        ? surface.expandedGrid(stats.level, stats.morph)
        : std::nullopt;
    const VkBuffer shared = expanded ? expanded->indices : VK_NULL_HANDLE;
    pc.gridTopology = shared ? NGI_GRID_SHARED_VERTICES : perQuadTopology();
    const uint32_t way = shared       ? NGI_WAY_SHARED
        : pc.gridSize == pc.levelSize ? NGI_WAY_PER_QUAD
                                      : NGI_WAY_PER_QUAD_BILINEAR;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.pipeline(way, false, surface.cutsOut()));
    setViewportScissor(cmd, params.viewport, params.scissor, extent);
    const VkDescriptorSet sets[2] = {surface.drawSet(stats.level), unusedInstanceSet_};
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(), 0, 2, sets, 0, nullptr);
    vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(pc),
                       &pc);
    const uint64_t quads = stats.triangles / 2;
    stats.sharedVertices = shared != VK_NULL_HANDLE;
    stats.vertexInvocations = shared ? uint64_t(pc.gridSize) * pc.gridSize : quads * (quadIndices_.buffer ? 4 : 6);
    recordGrid(cmd, quads, 1, 0, expanded ? &*expanded : nullptr);
    return stats;
}

void Renderer::setViewportScissor(VkCommandBuffer cmd, const std::optional<VkViewport>& viewport,
                                  const std::optional<VkRect2D>& scissor, std::optional<VkExtent2D> extent)
{
    if (viewport || extent) {
        const VkViewport v =
            viewport.value_or(VkViewport{0.0f, 0.0f, float(extent->width), float(extent->height), 0.0f, 1.0f});
        vkCmdSetViewport(cmd, 0, 1, &v);
    }
    if (scissor || extent) {
        const VkRect2D s = scissor.value_or(VkRect2D{{0, 0}, *extent});
        vkCmdSetScissor(cmd, 0, 1, &s);
    }
}

uint32_t Renderer::recordGrid(VkCommandBuffer cmd, uint64_t quads, uint32_t instanceCount, uint32_t firstInstance,
                              const GeometryImageSurface::ExpandedGrid* shared) const
{
    uint32_t calls = 0;
    if (shared) {
        // One draw per chunk of rows; vertexOffset makes its 16-bit indices sample numbers.
        vkCmdBindIndexBuffer(cmd, shared->indices, 0, VK_INDEX_TYPE_UINT16);
        const uint32_t quadsPerRow = shared->gridSize - 1;
        for (uint32_t row = 0; row < quadsPerRow; row += shared->chunkRows, ++calls) {
            const uint32_t rows = std::min(shared->chunkRows, quadsPerRow - row);
            vkCmdDrawIndexed(cmd, 6 * rows * quadsPerRow, instanceCount, 6 * row * quadsPerRow,
                             int32_t(row * shared->gridSize), firstInstance);
        }
        return calls;
    }
    if (quadIndices_.buffer == VK_NULL_HANDLE) {
        vkCmdDraw(cmd, uint32_t(6 * quads), instanceCount, 0, firstInstance);
        return 1;
    }
    vkCmdBindIndexBuffer(cmd, quadIndices_.buffer, 0, VK_INDEX_TYPE_UINT16);
    for (uint64_t first = 0; first < quads; first += NGI_QUADS_PER_CHUNK, ++calls) {
        const uint32_t count = uint32_t(std::min<uint64_t>(NGI_QUADS_PER_CHUNK, quads - first));
        vkCmdDrawIndexed(cmd, 6 * count, instanceCount, 0, int32_t(4 * first), firstInstance);
    }
    return calls;
}

}  // namespace ngi::vk
