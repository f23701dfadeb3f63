// The adaptive LoD's selection on the GPU (ngi/engine/gpu_tile_selection.h): core's
// selectTiles (CDLOD after Strugar 2009, per-tile error bounds) as per-tile compute passes,
// shaders/select_*.comp and tile_selection.glsl.
#include "ngi/engine/gpu_tile_selection.h"

#include "ngi/engine/pipelines.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/seam.h"
#include "ngi/tile_bound_code.h"
#include "ngi_shaders/select_close_comp.h"
#include "ngi_shaders/select_commands_comp.h"
#include "ngi_shaders/select_count_comp.h"
#include "ngi_shaders/select_refine_comp.h"
#include "ngi_shaders/select_write_comp.h"
#include "ngi_shared.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <string>
#include <unordered_map>
#include <utility>

namespace ngi::vk {
namespace {

static_assert(NGI_TILE_QUADS == kTileQuads, "ngi_shared.h and adaptive_lod.h disagree on the tile size");
constexpr uint32_t P = kTileQuads;
constexpr VkBufferUsageFlags kStorage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;

// A device-local storage buffer holding `data`, uploaded now (waits for the GPU).
template <class T> UniqueBuffer uploadStatic(const Context& context, const std::vector<T>& data)
{
    const VkDeviceSize bytes = std::max<VkDeviceSize>(sizeof(T) * data.size(), 16);
    UniqueBuffer staging(context, createHostWrittenBuffer(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT));
    if (!data.empty()) std::memcpy(staging->mapped, data.data(), sizeof(T) * data.size());
    UniqueBuffer buffer(context, bytes, kStorage | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                        VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    context.submitAndWait([&](VkCommandBuffer cmd) {
        const VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cmd, staging->buffer, buffer->buffer, 1, &region);
    });
    return buffer;
}

// Tiles (in `chart`, at `level`) whose closed square holds full-resolution sample s.
template <class F> void forEachTileHolding(const TileTree& tree, uint32_t level, glm::uvec2 s, F&& f)
{
    const uint32_t size = P << level, n = tree.tilesPerSide(level);
    auto range = [&](uint32_t v, uint32_t& first, uint32_t& last) {
        last = std::min(v / size, n - 1);
        first = (v % size == 0 && v > 0) ? v / size - 1 : last;
    };
    uint32_t x0, x1, y0, y1;
    range(s.x, x0, x1);
    range(s.y, y0, y1);
    for (uint32_t y = y0; y <= y1; ++y)
        for (uint32_t x = x0; x <= x1; ++x) f(x, y);
}

}  // namespace

GpuTileSelection::GpuTileSelection(const Renderer& renderer, const AdaptiveSurface& surface, uint32_t maxJobs,
                                   uint32_t groups, uint32_t tileCapacity, uint32_t framesInFlight)
    : renderer_(&renderer), surface_(&surface), maxJobs_(maxJobs), groups_(groups)
{
    const Context& context = renderer.context();
    const VkDevice device = context.device;
    if (!context.drawIndirectFirstInstance)
        throw Error("GPU tile selection: the device does not have the drawIndirectFirstInstance feature enabled; "
                    "select on the CPU (AdaptiveSurface::select)");
    if (framesInFlight == 0 || framesInFlight > surface.framesInFlight())
        throw Error("GPU tile selection: " + std::to_string(framesInFlight) + " frames in flight; the adaptive " +
                    "surface was made for " + std::to_string(surface.framesInFlight()) +
                    " (its level 0 residency follows them)");
    if (maxJobs == 0 || groups == 0 || tileCapacity == 0)
        throw Error("GPU tile selection: the job count, the group count and the tile capacity must be at least 1");
    const VkPhysicalDeviceLimits& limits = context.properties.limits;
    if (maxJobs > limits.maxComputeWorkGroupCount[1])
        throw Error("GPU tile selection: " + std::to_string(maxJobs) + " jobs, more than the device dispatches (" +
                    std::to_string(limits.maxComputeWorkGroupCount[1]) + ")");
    const std::vector<AdaptiveChart>& charts = surface.charts();
    const SurfaceMates& mates = surface.mates();
    chartCount_ = uint32_t(charts.size());
    if (chartCount_ >= (1u << 16)) throw Error("GPU tile selection: more than 65535 charts");

    // Tiles level by level, coarsest first, each level's run at a multiple of 32.
    for (const AdaptiveChart& c : charts) {
        if (c.tree->rootLevel >= NGI_SELECT_MAX_LEVELS)
            throw Error("GPU tile selection: a chart of more than " + std::to_string(NGI_SELECT_MAX_LEVELS) +
                        " levels");
        maxRoot_ = std::max(maxRoot_, c.tree->rootLevel);
    }
    chartRecords_.assign(chartCount_, gpu::SelectionChart{});
    levelFirst_.assign(maxRoot_ + 1, 0);
    levelCount_.assign(maxRoot_ + 1, 0);
    std::vector<gpu::SelectionTile> tiles;
    for (int level = int(maxRoot_); level >= 0; --level) {
        const uint32_t l = uint32_t(level);
        while (tiles.size() % 32) tiles.push_back(gpu::SelectionTile{0, 0, 0, 0, NGI_SELECT_NO_TILE});
        levelFirst_[l] = uint32_t(tiles.size());
        for (uint32_t c = 0; c < chartCount_; ++c) {
            const TileTree& tree = *charts[c].tree;
            if (l > tree.rootLevel) continue;
            chartRecords_[c].levelFirst[l] = uint32_t(tiles.size());
            const uint32_t n = tree.tilesPerSide(l);
            for (uint32_t y = 0; y < n; ++y)
                for (uint32_t x = 0; x < n; ++x) {
                    // The bound is its code's already (buildTileTree): this codes it again, exactly.
                    const TileBoundCode code = recodeTileBound(tree.tile(l, x, y));
                    const gpu::SelectionTile t{code.words[0], code.words[1], code.words[2], code.words[3],
                                               c | (l << 16)};
                    tiles.push_back(t);
                }
        }
        levelCount_[l] = uint32_t(tiles.size()) - levelFirst_[l];
    }
    while (tiles.size() % 32) tiles.push_back(gpu::SelectionTile{0, 0, 0, 0, NGI_SELECT_NO_TILE});
    tileCount_ = uint32_t(tiles.size());
    // Bits for levels >= 1 only: a level-0 tile is never refined (levels are numbered coarsest
    // first, so level 0's run is the last, from a multiple of 32), a quarter of the words.
    wordsPerJob_ = levelFirst_[0] / 32;

    // Every perimeter sample's mates (its key's samples, itself included), and per key the
    // samples in (chart, perimeter index).
    std::unordered_map<uint64_t, std::vector<uint32_t>> byKey;
    for (uint32_t c = 0; c < chartCount_; ++c) {
        const uint32_t r = charts[c].tree->resolution;
        if (4 * r > (1u << 16)) throw Error("GPU tile selection: a chart of more than 16384 cells per side");
        for (uint32_t t = 0; t < 4 * r; ++t) byKey[mates.perimeterKey[c][t]].push_back((c << 16) | t);
    }
    std::vector<uint32_t> perimeter, mateList;
    std::unordered_map<uint64_t, uint32_t> listOf;  // key -> its first entry in mateList
    uint32_t bucketFirst = 0;
    for (uint32_t c = 0; c < chartCount_; ++c) {
        const TileTree& tree = *charts[c].tree;
        gpu::SelectionChart& record = chartRecords_[c];
        record.rootLevel = tree.rootLevel;
        record.resolution = tree.resolution;
        record.perimeterLevel = tree.perimeterLevel;
        record.coarsestLevel = tree.coarsestLevel;
        record.closed = mates.closed[c] ? 1u : 0u;
        record.perimeterFirst = uint32_t(perimeter.size());
        record.bucketFirst = bucketFirst;
        bucketFirst += tree.rootLevel + 1;
        for (uint32_t t = 0; t < 4 * tree.resolution; ++t) {
            const uint64_t key = mates.perimeterKey[c][t];
            const std::vector<uint32_t>& group = byKey.at(key);
            if (group.size() < 2) {
                perimeter.push_back(0);
                continue;
            }
            auto [it, inserted] = listOf.try_emplace(key, uint32_t(mateList.size()));
            if (inserted) mateList.insert(mateList.end(), group.begin(), group.end());
            if (group.size() > 255 || it->second >= (1u << 24))
                throw Error("GPU tile selection: too many seam mates for its tables");
            perimeter.push_back(it->second | (uint32_t(group.size()) << 24));
        }
    }
    bucketsPerGroup_ = bucketFirst;

    // Each border tile's tiles one level finer across a seam: those whose closed square holds
    // a mate of one of its own level's border samples, outside its chart's ring.
    std::vector<uint32_t> crossOf(tileCount_, 0), crossList;
    for (uint32_t c = 0; c < chartCount_; ++c) {
        const TileTree& tree = *charts[c].tree;
        const uint32_t r = tree.resolution;
        for (uint32_t l = 1; l <= tree.rootLevel; ++l) {
            const uint32_t n = tree.tilesPerSide(l);
            for (uint32_t y = 0; y < n; ++y)
                for (uint32_t x = 0; x < n; ++x) {
                    if (!(x == 0 || y == 0 || x + 1 == n || y + 1 == n)) continue;
                    std::vector<uint32_t> found;
                    auto visit = [&](uint32_t i, uint32_t j) {
                        const uint32_t sx = (x * P + i) << l, sy = (y * P + j) << l;
                        if (!(sx == 0 || sy == 0 || sx == r || sy == r)) return;
                        const uint64_t key = vertexKey(mates, c, r, sx, sy);
                        const auto group = byKey.find(key);
                        if (group == byKey.end()) return;
                        for (uint32_t m : group->second) {
                            const uint32_t mc = m >> 16;
                            const TileTree& mt = *charts[mc].tree;
                            if (l - 1 > mt.rootLevel) continue;
                            const glm::uvec2 s = perimeterSample(mt.resolution, m & 0xFFFFu);
                            forEachTileHolding(mt, l - 1, s, [&](uint32_t tx, uint32_t ty) {
                                const bool ring =
                                    mc == c && tx + 1 >= 2 * x && tx <= 2 * x + 2 && ty + 1 >= 2 * y && ty <= 2 * y + 2;
                                if (ring) return;
                                const uint32_t index =
                                    chartRecords_[mc].levelFirst[l - 1] + ty * mt.tilesPerSide(l - 1) + tx;
                                if (std::find(found.begin(), found.end(), index) == found.end()) found.push_back(index);
                            });
                        }
                    };
                    for (uint32_t i = 0; i <= P; ++i) visit(i, 0), visit(i, P);
                    for (uint32_t j = 1; j < P; ++j) visit(0, j), visit(P, j);
                    if (found.empty()) continue;
                    if (found.size() > 255 || crossList.size() >= (1u << 24))
                        throw Error("GPU tile selection: too many tiles across a seam for its tables");
                    crossOf[chartRecords_[c].levelFirst[l] + y * n + x] =
                        uint32_t(crossList.size()) | (uint32_t(found.size()) << 24);
                    crossList.insert(crossList.end(), found.begin(), found.end());
                }
        }
    }

    const uint64_t bitBytes = uint64_t(wordsPerJob_) * maxJobs * 4;
    const uint64_t largest = std::max<uint64_t>(sizeof(gpu::SelectionTile) * uint64_t(tileCount_), bitBytes);
    if (largest > limits.maxStorageBufferRange)
        throw Error("GPU tile selection: " + std::to_string(largest) +
                    " bytes of tiles or bits, more than a storage buffer holds on this device (" +
                    std::to_string(limits.maxStorageBufferRange) + "); fewer jobs or smaller charts");
    tiles_ = uploadStatic(context, tiles);
    cross_ = uploadStatic(context, crossOf);
    crossTiles_ = uploadStatic(context, crossList);
    perimeter_ = uploadStatic(context, perimeter);
    mates_ = uploadStatic(context, mateList);
    const VkDeviceSize counterWords = 2 * VkDeviceSize(bucketsPerGroup_) * groups + 1 + 5 * maxJobs + chartCount_;
    frames_.resize(framesInFlight);
    for (FrameSet& f : frames_) {
        f.charts = UniqueBuffer(context,
                                createHostWrittenBuffer(context, sizeof(gpu::SelectionChart) * chartCount_, kStorage));
        f.views =
            UniqueBuffer(context, createHostWrittenBuffer(context, sizeof(gpu::SelectionView) * maxJobs, kStorage));
        f.instances =
            UniqueBuffer(context, createHostWrittenBuffer(context, sizeof(gpu::AdaptiveInstance) * maxJobs, kStorage));
        f.bits = UniqueBuffer(context, std::max<VkDeviceSize>(VkDeviceSize(wordsPerJob_) * maxJobs * 4, 4),
                              kStorage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        // The counters take every atomic of the passes: device-local (on a discrete GPU
        // host-visible memory would send each across the bus), copied for the host once the
        // passes are done.
        f.counters = UniqueBuffer(context, counterWords * 4,
                                  kStorage | VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                  VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        f.countersRead = UniqueBuffer(context, counterWords * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        std::memset(f.countersRead->mapped, 0, counterWords * 4);
        f.commands = UniqueBuffer(context, std::max<VkDeviceSize>(16 * VkDeviceSize(bucketsPerGroup_) * groups, 16),
                                  kStorage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                      VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                  VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    }
    context.submitAndWait([&](VkCommandBuffer cmd) {
        for (const FrameSet& f : frames_) vkCmdFillBuffer(cmd, f.commands->buffer, 0, VK_WHOLE_SIZE, 0);
    });

    // Per frame in flight, one set of every binding for the passes and one set 1 (records,
    // instances) for the draws.
    std::vector<VkDescriptorSetLayoutBinding> bindings;
    for (uint32_t b = 0; b <= NGI_SELECT_BINDING_RECORDS; ++b)
        bindings.push_back({b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr});
    VkDescriptorSetLayoutCreateInfo layoutInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    layoutInfo.bindingCount = uint32_t(bindings.size());
    layoutInfo.pBindings = bindings.data();
    setLayout_ = UniqueDescriptorSetLayout(device);
    NGI_VK_CHECK(vkCreateDescriptorSetLayout(device, &layoutInfo, nullptr, setLayout_.out()));
    tilesLayout_ = AdaptivePipeline::createTilesLayout(device);
    pool_ = UniqueDescriptorPool(device);
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                    (uint32_t(bindings.size()) + 2) * framesInFlight};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 2 * framesInFlight;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    NGI_VK_CHECK(vkCreateDescriptorPool(device, &poolInfo, nullptr, pool_.out()));
    const VkDescriptorSetLayout layouts[2] = {setLayout_.get(), tilesLayout_.get()};
    VkDescriptorSetAllocateInfo allocate{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    allocate.descriptorPool = pool_.get();
    allocate.descriptorSetCount = 2;
    allocate.pSetLayouts = layouts;
    for (FrameSet& f : frames_) {
        VkDescriptorSet sets[2];
        NGI_VK_CHECK(vkAllocateDescriptorSets(device, &allocate, sets));
        f.set = sets[0];
        f.drawSet = sets[1];
    }

    const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(gpu::SelectionPushConstants)};
    VkPipelineLayoutCreateInfo pipelineLayoutInfo{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    const VkDescriptorSetLayout setLayout = setLayout_.get();
    pipelineLayoutInfo.setLayoutCount = 1;
    pipelineLayoutInfo.pSetLayouts = &setLayout;
    pipelineLayoutInfo.pushConstantRangeCount = 1;
    pipelineLayoutInfo.pPushConstantRanges = &range;
    layout_ = UniquePipelineLayout(device);
    NGI_VK_CHECK(vkCreatePipelineLayout(device, &pipelineLayoutInfo, nullptr, layout_.out()));
    refine_ = UniquePipeline(device);
    close_ = UniquePipeline(device);
    count_ = UniquePipeline(device);
    commandsPass_ = UniquePipeline(device);
    write_ = UniquePipeline(device);
    *refine_.out() = createComputePipeline(device, layout_.get(), select_refine_comp_spv);
    *close_.out() = createComputePipeline(device, layout_.get(), select_close_comp_spv);
    *count_.out() = createComputePipeline(device, layout_.get(), select_count_comp_spv);
    *commandsPass_.out() = createComputePipeline(device, layout_.get(), select_commands_comp_spv);
    *write_.out() = createComputePipeline(device, layout_.get(), select_write_comp_spv);
    for (FrameSet& f : frames_)
        makeRecords(
            f, uint32_t(std::min<uint64_t>(tileCapacity, limits.maxStorageBufferRange / sizeof(gpu::AdaptiveTile))));
}

const GpuTileSelection::FrameSet& GpuTileSelection::frameSet(uint32_t frame) const
{
    if (frame >= frames_.size())
        throw Error("GPU tile selection: frame " + std::to_string(frame) + " of " + std::to_string(frames_.size()) +
                    " in flight");
    return frames_[frame];
}

GpuTileSelection::FrameSet& GpuTileSelection::frameSet(uint32_t frame)
{
    return const_cast<FrameSet&>(std::as_const(*this).frameSet(frame));
}

void GpuTileSelection::makeRecords(FrameSet& f, uint32_t capacity)
{
    const Context& context = renderer_->context();
    f.records = UniqueBuffer(context, VkDeviceSize(capacity) * sizeof(gpu::AdaptiveTile),
                             kStorage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    f.capacity = capacity;
    writeSet(f);
}

void GpuTileSelection::writeSet(const FrameSet& f)
{
    const Buffer* buffers[NGI_SELECT_BINDING_RECORDS + 1] = {&*tiles_,     &*cross_,     &*crossTiles_, &*f.charts,
                                                             &*perimeter_, &*mates_,     &*f.views,     &*f.bits,
                                                             &*f.counters, &*f.commands, &*f.records};
    VkDescriptorBufferInfo infos[NGI_SELECT_BINDING_RECORDS + 3];
    std::vector<VkWriteDescriptorSet> writes;
    for (uint32_t b = 0; b <= NGI_SELECT_BINDING_RECORDS; ++b) {
        infos[b] = {buffers[b]->buffer, 0, VK_WHOLE_SIZE};
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = f.set;
        w.dstBinding = b;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w.pBufferInfo = &infos[b];
        writes.push_back(w);
    }
    infos[NGI_SELECT_BINDING_RECORDS + 1] = {f.records->buffer, 0, VK_WHOLE_SIZE};
    infos[NGI_SELECT_BINDING_RECORDS + 2] = {f.instances->buffer, 0, VK_WHOLE_SIZE};
    for (uint32_t b = 0; b < 2; ++b) {
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = f.drawSet;
        w.dstBinding = b;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w.pBufferInfo = &infos[NGI_SELECT_BINDING_RECORDS + 1 + b];
        writes.push_back(w);
    }
    vkUpdateDescriptorSets(renderer_->context().device, uint32_t(writes.size()), writes.data(), 0, nullptr);
}

void GpuTileSelection::recordSelect(VkCommandBuffer cmd, std::span<const GpuSelectionJob> jobs, uint32_t frame)
{
    FrameSet& f = frameSet(frame);
    if (jobs.empty() || jobs.size() > maxJobs_)
        throw Error("GPU tile selection: " + std::to_string(jobs.size()) + " jobs (1 to " + std::to_string(maxJobs_) +
                    " allowed)");
    for (const GpuSelectionJob& job : jobs) {
        validateAdaptiveView(job.view);
        if (job.group >= groups_)
            throw Error("GPU tile selection: group " + std::to_string(job.group) + " of " + std::to_string(groups_));
    }
    for (uint32_t c = 0; c < chartCount_; ++c) {
        const TileTree& tree = *surface_->charts()[c].tree;
        const bool always = tree.perimeterLevel == 0 || tree.coarsestLevel == 0 || tree.rootLevel == 0;
        if (always && !surface_->finestResident(c))
            throw Error("GPU tile selection: chart " + std::to_string(c) +
                        " draws its level 0 at its border, which is not resident; make it resident first");
        chartRecords_[c].finestDrawable = surface_->finestResident(c) ? 0u : 1u;
    }
    // This frame's previous overflow (the GPU has finished that frame) asks every frame for
    // larger records; this one grows to the largest asked.
    if (f.lastJobs > 0) {
        const uint32_t overflow = static_cast<const uint32_t*>(f.countersRead->mapped)[2 * bucketsPerGroup_ * groups_];
        if (overflow > 0) {
            const uint64_t most =
                renderer_->context().properties.limits.maxStorageBufferRange / sizeof(gpu::AdaptiveTile);
            grownCapacity_ = uint32_t(std::max<uint64_t>(
                grownCapacity_,
                std::min<uint64_t>(2 * (uint64_t(f.capacity) + overflow), std::min<uint64_t>(most, 1u << 26))));
        }
    }
    if (grownCapacity_ > f.capacity) makeRecords(f, grownCapacity_);
    f.lastJobs = uint32_t(jobs.size());
    f.selected = true;
    std::memcpy(f.charts->mapped, chartRecords_.data(), sizeof(gpu::SelectionChart) * chartCount_);
    auto* views = static_cast<gpu::SelectionView*>(f.views->mapped);
    auto* instances = static_cast<gpu::AdaptiveInstance*>(f.instances->mapped);
    for (uint32_t j = 0; j < jobs.size(); ++j) {
        const AdaptiveView& view = jobs[j].view;
        gpu::SelectionView& v = views[j];
        std::memset(&v, 0, sizeof v);
        v.clipFromNormalized = view.clipFromNormalized;
        v.eye = glm::vec4(view.eye, 1.0f);
        v.viewportHeight = view.viewportHeight;
        v.budget = view.camera ? view.maxErrorPixels : view.maxError;
        v.instance = j;
        v.group = jobs[j].group;
        if (view.camera) {
            const ViewFrustum f = viewFrustum(view.clipFromNormalized);
            for (uint32_t k = 0; k < f.planeCount; ++k) v.planes[k] = f.planes[k];
            v.planeCount = f.planeCount;
            v.gradW = f.gradW;
            v.rowY = f.rowY;
            v.flags = 1u | (view.cull ? 2u : 0u) | (f.orthographic ? 0u : 4u);
        }
        const glm::mat4 worldFromNormalized = jobs[j].world * surface_->objectFromNormalized();
        instances[j].clipFromNormalized = view.clipFromNormalized;
        instances[j].worldFromNormalized = worldFromNormalized;
        instances[j].eye = glm::vec4(view.eye, 1.0f);
    }

    const uint32_t buckets = bucketsPerGroup_ * groups_;
    gpu::SelectionPushConstants pc{};
    pc.jobCount = uint32_t(jobs.size());
    pc.wordsPerJob = wordsPerJob_;
    pc.buckets = buckets;
    pc.statsFirst = 2 * buckets + 1;
    pc.bucketsPerGroup = bucketsPerGroup_;
    pc.levelFlagsFirst = pc.statsFirst + 4 * pc.jobCount + chartCount_;
    if (wordsPerJob_ > 0) vkCmdFillBuffer(cmd, f.bits->buffer, 0, VkDeviceSize(wordsPerJob_) * jobs.size() * 4, 0);
    vkCmdFillBuffer(cmd, f.counters->buffer, 0, VK_WHOLE_SIZE, 0);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout_.get(), 0, 1, &f.set, 0, nullptr);
    auto dispatch = [&](VkPipeline pipeline, uint32_t words, uint32_t jobCount) {
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
        vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, (words + NGI_SELECT_LOCAL - 1) / NGI_SELECT_LOCAL, jobCount, 1);
        memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    };
    auto atLevel = [&](uint32_t l) {
        pc.level = l;
        pc.firstTile = levelFirst_[l];
        pc.tileCount = levelCount_[l];
    };
    auto roots = [&](uint32_t l) {
        for (uint32_t c = 0; c < chartCount_; ++c)
            if (chartRecords_[c].rootLevel == l) return 1u;
        return 0u;
    };
    for (uint32_t l = maxRoot_; l >= 1; --l) {
        atLevel(l);
        pc.roots = roots(l);
        dispatch(refine_.get(), (pc.tileCount + 31) / 32, pc.jobCount);
    }
    for (uint32_t l = 1; l <= maxRoot_; ++l) {
        atLevel(l);
        dispatch(close_.get(), (pc.tileCount + 31) / 32, pc.jobCount);
    }
    for (uint32_t l = 0; l <= maxRoot_; ++l) {
        atLevel(l);
        pc.roots = roots(l);
        dispatch(count_.get(), (pc.tileCount + 31) / 32, pc.jobCount);
    }
    pc.tileCount = f.capacity;  // the commands pass: the records' capacity
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, commandsPass_.get());
    vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
    vkCmdDispatch(cmd, 1, 1, 1);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, write_.get());
    for (uint32_t l = 0; l <= maxRoot_; ++l) {  // the levels write to disjoint records: no barrier between
        atLevel(l);
        pc.roots = roots(l);
        vkCmdPushConstants(cmd, layout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
        vkCmdDispatch(cmd, ((pc.tileCount + 31) / 32 + NGI_SELECT_LOCAL - 1) / NGI_SELECT_LOCAL, pc.jobCount, 1);
    }
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                  VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                      VK_PIPELINE_STAGE_TRANSFER_BIT,
                  VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
    // The counters for the host (readFrame, the next recordSelect's overflow).
    const VkBufferCopy copy{0, 0, f.counters->size};
    vkCmdCopyBuffer(cmd, f.counters->buffer, f.countersRead->buffer, 1, &copy);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                  VK_ACCESS_HOST_READ_BIT);
}

uint32_t GpuTileSelection::recordDraw(VkCommandBuffer cmd, uint32_t group, const DrawParams& params,
                                      std::optional<VkExtent2D> extent, const AdaptivePipeline* pipeline,
                                      uint32_t frame)
{
    if (group >= groups_)
        throw Error("GPU tile selection: group " + std::to_string(group) + " of " + std::to_string(groups_));
    const FrameSet& f = frameSet(frame);
    if (!f.selected) return 0;  // nothing selected with this frame yet
    const AdaptivePipeline* drawWith = pipeline ? pipeline : surface_->ownPipeline();
    if (!drawWith) throw Error("adaptive draw: the renderer has no pass of its own; give a pipeline");
    gpu::DrawPushConstants pc{};
    pc.viewProjection = params.viewProjection;
    pc.eye = glm::vec4(params.eye, 1.0f);
    pc.mode = uint32_t(params.mode);
    pc.wireWidth = params.wireWidth;
    pc.gridTopology = NGI_GRID_NON_INDEXED;
    pc.instanced = 1;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, drawWith->pipeline(surface_->cutsOut()));
    Renderer::setViewportScissor(cmd, params.viewport, params.scissor, extent);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, drawWith->layout(), 1, 1, &f.drawSet, 0, nullptr);
    vkCmdPushConstants(cmd, drawWith->layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof pc,
                       &pc);
    uint32_t draws = 0;
    for (uint32_t c = 0; c < chartCount_; ++c)
        for (uint32_t l = 0; l <= chartRecords_[c].rootLevel; ++l) {
            const VkDescriptorSet set = surface_->levelSet(c, l);
            if (set == VK_NULL_HANDLE) continue;  // a level 0 not resident: the selection drew none of it
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, drawWith->layout(), 0, 1, &set, 0, nullptr);
            const VkDeviceSize bucket = VkDeviceSize(group) * bucketsPerGroup_ + chartRecords_[c].bucketFirst + l;
            vkCmdDrawIndirect(cmd, f.commands->buffer, bucket * sizeof(VkDrawIndirectCommand), 1,
                              sizeof(VkDrawIndirectCommand));
            ++draws;
        }
    return draws;
}

