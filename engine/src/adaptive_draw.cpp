// The adaptive LoD draw (ngi/engine/adaptive_draw.h): core's tile selection (adaptive_lod.h,
// CDLOD after Strugar 2009 with per-tile error bounds) drawn by shaders/adaptive_surface.vert.
#include "ngi/engine/adaptive_draw.h"

#include "ngi/engine/pipelines.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/compact_texel.h"
#include "ngi/fitted_levels.h"
#include "ngi/octahedral.h"
#include "ngi_shaders/adaptive_surface_vert.h"
#include "ngi_shaders/adaptive_surface_frag.h"
#include "ngi_shared.h"

#include <glm/gtc/matrix_inverse.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

namespace ngi::vk {
namespace {

static_assert(NGI_TILE_QUADS == kTileQuads, "ngi_shared.h and adaptive_lod.h disagree on the tile size");
static_assert(sizeof(gpu::AdaptiveInstance) == 144, "AdaptiveInstance as std430 lays it out");
// Instance records (recordDraw calls) one frame may write.
constexpr uint32_t kInstancesPerFrame = 4096;
static_assert(sizeof(gpu::AdaptiveTile) == 16 + 8 * NGI_TILE_QUADS, "AdaptiveTile as std430 lays it out");

// A chart's restored level read back into float images.
void readLevelInto(const GeometryImageSurface& surface, uint32_t level, GeometryImage& positions,
                   GeometryImage& normals)
{
    const std::vector<glm::uvec4> texels = surface.readLevel(level, false);
    const uint32_t n = surface.levelSize(level);
    positions = GeometryImage(n);
    normals = GeometryImage(n);
    for (size_t i = 0; i < texels.size(); ++i) {
        positions.texels[i] = glm::vec3(std::bit_cast<float>(texels[i].x), std::bit_cast<float>(texels[i].y),
                                        std::bit_cast<float>(texels[i].z));
        normals.texels[i] = unpackNormalOctahedral(texels[i].w);
    }
}

// One compact level's image: n x n RGBA16UI, sampled by the vertex stage, written by copies.
ImageDesc compactLevelDesc(uint32_t n)
{
    return {n, n, VK_FORMAT_R16G16B16A16_UINT, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
            VK_IMAGE_ASPECT_COLOR_BIT};
}

// Records the copies of `texels` (level by level, in `pool`'s order) from `staging` at
// `offsets` into the pool's images, leaving them in SHADER_READ_ONLY_OPTIMAL for the vertex stage.
void recordCompactCopies(VkCommandBuffer cmd, VkBuffer staging, const ImagePool& pool,
                         std::span<const VkDeviceSize> offsets)
{
    for (size_t i = 0; i < pool.size(); ++i) {
        const Image& image = pool[i];
        imageBarrier(cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkBufferImageCopy region{};
        region.bufferOffset = offsets[i];
        region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        region.imageExtent = {image.width, image.height, 1};
        vkCmdCopyBufferToImage(cmd, staging, image.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
        imageBarrier(cmd, image.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                     VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_VERTEX_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
}

// A host-visible staging buffer holding `texels` one after the other; their offsets in `offsets`.
UniqueBuffer stageCompactLevels(const Context& context, std::span<const std::vector<glm::u16vec4>* const> texels,
                                std::vector<VkDeviceSize>& offsets)
{
    VkDeviceSize bytes = 0;
    for (const auto* level : texels) bytes += level->size() * sizeof(glm::u16vec4);
    UniqueBuffer staging(context,
                         createBuffer(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT));
    offsets.clear();
    VkDeviceSize offset = 0;
    for (const auto* level : texels) {
        std::memcpy(static_cast<uint8_t*>(staging->mapped) + offset, level->data(),
                    level->size() * sizeof(glm::u16vec4));
        offsets.push_back(offset);
        offset += level->size() * sizeof(glm::u16vec4);
    }
    return staging;
}

// Uploads `texels` (level by level, in `pool`'s order) into the pool's images and leaves them
// in SHADER_READ_ONLY_OPTIMAL for the vertex stage; waits for the GPU.
void uploadCompactLevels(const Context& context, const ImagePool& pool,
                         std::span<const std::vector<glm::u16vec4>> texels)
{
    std::vector<const std::vector<glm::u16vec4>*> levels;
    for (const auto& level : texels) levels.push_back(&level);
    std::vector<VkDeviceSize> offsets;
    const UniqueBuffer staging = stageCompactLevels(context, levels, offsets);
    context.submitAndWait([&](VkCommandBuffer cmd) { recordCompactCopies(cmd, staging->buffer, pool, offsets); });
}

}  // namespace

namespace {

// A descriptor set layout of `bindings`.
UniqueDescriptorSetLayout createSetLayout(VkDevice device, std::span<const VkDescriptorSetLayoutBinding> bindings)
{
    VkDescriptorSetLayoutCreateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    info.bindingCount = uint32_t(bindings.size());
    info.pBindings = bindings.data();
    UniqueDescriptorSetLayout layout(device);
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &info, nullptr, layout.out()));
    return layout;
}

}  // namespace

UniqueDescriptorSetLayout AdaptivePipeline::createLevelsLayout(VkDevice device)
{
    // The level and the next two coarser ones (vertex stage: 0, 1, 2), the chart's base colour
    // (fragment: NGI_DRAW_BINDING_BASE_COLOUR, as in the uniform draw's set 0).
    constexpr VkDescriptorType sampler = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    const VkDescriptorSetLayoutBinding bindings[4] = {
        {0, sampler, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
        {1, sampler, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
        {2, sampler, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
        {NGI_DRAW_BINDING_BASE_COLOUR, sampler, 1, VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
    return createSetLayout(device, bindings);
}

UniqueDescriptorSetLayout AdaptivePipeline::createTilesLayout(VkDevice device)
{
    // The tile records and the instance records (vertex stage).
    constexpr VkDescriptorType storage = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const VkDescriptorSetLayoutBinding bindings[2] = {{0, storage, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr},
                                                      {1, storage, 1, VK_SHADER_STAGE_VERTEX_BIT, nullptr}};
    return createSetLayout(device, bindings);
}

AdaptivePipeline::AdaptivePipeline(const Renderer& renderer, const PassDescription& pass,
                                   std::span<const uint32_t> fragmentSpirv,
                                   std::span<const VkDescriptorSetLayout> hostSetLayouts)
    : levelsLayout_(createLevelsLayout(renderer.context().device)),
      tilesLayout_(createTilesLayout(renderer.context().device)), layout_(renderer.context().device),
      pipeline_(renderer.context().device), cutOutPipeline_(renderer.context().device)
{
    static_assert(NGI_ADAPTIVE_HOST_SET == firstHostSet && NGI_ADAPTIVE_SET_LEVELS == 0 && NGI_ADAPTIVE_SET_TILES == 1);
    const VkDevice device = renderer.context().device;
    std::vector<VkDescriptorSetLayout> sets{levelsLayout_.get(), tilesLayout_.get()};
    sets.insert(sets.end(), hostSetLayouts.begin(), hostSetLayouts.end());
    const VkPushConstantRange range{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                    sizeof(gpu::DrawPushConstants)};
    VkPipelineLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    layoutInfo.setLayoutCount = uint32_t(sets.size());
    layoutInfo.pSetLayouts = sets.data();
    layoutInfo.pushConstantRangeCount = 1;
    layoutInfo.pPushConstantRanges = &range;
    NGI_VK_CHECK(vkCreatePipelineLayout(device, &layoutInfo, nullptr, layout_.out()));
    GraphicsPipelineDesc desc;
    desc.vertexSpirv = adaptive_surface_vert_spv;
    desc.fragmentSpirv = !fragmentSpirv.empty() ? fragmentSpirv
        : pass.colorFormats.empty()             ? std::span<const uint32_t>{}
                                                : std::span<const uint32_t>(adaptive_surface_frag_spv);
    desc.layout = layout_.get();
    desc.pass = pass;
    desc.writeFirstAttachmentOnly = fragmentSpirv.empty();
    if (desc.writeFirstAttachmentOnly && pass.colorFormats.size() > 1 && !renderer.context().independentBlend)
        throw Error("adaptive pipeline: ngi's fragment shader writes colour attachment 0 only; a pass of " +
                    std::to_string(pass.colorFormats.size()) +
                    " colour attachments needs the independentBlend feature");
    try {
        const bool ownShading = fragmentSpirv.empty() && !pass.colorFormats.empty();
        if (ownShading) desc.fragmentConstants = {0};  // NGI_SPEC_CUT_OUT
        *pipeline_.out() = createGraphicsPipeline(device, desc);
        if (ownShading) {
            desc.fragmentConstants = {1};
            *cutOutPipeline_.out() = createGraphicsPipeline(device, desc);
        }
    } catch (const Error& e) {
        throw Error(std::string("adaptive pipeline for a pass of ") + std::to_string(pass.colorFormats.size()) +
                    " colour attachment(s)" + (pass.renderPass ? " (render pass)" : " (dynamic rendering)") + ": " +
                    e.what());
    }
}

AdaptiveSurface::AdaptiveSurface(const Renderer& renderer, const AssetSurface& surface, const Asset& asset,
                                 uint32_t tileCapacity, uint32_t framesInFlight, bool uploadFinest)
    : pool_(renderer.context().device)
{
    if (tileCapacity == 0 || tileCapacity > (1u << 24))
        throw Error("adaptive draw: the tile capacity " + std::to_string(tileCapacity) + " is not in [1, 2^24]");
    if (framesInFlight == 0 || framesInFlight > 8)
        throw Error("adaptive draw: frames in flight " + std::to_string(framesInFlight) + " is not in [1, 8]");
    regions_ = framesInFlight;
    if (asset.charts.size() != surface.chartCount()) throw Error("adaptive draw: the asset does not match the surface");
    const Context& context = renderer.context();
    const VkDevice device = context.device;
    context_ = &context;
    sampler_ = renderer.texelSampler();
    objectFromNormalized_ = surface.chart(0).objectFromNormalized();

    // The CPU mirror: level 0 as the GPU restored it, the coarser levels fitted to it
    // (fitted_levels.h), all made compact; the draw's own copy of the levels is the compact one.
    const size_t chartCount = surface.chartCount();
    pyramids_.resize(chartCount);
    trees_.reserve(chartCount);
    std::vector<std::vector<glm::u16vec4>> compact;
    std::vector<ImageDesc> descs;
    for (size_t c = 0; c < chartCount; ++c) {
        const GeometryImageSurface& chart = surface.chart(c);
        if (chart.finestLevel() != 0)
            throw Error("adaptive draw: chart " + std::to_string(c) + " released its level 0");
        SurfacePyramid& pyramid = pyramids_[c];
        pyramid.positions.resize(chart.levelCount());
        pyramid.normals.resize(chart.levelCount());
        firstImage_.push_back(uint32_t(descs.size()));
        for (uint32_t l = 0; l < chart.levelCount(); ++l)
            readLevelInto(chart, l, pyramid.positions[l], pyramid.normals[l]);
        fitCoarseLevels(pyramid);
        for (uint32_t l = 0; l < chart.levelCount(); ++l) {
            (l == 0 ? finest_ : compact).push_back(makeLevelCompact(pyramid.positions[l], pyramid.normals[l]));
            if (l > 0) descs.push_back(compactLevelDesc(chart.levelSize(l)));
        }
        const uint32_t coarsest = chart.drawnLevelCount() - 1;
        const ChartSeams& seams = asset.charts[c].seams;
        trees_.push_back(buildTileTree(pyramid, coarsest, seams.matched ? seams.coarsestWatertightLevel : coarsest));
    }
    for (size_t c = 0; c < chartCount; ++c) charts_.push_back({&pyramids_[c], &trees_[c], asset.charts[c].seams});
    levels_ = ImagePool(context, descs);
    uploadCompactLevels(context, levels_, compact);
    compact.clear();
    finestImages_.resize(chartCount);
    finestLastUsed_.assign(chartCount, 0);
    {
        // Level 0 now, or (uploadFinest false) when a selection first draws it; a chart of
        // one level keeps it (its level sets read nothing else).
        std::vector<size_t> now;
        for (size_t c = 0; c < chartCount; ++c)
            if (uploadFinest || surface.chart(c).levelCount() < 2) now.push_back(c);
        UniqueBuffer staging;
        if (!now.empty()) context.submitAndWait([&](VkCommandBuffer cmd) { staging = recordFinestUploads(cmd, now); });
    }
    mates_ = buildSurfaceMates(charts_, asset.crossSeams);

    // Set 0: the tile's level and the next coarser one; set 1: the tile and instance records.
    capacity_ = tileCapacity;
    levelsLayout_ = AdaptivePipeline::createLevelsLayout(device);
    tilesLayout_ = AdaptivePipeline::createTilesLayout(device);
    blocks_.push_back(makeRecordBlock(tileCapacity));
    // The asset surface's base colours where it has them (shared), else the default grey's.
    colors_ = surface.baseColours() ? surface.baseColours() : std::make_shared<const ChartColorImages>(context, asset);
    if (!renderer.options().pass().colorFormats.empty() || renderer.options().pass().depthFormat != VK_FORMAT_UNDEFINED)
        ownPipeline_.emplace(renderer, renderer.options().pass());

    uint32_t levelSetCount = 0;
    for (size_t c = 0; c < chartCount; ++c) levelSetCount += surface.chart(c).levelCount();
    const VkDescriptorPoolSize sizes[1] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4 * levelSetCount}};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = levelSetCount;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = sizes;
    NGI_VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, pool_.out()));
    auto allocateSet = [&](VkDescriptorSetLayout layout) {
        VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        allocate.descriptorPool = pool_.get();
        allocate.descriptorSetCount = 1;
        allocate.pSetLayouts = &layout;
        VkDescriptorSet set = VK_NULL_HANDLE;
        NGI_VK_CHECK(vkAllocateDescriptorSets(device, &allocate, &set));
        return set;
    };
    levelSets_.resize(chartCount);
    for (size_t c = 0; c < chartCount; ++c) {
        const GeometryImageSurface& chart = surface.chart(c);
        for (uint32_t l = 0; l < chart.levelCount(); ++l) {
            const VkDescriptorSet set = allocateSet(levelsLayout_.get());
            const uint32_t coarser = std::min(l + 1, chart.levelCount() - 1),
                           coarser2 = std::min(l + 2, chart.levelCount() - 1);
            const VkDescriptorImageInfo images[4] = {
                {renderer.texelSampler(), levelView(c, l), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                {renderer.texelSampler(), levelView(c, coarser), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                {renderer.texelSampler(), levelView(c, coarser2), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
                {colors_->sampler(), colors_->view(c), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
            // Bindings 0-1, 2 and 3: one write each (0-1 change with level 0's residency; 3 is
            // another stage's).
            VkWriteDescriptorSet writes[3]{{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                           {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET},
                                           {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
            for (VkWriteDescriptorSet& w : writes) {
                w.dstSet = set;
                w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
            }
            writes[0].dstBinding = 0;
            writes[0].descriptorCount = 2;
            writes[0].pImageInfo = images;
            writes[1].dstBinding = 2;
            writes[1].descriptorCount = 1;
            writes[1].pImageInfo = images + 2;
            writes[2].dstBinding = 3;
            writes[2].descriptorCount = 1;
            writes[2].pImageInfo = images + 3;
            // Level 0 left on the host: its bindings 0-1 are written when it is uploaded.
            const bool waiting = l == 0 && !finestResident(c);
            vkUpdateDescriptorSets(device, waiting ? 2 : 3, waiting ? writes + 1 : writes, 0, nullptr);
            levelSets_[c].push_back(set);
        }
    }
}

AdaptiveView AdaptiveSurface::view(const glm::mat4& viewProjection, const glm::mat4& world, glm::vec3 eye,
                                   float viewportHeight, float maxErrorPixels, bool cull) const
{
    const glm::mat4 worldFromNormalized = world * objectFromNormalized_;
    AdaptiveView v;
    v.camera = true;
    v.clipFromNormalized = viewProjection * worldFromNormalized;
    const glm::vec4 e = glm::inverse(worldFromNormalized) * glm::vec4(eye, 1.0f);
    v.eye = glm::vec3(e) / e.w;
    v.viewportHeight = viewportHeight;
    // The bound is in normalized units; a world matrix that scales the instance scales the
    // projection with it, which clipFromNormalized already holds.
    v.maxErrorPixels = maxErrorPixels;
    v.cull = cull;
    validateAdaptiveView(v);
    return v;
}

AdaptiveSurface::RecordBlock AdaptiveSurface::makeRecordBlock(uint32_t capacity) const
{
    const Context& context = *context_;
    const VkDevice device = context.device;
    RecordBlock block;
    block.capacity = capacity;
    block.instanceCapacity = std::clamp(capacity / 8, 16u, kInstancesPerFrame);
    block.tiles =
        UniqueBuffer(context,
                     createHostWrittenBuffer(context, VkDeviceSize(capacity) * regions_ * sizeof(gpu::AdaptiveTile),
                                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT));
    block.instances =
        UniqueBuffer(context,
                     createHostWrittenBuffer(
                         context, VkDeviceSize(block.instanceCapacity) * regions_ * sizeof(gpu::AdaptiveInstance),
                         VK_BUFFER_USAGE_STORAGE_BUFFER_BIT));
    block.pool = UniqueDescriptorPool(device);
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    NGI_VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, block.pool.out()));
    VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocate.descriptorPool = block.pool.get();
    allocate.descriptorSetCount = 1;
    const VkDescriptorSetLayout layout = tilesLayout_.get();
    allocate.pSetLayouts = &layout;
    NGI_VK_CHECK(vkAllocateDescriptorSets(device, &allocate, &block.set));
    const VkDescriptorBufferInfo buffers[2] = {{block.tiles->buffer, 0, VK_WHOLE_SIZE},
                                               {block.instances->buffer, 0, VK_WHOLE_SIZE}};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = block.set;
    write.dstBinding = 0;
    write.descriptorCount = 2;
    write.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    write.pBufferInfo = buffers;
    vkUpdateDescriptorSets(device, 1, &write, 0, nullptr);
    return block;
}

VkDeviceSize AdaptiveSurface::recordBytes() const
{
    VkDeviceSize bytes = 0;
    for (const RecordBlock& b : blocks_) bytes += b.tiles->size + b.instances->size;
    return bytes;
}

TileSelection AdaptiveSurface::select(const AdaptiveView& view) const { return selectTiles(charts_, mates_, view); }

AdaptiveDrawStats AdaptiveSurface::recordDraw(VkCommandBuffer cmd, const TileSelection& selection,
                                              const DrawParams& params, std::optional<VkExtent2D> extent,
                                              const AdaptivePipeline* pipeline)
{
    if (!pipeline && !ownPipeline_) throw Error("adaptive draw: the renderer has no pass of its own; give a pipeline");
    const AdaptivePipeline& drawWith = pipeline ? *pipeline : *ownPipeline_;
    AdaptiveDrawStats stats;
    stats.tiles = uint32_t(selection.tiles.size());
    stats.forcedSplits = selection.forcedSplits;
    stats.culled = selection.culledFrustum + selection.culledBackface;
    stats.triangles = selection.triangles;
    // Tiles grouped by (chart, level): one instanced draw each.
    std::vector<const SelectedTile*> drawn;
    for (const SelectedTile& t : selection.tiles)
        if (!t.culled) drawn.push_back(&t);
    std::stable_sort(drawn.begin(), drawn.end(), [](const SelectedTile* a, const SelectedTile* b) {
        return a->chart != b->chart ? a->chart < b->chart : a->level < b->level;
    });
    stats.drawnTiles = uint32_t(drawn.size());
    for (const SelectedTile* t : drawn)
        if (t->level == 0 && !finestResident(t->chart))
            throw Error("adaptive draw: chart " + std::to_string(t->chart) +
                        "'s level 0 is not resident; make it resident for this selection first (recordResidency)");
    // The records go to the frame's current block, or the next one that holds them (made now,
    // kept for later frames, where this frame needs more than the blocks so far).
    const uint32_t count = uint32_t(drawn.size());
    if (drawn.size() >= (size_t(1) << 24)) throw Error("adaptive draw: more than 2^24 tiles in one draw");
    if (used_ + count > blocks_[block_].capacity || instancesUsed_ + 1 > blocks_[block_].instanceCapacity) {
        used_ = instancesUsed_ = 0;
        for (++block_; block_ < blocks_.size() && blocks_[block_].capacity < count;) ++block_;
        if (block_ == blocks_.size()) blocks_.push_back(makeRecordBlock(std::max(capacity_, count)));
    }
    const RecordBlock& block = blocks_[block_];

    // The instance: as Renderer::recordDraw, without a world matrix world space is normalized space.
    const glm::mat4 worldFromNormalized = params.world ? *params.world * objectFromNormalized_ : glm::mat4(1.0f);
    const uint32_t instance = region_ * block.instanceCapacity + instancesUsed_++;
    gpu::AdaptiveInstance& record = static_cast<gpu::AdaptiveInstance*>(block.instances->mapped)[instance];
    record.clipFromNormalized = params.viewProjection * worldFromNormalized;
    record.worldFromNormalized = worldFromNormalized;
    const glm::vec4 eye = glm::inverse(worldFromNormalized) * glm::vec4(params.eye, 1.0f);
    record.eye = eye / eye.w;

    const uint32_t first = region_ * block.capacity + used_;
    auto* records = static_cast<gpu::AdaptiveTile*>(block.tiles->mapped) + first;
    for (size_t i = 0; i < drawn.size(); ++i) {
        const SelectedTile& t = *drawn[i];
        gpu::AdaptiveTile& r = records[i];
        std::memset(&r, 0, sizeof r);
        r.x = t.x * kTileQuads;
        r.y = t.y * kTileQuads;
        r.levelInstance = t.level | (instance << 8);
        r.morph = t.morph;
        constexpr uint32_t P = kTileQuads;
        for (uint32_t b = 0; b < 4 * P; ++b) {
            const uint32_t i0 = b <= P ? b : b <= 2 * P ? P : b <= 3 * P ? 3 * P - b : 0;
            const uint32_t j0 = b <= P ? 0 : b <= 2 * P ? b - P : b <= 3 * P ? P : 4 * P - b;
            const uint32_t x = r.x + i0, y = r.y + j0;
            const BorderState s = selection.borderState(mates_, t.chart, x << t.level, y << t.level);
            const uint32_t bits =
                (s.level > t.level ? NGI_TILE_COARSER_BIT : 0u) | uint32_t(std::lround(s.morph * float(kMorphSteps)));
            r.border[b / 2] |= bits << (16 * (b & 1));
        }
    }

    gpu::DrawPushConstants pc{};
    pc.viewProjection = params.viewProjection;  // world -> clip (the tiles use their instance's)
    pc.eye = glm::vec4(params.eye, 1.0f);       // world space, as in batched draws
    pc.mode = uint32_t(params.mode);
    pc.wireWidth = params.wireWidth;
    pc.gridTopology = NGI_GRID_NON_INDEXED;
    pc.instanced = 1;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, drawWith.pipeline(cutsOut()));
    Renderer::setViewportScissor(cmd, params.viewport, params.scissor, extent);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, drawWith.layout(), 1, 1, &block.set, 0, nullptr);
    vkCmdPushConstants(cmd, drawWith.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof pc,
                       &pc);
    for (size_t begin = 0; begin < drawn.size();) {
        size_t last = begin;
        while (last < drawn.size() && drawn[last]->chart == drawn[begin]->chart &&
               drawn[last]->level == drawn[begin]->level)
            ++last;
        const VkDescriptorSet set = levelSets_[drawn[begin]->chart][drawn[begin]->level];
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, drawWith.layout(), 0, 1, &set, 0, nullptr);
        vkCmdDraw(cmd, 6 * kTileQuads * kTileQuads, uint32_t(last - begin), 0, first + uint32_t(begin));
        ++stats.drawCalls;
        begin = last;
    }
    stats.vertexInvocations = uint64_t(drawn.size()) * 6 * kTileQuads * kTileQuads;
    used_ += uint32_t(drawn.size());
    return stats;
}

VkImageView AdaptiveSurface::levelView(size_t chart, uint32_t level) const
{
    if (level == 0) return finestResident(chart) ? finestImages_[chart][0].view : VK_NULL_HANDLE;
    return levels_[firstImage_.at(chart) + level - 1].view;
}

std::vector<size_t> AdaptiveSurface::finestNeeds(std::span<const TileSelection* const> selections) const
{
    std::vector<size_t> charts;
    for (const TileSelection* selection : selections)
        for (const SelectedTile& t : selection->tiles)
            if (!t.culled && t.level == 0 && t.chart < finest_.size() &&
                std::find(charts.begin(), charts.end(), t.chart) == charts.end())
                charts.push_back(t.chart);
    return charts;
}

void AdaptiveSurface::noteNeeds(std::span<const size_t> charts, uint64_t frame, std::vector<size_t>& missing)
{
    for (size_t c : charts) {
        if (c >= finestLastUsed_.size()) throw Error("adaptive draw: no chart " + std::to_string(c));
        finestLastUsed_[c] = std::max(finestLastUsed_[c], frame);
        if (!finestResident(c) && std::find(missing.begin(), missing.end(), c) == missing.end()) missing.push_back(c);
    }
}

uint32_t AdaptiveSurface::recordResidency(VkCommandBuffer cmd, std::span<const TileSelection* const> selections,
                                          uint64_t frame, uint32_t idleFrames)
{
    const std::vector<size_t> charts = finestNeeds(selections);
    return recordResidency(cmd, std::span<const size_t>(charts), frame, idleFrames);
}

uint32_t AdaptiveSurface::recordResidency(VkCommandBuffer cmd, std::span<const size_t> finestCharts, uint64_t frame,
                                          uint32_t idleFrames)
{
    if (frame < lastFrame_)
        throw Error("adaptive draw: residency for frame " + std::to_string(frame) + " after frame " +
                    std::to_string(lastFrame_));
    lastFrame_ = frame;
    // Staging buffers of uploads the GPU has finished (recorded framesInFlight frames ago).
    std::erase_if(pendingUploads_, [&](const PendingUpload& u) { return u.frame + regions_ <= frame; });
    // Level 0s given back framesInFlight frames ago: no command buffer reads them any more.
    std::erase_if(retired_, [&](const RetiredFinest& r) { return r.frame + regions_ <= frame; });
    std::vector<size_t> missing;
    noteNeeds(finestCharts, frame, missing);
    takeBackRetired(missing);
    // Give back what no selection drew for idleFrames frames. It is freed framesInFlight frames
    // later: a frame still in flight may draw it (a GPU selection reports its draws late).
    const uint64_t idle = std::max<uint64_t>(idleFrames, regions_);
    for (size_t c = 0; c < finestImages_.size(); ++c)
        if (finestResident(c) && finestLastUsed_[c] + idle <= frame) {
            retired_.push_back({c, frame, std::move(finestImages_[c])});
            finestImages_[c] = ImagePool();
        }
    if (missing.empty()) return 0;
    pendingUploads_.push_back({frame, recordFinestUploads(cmd, missing)});
    for (size_t c : missing) writeFinestSet(c);
    return uint32_t(missing.size());
}

void AdaptiveSurface::takeBackRetired(std::vector<size_t>& missing)
{
    std::erase_if(missing, [&](size_t c) {
        const auto it =
            std::find_if(retired_.begin(), retired_.end(), [&](const RetiredFinest& r) { return r.chart == c; });
        if (it == retired_.end()) return false;
        finestImages_[c] = std::move(it->images);  // its level set still points at these images
        retired_.erase(it);
        return true;
    });
}

uint32_t AdaptiveSurface::makeResident(std::span<const TileSelection* const> selections)
{
    std::vector<size_t> missing;
    noteNeeds(finestNeeds(selections), lastFrame_, missing);
    takeBackRetired(missing);
    if (missing.empty()) return 0;
    UniqueBuffer staging;
    context_->submitAndWait([&](VkCommandBuffer cmd) { staging = recordFinestUploads(cmd, missing); });
    for (size_t c : missing) writeFinestSet(c);
    return uint32_t(missing.size());
}

UniqueBuffer AdaptiveSurface::recordFinestUploads(VkCommandBuffer cmd, std::span<const size_t> charts)
{
    std::vector<const std::vector<glm::u16vec4>*> texels;
    for (size_t c : charts) texels.push_back(&finest_[c]);
    std::vector<VkDeviceSize> offsets;
    UniqueBuffer staging = stageCompactLevels(*context_, texels, offsets);
    for (size_t i = 0; i < charts.size(); ++i) {
        const ImageDesc desc = compactLevelDesc(pyramids_[charts[i]].positions[0].size);
        finestImages_[charts[i]] = ImagePool(*context_, {&desc, 1});
        recordCompactCopies(cmd, staging->buffer, finestImages_[charts[i]], {&offsets[i], 1});
    }
    return staging;
}

void AdaptiveSurface::writeFinestSet(size_t c)
{
    // Set [c][0] reads level 0 (binding 0) and level 1 (binding 1; level 0 again for a chart of one level).
    const uint32_t coarser = std::min<uint32_t>(1, uint32_t(levelSets_[c].size()) - 1);
    const VkDescriptorImageInfo images[2] = {
        {sampler_, levelView(c, 0), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL},
        {sampler_, levelView(c, coarser), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL}};
    VkWriteDescriptorSet write{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    write.dstSet = levelSets_[c][0];
    write.dstBinding = 0;
    write.descriptorCount = 2;
    write.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    write.pImageInfo = images;
    vkUpdateDescriptorSets(context_->device, 1, &write, 0, nullptr);
}

VkDeviceSize AdaptiveSurface::levelBytes() const
{
    VkDeviceSize bytes = levels_.allocatedBytes();
    for (const ImagePool& pool : finestImages_) bytes += pool.allocatedBytes();
    for (const RetiredFinest& r : retired_) bytes += r.images.allocatedBytes();
    return bytes;
}

uint32_t AdaptiveSurface::residentFinestCount() const
{
    uint32_t n = 0;
    for (size_t c = 0; c < finestImages_.size(); ++c) n += finestResident(c) ? 1 : 0;
    return n;
}

}  // namespace ngi::vk
