// A geometry image on the GPU: upload, restoration, nested mip chain, geomorph targets.
#include "ngi/engine/surface.h"

#include "ngi/engine/renderer.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/octahedral.h"
#include "ngi_shared.h"

#include <glm/common.hpp>

#include <algorithm>
#include <cstring>
#include <limits>
#include <span>

namespace ngi::vk {
namespace {

constexpr VkFormat kTexelFormat = VK_FORMAT_R32G32B32A32_UINT;
constexpr VkImageUsageFlags kTexelUsage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT |
    VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;

uint32_t groups(uint32_t n) { return (n + NGI_TILE - 1) / NGI_TILE; }

void computeBarrier(VkCommandBuffer cmd)
{
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
}

// Writes `views` at bindings first, first + 1, ... of `set` (in `layout`; `sampler` for
// combined image samplers, null for storage images).
void writeImages(VkDevice device, VkDescriptorSet set, uint32_t first, VkDescriptorType type, VkSampler sampler,
                 std::initializer_list<VkImageView> views, VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL)
{
    std::vector<VkDescriptorImageInfo> images;
    for (VkImageView view : views) images.push_back({sampler, view, layout});
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.dstBinding = first;
    w.descriptorCount = uint32_t(images.size());
    w.descriptorType = type;
    w.pImageInfo = images.data();
    vkUpdateDescriptorSets(device, 1, &w, 0, nullptr);
}

// Writes all of `buffer` as the storage buffer at `binding` of `set`.
void writeStorageBuffer(VkDevice device, VkDescriptorSet set, uint32_t binding, VkBuffer buffer)
{
    const VkDescriptorBufferInfo info{buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.dstBinding = binding;
    w.descriptorCount = 1;
    w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    w.pBufferInfo = &info;
    vkUpdateDescriptorSets(device, 1, &w, 0, nullptr);
}

}  // namespace

GeometryImageSurface::GeometryImageSurface(const Renderer& renderer, const GeometryImage& positions,
                                           const GeometryImage& normals, uint32_t fullSize, const ChartSeams& seams,
                                           SurfaceDraws draws)
    : renderer_(&renderer), fullSize_(fullSize), draws_(draws)
{
    if (!isNestedGridSize(fullSize))
        throw Error("geometry image: full size " + std::to_string(fullSize) + " is not 2^k+1");
    if (positions.size != normals.size) throw Error("geometry image: position and normal images differ in size");
    const uint32_t count = mipLevelCount(fullSize);
    storedLevel_ = count;
    for (uint32_t l = 0; l < count; ++l)
        if (mipLevelSize(fullSize, l) == positions.size) storedLevel_ = l;
    if (storedLevel_ == count)
        throw Error("geometry image: " + std::to_string(positions.size) + " samples is not a level of a " +
                    std::to_string(fullSize) + "-sample image");

    const Context& c = renderer.context();
    if (fullSize > c.properties.limits.maxImageDimension2D)
        throw Error("geometry image: " + std::to_string(fullSize) + " samples exceed this device's image limit");
    boundsMin_ = glm::vec3(std::numeric_limits<float>::max());
    boundsMax_ = glm::vec3(std::numeric_limits<float>::lowest());
    // Level 0's images in one pool (releaseFinestLevel), the other levels' in another.
    auto samples = [&](uint32_t l) { return ImageDesc{levelSize(l), levelSize(l), kTexelFormat, kTexelUsage}; };
    auto quads = [&](uint32_t l) {
        return ImageDesc{levelSize(l) - 1, levelSize(l) - 1, VK_FORMAT_R32G32B32A32_SFLOAT, kTexelUsage};
    };
    levelCount_ = count;
    if (count < 2) throw Error("geometry image: " + std::to_string(fullSize) + " samples make a single level");
    const bool uniform = draws == SurfaceDraws::uniformAndAdaptive;
    const ImageDesc fine[3] = {samples(0), samples(0), quads(0)};
    fineImages_ = ImagePool(c, std::span<const ImageDesc>(fine, uniform ? 3 : 1));
    std::vector<ImageDesc> descs;
    for (uint32_t l = 1; l < count; ++l) descs.push_back(samples(l));
    for (uint32_t l = 1; l + 1 < count && uniform; ++l) descs.push_back(samples(l));
    for (uint32_t l = 1; l < count && uniform; ++l) descs.push_back(quads(l));
    // The uniform draw's stand-in base colour (setBaseColour): 1 x 1, cleared by recordDrawData.
    if (uniform)
        descs.push_back(
            ImageDesc{1, 1, VK_FORMAT_R8G8B8A8_SRGB, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT});
    images_ = ImagePool(c, descs);
    const VkDeviceSize bytes = VkDeviceSize(positions.texels.size()) * sizeof(glm::uvec4);
    upload_ = UniqueBuffer(c, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                           VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    auto* texels = static_cast<glm::uvec4*>(upload_->mapped);
    for (size_t i = 0; i < positions.texels.size(); ++i) {
        const glm::vec3 p = positions.texels[i];
        boundsMin_ = glm::min(boundsMin_, p);
        boundsMax_ = glm::max(boundsMax_, p);
        uint32_t bits[3];
        std::memcpy(bits, &p, sizeof(bits));
        texels[i] = glm::uvec4(bits[0], bits[1], bits[2], packNormalOctahedral(normals.texels[i]));
    }

    // The seam: levels drawn, and the weld pairs of every restored level it is aligned to
    // (the restore writes levels 0 .. storedLevel - 1; coarser levels are nested subsamples
    // of welded ones, or the stored level, welded by the bake).
    drawnLevelCount_ = count;
    uint32_t weldLevels = 0;
    std::vector<glm::uvec2> pairs;
    if (seams.matched) {
        const uint32_t resolution = fullSize - 1;
        validateSeams(seams, resolution, count, "geometry image");
        drawnLevelCount_ = coarsestDrawnLevel(seams, count) + 1;
        weldLevels = std::min(seams.coarsestWatertightLevel + 1, storedLevel_);
        for (uint32_t l = 0; l < weldLevels; ++l) {
            weldOffsets_.push_back(uint32_t(pairs.size()));
            const std::vector<uint32_t> table = seamWeldTable(seams, resolution, l);
            for (uint32_t t = 0; t < table.size(); ++t)
                if (table[t] != t) pairs.push_back({t, table[t]});
        }
        weldOffsets_.push_back(uint32_t(pairs.size()));
        if (pairs.empty()) weldLevels = 0;  // an open disk: nothing to weld
    }
    if (weldLevels > 0) {
        weldPairs_ =
            UniqueBuffer(c, VkDeviceSize(pairs.size()) * sizeof(glm::uvec2), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        std::memcpy(weldPairs_->mapped, pairs.data(), pairs.size() * sizeof(glm::uvec2));
    }

    // Descriptor sets: compute pairs, geomorph, draw, weld.
    const uint32_t pairCount = count - 1, morphCount = count - 1;
    const uint32_t computeSets = pairCount + morphCount + count + 1;  // + 1: the bicubic restore's
    // Draw sets of three samplers; per level, for the grid expansion, its compute set (a
    // storage image, a storage buffer).
    VkDescriptorPoolSize sizes[3] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 3 * computeSets + weldLevels + count},
                                     {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 4 * count},
                                     {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, weldLevels + count}};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = computeSets + count + weldLevels + count;
    poolInfo.poolSizeCount = 3;
    poolInfo.pPoolSizes = sizes;
    pool_ = UniqueDescriptorPool(c.device);
    NGI_VK_CHECK(vkCreateDescriptorPool(c.device, &poolInfo, nullptr, pool_.out()));
    auto allocate = [&](VkDescriptorSetLayout layout, uint32_t n) {
        std::vector<VkDescriptorSetLayout> layouts(n, layout);
        std::vector<VkDescriptorSet> sets(n);
        if (n == 0) return sets;
        VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        info.descriptorPool = pool_.get();
        info.descriptorSetCount = n;
        info.pSetLayouts = layouts.data();
        NGI_VK_CHECK(vkAllocateDescriptorSets(c.device, &info, sets.data()));
        return sets;
    };
    pairSets_ = allocate(renderer.mipChain().setLayout(), pairCount);
    cubicSet_ = allocate(renderer.mipChain().setLayout(), 1)[0];
    const uint32_t drawn = uniform ? count : 0;  // the uniform draw's data, per level
    morphSets_ = allocate(renderer.mipChain().setLayout(), uniform ? morphCount : 0);
    quadSets_ = allocate(renderer.mipChain().setLayout(), drawn);
    drawSets_ = allocate(renderer.drawSetLayout(), drawn);
    const std::vector<VkDescriptorSet> expansionSets = allocate(renderer.gridExpansionSetLayout(), drawn);
    expansions_.resize(drawn);
    constexpr VkDescriptorType storage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE,
                               sampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    const VkSampler sampler = renderer.texelSampler();
    // Level 0 (binding 0) restored from the stored level (binding 1) in one pass.
    writeImages(c.device, cubicSet_, 0, storage, VK_NULL_HANDLE, {level(0).view, level(storedLevel_).view});
    for (uint32_t l = 0; l < count; ++l) {
        if (l + 1 < count)
            writeImages(c.device, pairSets_[l], 0, storage, VK_NULL_HANDLE, {level(l).view, level(l + 1).view});
        if (!uniform) continue;
        const VkImageView morph = l + 1 < count ? morphTarget(l).view : level(l).view;
        if (l + 1 < count)
            writeImages(c.device, morphSets_[l], 0, storage, VK_NULL_HANDLE, {level(l).view, morphTarget(l).view});
        writeImages(c.device, quadSets_[l], 0, storage, VK_NULL_HANDLE, {level(l).view, morph, quadDiagonal(l).view});
        writeImages(c.device, drawSets_[l], 0, sampled, sampler, {level(l).view, morph, quadDiagonal(l).view});
        writeImages(c.device, drawSets_[l], NGI_DRAW_BINDING_BASE_COLOUR, sampled, sampler, {standInColour().view},
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
        // The grid expansion's set: the diagonals now, the index buffer when it is made.
        GridExpansion& e = expansions_[l];
        e.computeSet = expansionSets[l];
        writeImages(c.device, e.computeSet, NGI_EXPANSION_BINDING_DIAGONALS, storage, VK_NULL_HANDLE,
                    {quadDiagonal(l).view});
    }
    weldSets_ = allocate(renderer.mipChain().weldSetLayout(), weldLevels);
    for (uint32_t l = 0; l < weldLevels; ++l) {
        writeImages(c.device, weldSets_[l], 0, storage, VK_NULL_HANDLE, {level(l).view});
        writeStorageBuffer(c.device, weldSets_[l], 1, weldPairs_->buffer);
    }
}

GeometryImageSurface GeometryImageSurface::fromAsset(const Renderer& renderer, const Asset& asset, size_t chart,
                                                     SurfaceDraws draws)
{
    if (chart >= asset.charts.size())
        throw Error("geometry image: the asset has " + std::to_string(asset.charts.size()) + " charts, not " +
                    std::to_string(chart + 1));
    const AssetChart& c = asset.charts[chart];
    GeometryImageSurface surface(renderer, storedPositions(c), storedNormals(c), c.fullSize(), c.seams, draws);
    glm::mat4 m(1.0f);
    for (int i = 0; i < 3; ++i) {
        m[i][i] = asset.scale[i];
        m[3][i] = asset.offset[i];
    }
    surface.objectFromNormalized_ = m;
    return surface;
}

uint32_t GeometryImageSurface::levelSize(uint32_t level) const { return mipLevelSize(fullSize_, level); }

VkDeviceSize GeometryImageSurface::gpuBytes() const { return fineImages_.allocatedBytes() + images_.allocatedBytes(); }

void GeometryImageSurface::releaseFinestLevel()
{
    if (!built_) throw Error("geometry image surface: releaseFinestLevel before recordBuild");
    fineImages_ = ImagePool{};
    if (!expansions_.empty()) {
        expansions_[0].indices.reset();
        expansions_[0].recorded = false;
    }
    finestLevel_ = 1;
}

std::optional<GeometryImageSurface::ExpandedGrid> GeometryImageSurface::expandedGrid(uint32_t level, float morph) const
{
    if (level >= expansions_.size()) return std::nullopt;
    const GridExpansion& e = expansions_[level];
    if (!e.recorded || e.morph != morph) return std::nullopt;
    return ExpandedGrid{e.indices->buffer, levelSize(level), gridChunkRows(levelSize(level))};
}

uint32_t GeometryImageSurface::gridChunkRows(uint32_t gridSize)
{
    return std::max(1u, std::min(gridSize - 1, 65535u / gridSize - 1));
}

GeometryImageSurface::GridExpansion& GeometryImageSurface::allocateExpansion(uint32_t level) const
{
    GridExpansion& e = expansions_.at(level);
    if (e.indices) return e;
    const Context& c = renderer_->context();
    const uint64_t n = levelSize(level);
    e.indices = UniqueBuffer(c, 6 * (n - 1) * (n - 1) * sizeof(uint16_t),
                             VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDEX_BUFFER_BIT |
                                 VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                             VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    writeStorageBuffer(c.device, e.computeSet, NGI_EXPANSION_BINDING_INDICES, e.indices->buffer);
    e.recorded = false;
    return e;
}

VkDeviceSize GeometryImageSurface::gridExpansionBytes() const
{
    VkDeviceSize bytes = 0;
    for (const GridExpansion& e : expansions_)
        if (e.indices) bytes += e.indices->size;
    return bytes;
}

void GeometryImageSurface::releaseGridExpansions() const
{
    for (GridExpansion& e : expansions_) {
        e.indices.reset();
        e.recorded = false;
    }
}

uint32_t GeometryImageSurface::deviceAllocationCount() const
{
    uint32_t expanded = 0;
    for (const GridExpansion& e : expansions_) expanded += e.indices ? 1 : 0;
    return fineImages_.allocationCount() + images_.allocationCount() + (weldPairs_ ? 1 : 0) + (upload_ ? 1 : 0) +
        expanded;
}

void GeometryImageSurface::recordBuild(VkCommandBuffer cmd, const ChartRestore& restore)
{
    recordLevels(cmd, restore);
    recordDrawData(cmd);
}

void GeometryImageSurface::recordMipPass(VkCommandBuffer cmd, VkPipeline pipeline, VkDescriptorSet set, uint32_t fine,
                                         uint32_t coarse, uint32_t extent) const
{
    const MipChainPipelines& chain = renderer_->mipChain();
    const gpu::MipPushConstants pc{fine, coarse, 0, 0};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, chain.layout(), 0, 1, &set, 0, nullptr);
    vkCmdPushConstants(cmd, chain.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(pc), &pc);
    vkCmdDispatch(cmd, groups(extent), groups(extent), 1);
    computeBarrier(cmd);
}

void GeometryImageSurface::recordLevels(VkCommandBuffer cmd, const ChartRestore& restore)
{
    SuperResolution* const sr = restore.network;
    if (built_) throw Error("geometry image surface: recordBuild called twice");
    if (!upload_) throw Error("geometry image surface: upload already released");
    if (sr && (storedLevel_ == 0 || sr->outputSize(levelSize(storedLevel_)) != fullSize_))
        throw Error("geometry image surface: the x" + std::to_string(sr->scaleFactor()) + " network does not restore " +
                    std::to_string(levelSize(storedLevel_)) + " samples to " + std::to_string(fullSize_));
    built_ = true;
    const Renderer& r = *renderer_;
    const uint32_t count = levelCount();
    const Image& stored = level(storedLevel_);
    auto toGeneral = [&](const Image& img) {
        imageBarrier(cmd, img.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                     VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_GENERAL);
    };
    for (const ImagePool* pool : {&fineImages_, &images_})
        for (size_t i = 0; i < pool->size(); ++i)
            if ((*pool)[i].image != stored.image) toGeneral((*pool)[i]);

    imageBarrier(cmd, stored.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    VkBufferImageCopy copy{};
    copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    copy.imageExtent = {stored.width, stored.height, 1};
    vkCmdCopyBufferToImage(cmd, upload_->buffer, stored.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    imageBarrier(cmd, stored.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT,
                 VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL);

    auto dispatch = [&](VkPipeline pipeline, VkDescriptorSet set, uint32_t fine, uint32_t coarse, uint32_t extent) {
        recordMipPass(cmd, pipeline, set, fine, coarse, extent);
    };
    // Mates of a restored level made bitwise equal (seam_weld.comp), before anything reads it.
    auto weld = [&](uint32_t l) {
        if (l >= weldSets_.size()) return;
        const gpu::SeamWeldPushConstants pc{levelSize(l) - 1, weldOffsets_[l + 1] - weldOffsets_[l], weldOffsets_[l],
                                            0};
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r.mipChain().weld());
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r.mipChain().weldLayout(), 0, 1, &weldSets_[l], 0,
                                nullptr);
        vkCmdPushConstants(cmd, r.mipChain().weldLayout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(pc), &pc);
        vkCmdDispatch(cmd, (pc.pairCount + 63) / 64, 1, 1);
        computeBarrier(cmd);
    };
    // Finer levels: level 0 by the network or bicubically and nested subsamples of it, or bilinear.
    if (sr) {
        sr->record(cmd, stored, level(0), restore.residualGain);
        computeBarrier(cmd);
        weld(0);
        for (uint32_t l = 1; l < storedLevel_; ++l)
            dispatch(r.mipChain().downsample(), pairSets_[l - 1], levelSize(l - 1), levelSize(l), levelSize(l));
    } else if (restore.withoutNetwork == Upsampling::bicubic && storedLevel_ > 0) {
        dispatch(r.mipChain().cubicRestore(), cubicSet_, levelSize(0), levelSize(storedLevel_), levelSize(0));
        weld(0);
        for (uint32_t l = 1; l < storedLevel_; ++l)
            dispatch(r.mipChain().downsample(), pairSets_[l - 1], levelSize(l - 1), levelSize(l), levelSize(l));
    } else {
        for (uint32_t l = storedLevel_; l-- > 0;) {
            dispatch(r.mipChain().upsample(), pairSets_[l], levelSize(l), levelSize(l + 1), levelSize(l));
            weld(l);
        }
    }
    // Coarser levels: nested subsamples.
    for (uint32_t l = storedLevel_ + 1; l < count; ++l)
        dispatch(r.mipChain().downsample(), pairSets_[l - 1], levelSize(l - 1), levelSize(l), levelSize(l));
}

void GeometryImageSurface::recordDrawData(VkCommandBuffer cmd)
{
    if (!built_) throw Error("geometry image surface: recordDrawData before recordLevels");
    const Renderer& r = *renderer_;
    const uint32_t count = uniformDrawable() ? levelCount() : 0;  // adaptiveOnly: the levels are all it draws
    auto dispatch = [&](VkPipeline pipeline, VkDescriptorSet set, uint32_t fine, uint32_t coarse, uint32_t extent) {
        recordMipPass(cmd, pipeline, set, fine, coarse, extent);
    };
    // Geomorph targets of every level but the coarsest.
    for (uint32_t l = 0; l + 1 < count; ++l)
        dispatch(r.mipChain().morphTargets(), morphSets_[l], levelSize(l), levelSize(l + 1), levelSize(l));
    // Per-quad diagonal choice as a function of the geomorph factor.
    for (uint32_t l = 0; l < count; ++l)
        dispatch(r.mipChain().quadDiagonals(), quadSets_[l], levelSize(l), levelSize(l), levelSize(l) - 1);

    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                  VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
    // The stand-in base colour: ngi's grey (the shader tells a 1 x 1 image from a chart's own).
    if (count > 0) {
        const VkImage grey = standInColour().image;
        imageBarrier(cmd, grey, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0,
                     VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        const VkClearColorValue value{{0.78f, 0.80f, 0.84f, 1.0f}};
        const VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdClearColorImage(cmd, grey, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value, 1, &range);
        imageBarrier(cmd, grey, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                     VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT,
                     VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
}

void GeometryImageSurface::setBaseColour(VkImageView view, VkSampler sampler, bool cutsOut)
{
    if (!uniformDrawable())
        throw Error("geometry image surface: setBaseColour on a surface built for the adaptive draw alone");
    if (!view || !sampler) throw Error("geometry image surface: setBaseColour needs an image view and a sampler");
    cutsOut_ = cutsOut;
    for (VkDescriptorSet set : drawSets_)
        writeImages(renderer_->context().device, set, NGI_DRAW_BINDING_BASE_COLOUR,
                    VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, sampler, {view},
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
}

void GeometryImageSurface::releaseUpload() { upload_.reset(); }

namespace {

// Copies one GENERAL-layout image to the host (16 bytes per texel); waits for the GPU.
template <class Texel> std::vector<Texel> readImage(const Context& c, const Image& img)
{
    static_assert(sizeof(Texel) == 16);
    const UniqueBuffer readback(c, VkDeviceSize(img.width) * img.height * sizeof(Texel),
                                VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    std::vector<Texel> texels(size_t(img.width) * img.height);
    c.submitAndWait([&](VkCommandBuffer cmd) {
        imageBarrier(cmd, img.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                     VK_ACCESS_MEMORY_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT,
                     VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        VkBufferImageCopy copy{};
        copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
        copy.imageExtent = {img.width, img.height, 1};
        vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback->buffer, 1, &copy);
        imageBarrier(cmd, img.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                     VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_SHADER_READ_BIT,
                     VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_IMAGE_LAYOUT_GENERAL);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                      VK_ACCESS_HOST_READ_BIT);
    });
    std::memcpy(texels.data(), readback->mapped, texels.size() * sizeof(Texel));
    return texels;
}

}  // namespace

std::vector<glm::uvec4> GeometryImageSurface::readLevel(uint32_t level, bool morph) const
{
    if (level >= levelCount() || (morph && level + 1 >= levelCount()) || level < finestLevel_)
        throw Error("geometry image surface: no such level " + std::to_string(level));
    if (morph && !uniformDrawable())
        throw Error("geometry image surface: built for the adaptive draw, it has no geomorph targets");
    return readImage<glm::uvec4>(renderer_->context(), morph ? morphTarget(level) : this->level(level));
}

namespace {

// Copies a device-local buffer to the host as Ts; waits for the GPU.
template <class T> std::vector<T> readBuffer(const Context& c, const Buffer& buffer)
{
    const UniqueBuffer readback(c, buffer.size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    c.submitAndWait([&](VkCommandBuffer cmd) {
        memoryBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        const VkBufferCopy copy{0, 0, buffer.size};
        vkCmdCopyBuffer(cmd, buffer.buffer, readback->buffer, 1, &copy);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                      VK_ACCESS_HOST_READ_BIT);
    });
    std::vector<T> out(buffer.size / sizeof(T));
    std::memcpy(out.data(), readback->mapped, out.size() * sizeof(T));
    return out;
}

}  // namespace

std::vector<uint32_t> GeometryImageSurface::readGridIndices(uint32_t level) const
{
    if (level >= expansions_.size() || !expansions_[level].indices)
        throw Error("geometry image surface: level " + std::to_string(level) + " has no expanded grid");
    const std::vector<uint16_t> local = readBuffer<uint16_t>(renderer_->context(), *expansions_[level].indices);
    const uint32_t n = levelSize(level), rows = gridChunkRows(n);
    std::vector<uint32_t> indices(local.size());
    for (size_t k = 0; k < local.size(); ++k) {
        const uint32_t row = uint32_t(k / (6 * size_t(n - 1)));  // the quad's row
        indices[k] = local[k] + (row - row % rows) * n;          // + its chunk's first sample
    }
    return indices;
}

std::vector<glm::vec4> GeometryImageSurface::readQuadDiagonals(uint32_t level) const
{
    if (level >= levelCount() || level < finestLevel_)
        throw Error("geometry image surface: no such level " + std::to_string(level));
    if (!uniformDrawable())
        throw Error("geometry image surface: built for the adaptive draw, it has no quad diagonals");
    return readImage<glm::vec4>(renderer_->context(), quadDiagonal(level));
}

}  // namespace ngi::vk