GpuTileSelection::Frame GpuTileSelection::readFrame(uint32_t frame) const
{
    const FrameSet& f = frameSet(frame);
    const auto* counters = static_cast<const uint32_t*>(f.countersRead->mapped);
    const uint32_t statsFirst = 2 * bucketsPerGroup_ * groups_ + 1;
    Frame result;
    result.overflow = counters[statsFirst - 1];
    for (uint32_t j = 0; j < f.lastJobs; ++j) {
        const uint32_t* s = counters + statsFirst + 4 * j;
        result.jobs.push_back({s[NGI_SELECT_STAT_DRAWN], s[NGI_SELECT_STAT_CULLED_FRUSTUM],
                               s[NGI_SELECT_STAT_CULLED_BACKFACE], s[NGI_SELECT_STAT_TRIANGLES]});
    }
    for (uint32_t c = 0; c < chartCount_; ++c)
        if (counters[statsFirst + 4 * f.lastJobs + c] != 0) result.finestCharts.push_back(c);
    return result;
}

std::vector<GpuSelectedTile> GpuTileSelection::readRecords(uint32_t frame) const
{
    const FrameSet& f = frameSet(frame);
    const Context& context = renderer_->context();
    const VkDeviceSize commandBytes = 16 * VkDeviceSize(bucketsPerGroup_) * groups_;
    UniqueBuffer readback(context, commandBytes + f.records->size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    context.submitAndWait([&](VkCommandBuffer cmd) {
        const VkBufferCopy commands{0, 0, commandBytes}, records{0, commandBytes, f.records->size};
        vkCmdCopyBuffer(cmd, f.commands->buffer, readback->buffer, 1, &commands);
        vkCmdCopyBuffer(cmd, f.records->buffer, readback->buffer, 1, &records);
    });
    const auto* bytes = static_cast<const uint8_t*>(readback->mapped);
    std::vector<GpuSelectedTile> out;
    for (uint32_t g = 0; g < groups_; ++g)
        for (uint32_t c = 0; c < chartCount_; ++c)
            for (uint32_t l = 0; l <= chartRecords_[c].rootLevel; ++l) {
                VkDrawIndirectCommand command;
                std::memcpy(&command,
                            bytes + 16 * (VkDeviceSize(g) * bucketsPerGroup_ + chartRecords_[c].bucketFirst + l),
                            sizeof command);
                for (uint32_t k = 0; k < command.instanceCount; ++k) {
                    gpu::AdaptiveTile r;
                    std::memcpy(&r, bytes + commandBytes + sizeof r * (VkDeviceSize(command.firstInstance) + k),
                                sizeof r);
                    GpuSelectedTile t;
                    t.group = g;
                    t.chart = c;
                    t.level = r.levelInstance & 0xFFu;
                    t.instance = r.levelInstance >> 8;
                    t.x = r.x / P;
                    t.y = r.y / P;
                    t.morph = r.morph;
                    for (uint32_t b = 0; b < 4 * P; ++b) t.border[b] = uint16_t(r.border[b / 2] >> (16 * (b & 1)));
                    out.push_back(t);
                }
            }
    return out;
}

VkDeviceSize GpuTileSelection::staticBytes() const
{
    return tiles_->size + cross_->size + crossTiles_->size + perimeter_->size + mates_->size;
}

VkDeviceSize GpuTileSelection::frameBytes() const
{
    VkDeviceSize bytes = 0;
    for (const FrameSet& f : frames_)
        bytes += f.charts->size + f.views->size + f.instances->size + f.bits->size + f.counters->size +
            f.countersRead->size + f.commands->size + f.records->size;
    return bytes;
}

}  // namespace ngi::vk
