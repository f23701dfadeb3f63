// Batched drawing: instances sorted into (chart, level) buckets, one instanced draw each.
#include "ngi/engine/draw_batch.h"

#include "ngi/engine/asset_surface.h"
#include "ngi/engine/surface.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi_shared.h"

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <map>
#include <numeric>
#include <unordered_map>

namespace ngi::vk {

DrawBatch::DrawBatch(const Renderer& renderer, uint32_t capacity)
    : renderer_(renderer), capacity_(capacity), pool_(renderer.context().device)
{
    if (capacity == 0) throw Error("draw batch: capacity must be at least one instance record");
    const Context& c = renderer.context();
    records_ = UniqueBuffer(c,
                            createHostWrittenBuffer(c, VkDeviceSize(capacity) * sizeof(gpu::DrawInstance),
                                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT));
    const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = 1;
    poolInfo.poolSizeCount = 1;
    poolInfo.pPoolSizes = &size;
    NGI_VK_CHECK(vkCreateDescriptorPool(c.device, &poolInfo, nullptr, pool_.out()));
    set_ = renderer.allocateInstanceSet(pool_.get(), records_->buffer);
}

void DrawBatch::clear()
{
    entries_.clear();
    instances_ = 0;
    used_ = 0;
}

void DrawBatch::add(const AssetSurface& asset, const glm::mat4& world, float lod)
{
    if (asset.chartCount() > 0 && !asset.chart(0).uniformDrawable())
        throw Error(
            "draw batch: a surface built for the adaptive draw only (SurfaceDraws::adaptiveOnly) has no uniform draw");
    for (size_t c = 0; c < asset.chartCount(); ++c)
        entries_.push_back({&asset.chart(c), world, asset.chartLod(c, lod)});
    ++instances_;
}

void DrawBatch::add(const GeometryImageSurface& surface, const glm::mat4& world, float lod)
{
    if (!surface.uniformDrawable())
        throw Error(
            "draw batch: a surface built for the adaptive draw only (SurfaceDraws::adaptiveOnly) has no uniform draw");
    entries_.push_back({&surface, world, lod});
    ++instances_;
}

DrawBatch::Selection DrawBatch::select(const Entry& e)
{
    // As Renderer::recordDraw: never finer than the surface keeps.
    const float lod = std::max(e.lod, float(e.surface->finestLevel()));
    const LodSelection s = selectLod(e.surface->drawnLevelCount(), e.surface->fullSize(), lod);
    return {s.level, s.morph, s.gridSize, lod};
}

uint32_t DrawBatch::recordGridExpansion(VkCommandBuffer cmd)
{
    // (chart, level) -> the one geomorph factor of its instances, unless they differ.
    struct Morph {
        float morph;
        bool uniform;
    };
    std::map<std::pair<const GeometryImageSurface*, uint32_t>, Morph> buckets;
    for (const Entry& e : entries_) {
        const Selection s = select(e);
        const auto [b, added] = buckets.emplace(std::pair(e.surface, s.level), Morph{s.morph, true});
        if (!added) b->second.uniform = b->second.uniform && b->second.morph == s.morph;
    }
    std::vector<Renderer::Expansion> expansions;
    for (const auto& [key, m] : buckets)
        if (m.uniform) expansions.push_back({key.first, key.second, m.morph});
    return renderer_.recordExpansions(cmd, expansions);
}

BatchStats DrawBatch::record(VkCommandBuffer cmd, const BatchParams& params, std::optional<VkExtent2D> extent)
{
    BatchStats stats;
    stats.instances = uint32_t(instances_);
    if (entries_.size() > capacity_ - used_)
        throw Error("draw batch: " + std::to_string(entries_.size()) + " instance records do not fit (capacity " +
                    std::to_string(capacity_) + ", " + std::to_string(used_) + " used since clear())");
    // The frustum's planes (Gribb and Hartmann 2001, "Fast Extraction of Viewing Frustum
    // Planes from the World-View-Projection Matrix"), Vulkan's 0 <= z <= w; inward normals.
    std::vector<glm::vec4> planes;
    if (params.frustumCull) {
        const glm::mat4 m = glm::transpose(params.viewProjection);  // m[i]: row i
        for (const glm::vec4 p : {m[3] + m[0], m[3] - m[0], m[3] + m[1], m[3] - m[1], m[2], m[3] - m[2]}) {
            const float n = glm::length(glm::vec3(p));
            if (n > 1e-20f) planes.push_back(p / n);  // a degenerate plane (infinite far) culls nothing
        }
    }
    auto outside = [&](const Entry& e) {
        const glm::mat4 w = e.world * e.surface->objectFromNormalized();
        const glm::vec3 lo = e.surface->boundsMin(), hi = e.surface->boundsMax();
        const glm::vec3 centre = w * glm::vec4(0.5f * (lo + hi), 1.0f);
        const float scale =
            std::max({glm::length(glm::vec3(w[0])), glm::length(glm::vec3(w[1])), glm::length(glm::vec3(w[2]))});
        // The sphere around the stored samples' box, 25% wider for restored detail beyond it.
        const float radius = 1.25f * 0.5f * glm::length(hi - lo) * scale;
        for (const glm::vec4& p : planes)
            if (glm::dot(glm::vec3(p), centre) + p.w < -radius) return true;
        return false;
    };

    // Level and geomorph of each record (Renderer::recordDraw's rule), then buckets: charts
    // in the order they were first added, levels fine to coarse, instances in added order.
    struct Item {
        uint32_t entry, surfaceRank, level;
        float morph;
        uint32_t gridSize;
        float lod;  // clamped to the surface's finest level
    };
    std::unordered_map<const GeometryImageSurface*, uint32_t> rank;
    std::vector<Item> items;
    items.reserve(entries_.size());
    for (uint32_t i = 0; i < entries_.size(); ++i) {
        const Entry& e = entries_[i];
        if (!planes.empty() && outside(e)) {
            ++stats.culled;
            continue;
        }
        const Selection s = select(e);
        const uint32_t r = rank.emplace(e.surface, uint32_t(rank.size())).first->second;
        items.push_back({i, r, s.level, s.morph, s.gridSize, s.lod});
    }
    stats.records = uint32_t(items.size());
    if (items.empty()) return stats;
    std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
        return a.surfaceRank != b.surfaceRank ? a.surfaceRank < b.surfaceRank : a.level < b.level;
    });

    // The records, exactly as recordDraw computes its push constants.
    auto* out = static_cast<gpu::DrawInstance*>(records_->mapped) + used_;
    for (size_t k = 0; k < items.size(); ++k) {
        const Entry& e = entries_[items[k].entry];
        gpu::DrawInstance& d = out[k];
        const glm::mat4 worldFromNormalized = e.world * e.surface->objectFromNormalized();
        d.clipFromNormalized = params.viewProjection * worldFromNormalized;
        d.worldFromNormalized = worldFromNormalized;
        d.eye = glm::inverse(worldFromNormalized) * glm::vec4(params.eye, 1.0f);
        d.eye /= d.eye.w;
        d.morph = items[k].morph;
        d.lod = items[k].lod;
        d.pad0 = d.pad1 = 0;
    }

    const SurfacePipeline& pipeline = renderer_.pipelineFor(params.pipeline);
    // Every bucket's grid is its level's (selectLod): per quad or shared; the alpha test where
    // the bucket's surface cuts out.
    uint32_t boundWay = NGI_WAY_PER_QUAD;
    bool boundCutOut = false;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.pipeline(boundWay, true, boundCutOut));
    Renderer::setViewportScissor(cmd, params.viewport, params.scissor, extent);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(), NGI_DRAW_SET_INSTANCES, 1, &set_,
                            0, nullptr);
    gpu::DrawPushConstants pc{};
    pc.viewProjection = params.viewProjection;
    pc.eye = glm::vec4(params.eye, 1.0f);
    pc.mode = uint32_t(params.mode);
    pc.wireWidth = params.wireWidth;
    pc.instanced = 1;
    for (size_t first = 0; first < items.size();) {
        size_t end = first + 1;
        while (end < items.size() && items[end].surfaceRank == items[first].surfaceRank &&
               items[end].level == items[first].level)
            ++end;
        const GeometryImageSurface& surface = *entries_[items[first].entry].surface;
        const uint32_t level = items[first].level;
        pc.gridSize = items[first].gridSize;
        pc.levelSize = surface.levelSize(level);
        // Shared vertices when the bucket's level was expanded for its one geomorph factor.
        bool uniform = true;
        for (size_t k = first; k < end; ++k) uniform = uniform && items[k].morph == items[first].morph;
        const std::optional<GeometryImageSurface::ExpandedGrid> expanded =
            uniform && renderer_.sharesVertices(pipeline, params.mode, pc.gridSize, pc.levelSize)
            ? surface.expandedGrid(level, items[first].morph)
            : std::nullopt;
        const VkBuffer shared = expanded ? expanded->indices : VK_NULL_HANDLE;
        pc.gridTopology = shared ? NGI_GRID_SHARED_VERTICES : renderer_.perQuadTopology();
        const uint32_t way = shared ? NGI_WAY_SHARED : NGI_WAY_PER_QUAD;
        if (way != boundWay ||
            surface.cutsOut() != boundCutOut) {  // the same layout: sets and push constants stay bound
            boundWay = way, boundCutOut = surface.cutsOut();
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.pipeline(way, true, boundCutOut));
        }
        const VkDescriptorSet set = surface.drawSet(level);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipeline.layout(), NGI_DRAW_SET_LEVEL, 1, &set, 0,
                                nullptr);
        vkCmdPushConstants(cmd, pipeline.layout(), VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           sizeof(pc), &pc);
        const uint32_t count = uint32_t(end - first);
        const uint64_t quads = gridTriangleCount(pc.gridSize) / 2;
        stats.drawCalls +=
            renderer_.recordGrid(cmd, quads, count, used_ + uint32_t(first), expanded ? &*expanded : nullptr);
        stats.triangles += 2 * quads * count;
        stats.vertexInvocations += (shared ? uint64_t(pc.gridSize) * pc.gridSize
                                           : quads * (pc.gridTopology == NGI_GRID_QUAD_INDEXED ? 4 : 6)) *
            count;
        stats.sharedBuckets += shared ? 1 : 0;
        ++stats.buckets;
        first = end;
    }
    used_ += uint32_t(items.size());
    return stats;
}

}  // namespace ngi::vk
