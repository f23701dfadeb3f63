// ngi engine: every chart of an asset on the GPU, drawn at one LoD (see asset_surface.h).
#include "ngi/engine/asset_surface.h"

#include "ngi/engine/super_resolution.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/network_catalog.h"
#include "ngi/printable_text.h"
#include "ngi/seam.h"
#include "ngi_shared.h"

#include <glm/common.hpp>

#include <algorithm>
#include <bit>
#include <cstring>

namespace ngi::vk {

AssetSurface::AssetSurface(const Renderer& renderer, const Asset& asset, const RestoreOptions& restore,
                           SurfaceDraws draws)
    : renderer_(&renderer), withoutNetwork_(restore.withoutNetwork), network_(restore.network)
{
    if (asset.charts.empty()) throw Error("asset '" + printableText(asset.sourceName) + "' has no chart");
    const int largest = std::countr_zero(asset.fullResolution());
    charts_.reserve(asset.charts.size());
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        charts_.push_back(GeometryImageSurface::fromAsset(renderer, asset, c, draws));
        residualGains_.push_back(asset.charts[c].residualGain);
        shifts_.push_back(uint32_t(largest - std::countr_zero(asset.charts[c].fullResolution)));
    }
    // The largest chart first: its levels are the asset's LoD range.
    if (shifts_.front() != 0)
        throw Error("asset '" + printableText(asset.sourceName) + "': chart 0 is not the largest chart");
    if (!asset.crossSeams.empty()) prepareGroupWeld(asset);
    if (asset.hasBaseColors()) {
        colours_ = std::make_shared<const ChartColorImages>(renderer.context(), asset);
        if (draws == SurfaceDraws::uniformAndAdaptive)
            for (size_t c = 0; c < charts_.size(); ++c)
                charts_[c].setBaseColour(colours_->view(c), colours_->sampler(), colours_->cutsOut(c));
    }
    if (!network_ && restore.findNetwork) {
        const std::optional<NetworkWeights> weights =
            defaultRestoreNetwork(asset, networkSearchPath(restore.networkDir), restoreProblem_, skippedNetworkFiles_);
        if (weights) {
            ownNetwork_ = std::make_unique<SuperResolution>(renderer.context(), *weights, restore.networkOptions);
            network_ = ownNetwork_.get();
        }
    }
}

void AssetSurface::prepareGroupWeld(const Asset& asset)
{
    // Every level the welded charts draw (their coarsest watertight level is one per group).
    std::vector<ChartSeams> seams;
    std::vector<uint32_t> resolutions;
    for (const AssetChart& chart : asset.charts)
        seams.push_back(chart.seams), resolutions.push_back(chart.fullResolution);
    uint32_t levels = ~0u;
    for (const CrossSeamSegment& s : asset.crossSeams)
        for (uint32_t c : {s.chartA, s.chartB}) levels = std::min(levels, charts_.at(c).drawnLevelCount());
    std::vector<glm::uvec2> pairs;
    uint32_t slots = 1;
    for (uint32_t l = 0; l < levels; ++l) {
        const GroupWeldPlan plan = groupWeldPlan(seams, resolutions, asset.crossSeams, l);
        slots = std::max(slots, plan.slots);
        for (uint32_t scatter : {0u, 1u})
            for (uint32_t c = 0; c < charts_.size(); ++c) {
                const std::vector<glm::uvec2>& run = scatter ? plan.scatter[c] : plan.gather[c];
                if (run.empty()) continue;
                groupWeld_.push_back({c, l, uint32_t(pairs.size()), uint32_t(run.size()), scatter});
                pairs.insert(pairs.end(), run.begin(), run.end());
            }
    }
    if (groupWeld_.empty()) return;
    const Context& context = renderer_->context();
    groupPairs_ =
        UniqueBuffer(context, VkDeviceSize(pairs.size()) * sizeof(glm::uvec2), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                     VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
    std::memcpy(groupPairs_->mapped, pairs.data(), pairs.size() * sizeof(glm::uvec2));
    groupValues_ = UniqueBuffer(context, VkDeviceSize(slots) * 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    const uint32_t sets = uint32_t(groupWeld_.size());
    const VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, sets},
                                           {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * sets}};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = sets;
    poolInfo.poolSizeCount = 2;
    poolInfo.pPoolSizes = sizes;
    groupPool_ = UniqueDescriptorPool(context.device);
    NGI_VK_CHECK(vkCreateDescriptorPool(context.device, &poolInfo, nullptr, groupPool_.out()));
    const std::vector<VkDescriptorSetLayout> layouts(sets, renderer_->mipChain().groupWeldSetLayout());
    std::vector<VkDescriptorSet> allocated(sets);
    VkDescriptorSetAllocateInfo info{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    info.descriptorPool = groupPool_.get();
    info.descriptorSetCount = sets;
    info.pSetLayouts = layouts.data();
    NGI_VK_CHECK(vkAllocateDescriptorSets(context.device, &info, allocated.data()));
    for (uint32_t i = 0; i < sets; ++i) {
        GroupWeldRun& run = groupWeld_[i];
        run.set = allocated[i];
        const VkDescriptorImageInfo image{VK_NULL_HANDLE, charts_[run.chart].levelView(run.level),
                                          VK_IMAGE_LAYOUT_GENERAL};
        const VkDescriptorBufferInfo buffers[2] = {{groupPairs_->buffer, 0, VK_WHOLE_SIZE},
                                                   {groupValues_->buffer, 0, VK_WHOLE_SIZE}};
        VkWriteDescriptorSet writes[3]{};
        for (uint32_t b = 0; b < 3; ++b) {
            writes[b].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
            writes[b].dstSet = run.set;
            writes[b].dstBinding = b;
            writes[b].descriptorCount = 1;
            writes[b].descriptorType = b == 0 ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            if (b == 0)
                writes[b].pImageInfo = &image;
            else
                writes[b].pBufferInfo = &buffers[b - 1];
        }
        vkUpdateDescriptorSets(context.device, 3, writes, 0, nullptr);
    }
}

void AssetSurface::recordGroupWeld(VkCommandBuffer cmd) const
{
    const MipChainPipelines& chain = renderer_->mipChain();
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, chain.groupWeld());
    uint32_t phase = ~0u;  // (level, pass) of the runs recorded so far
    for (const GroupWeldRun& run : groupWeld_) {
        // A barrier between a level's gather and its scatter, and before the next level.
        const uint32_t now = run.level * 2 + run.scatter;
        if (phase != ~0u && now != phase)
            memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        phase = now;
        const uint32_t resolution = charts_[run.chart].levelSize(run.level) - 1;
        const gpu::GroupWeldPushConstants pc{resolution, run.count, run.offset, run.scatter};
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, chain.groupWeldLayout(), 0, 1, &run.set, 0,
                                nullptr);
        vkCmdPushConstants(cmd, chain.groupWeldLayout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(pc), &pc);
        vkCmdDispatch(cmd, (run.count + 63) / 64, 1, 1);
    }
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

bool AssetSurface::restoredByNetwork(size_t i) const
{
    const GeometryImageSurface& c = charts_.at(i);
    const uint32_t stored = ((c.fullSize() - 1) >> c.storedLevel()) + 1;
    return network_ && c.storedLevel() > 0 && network_->outputSize(stored) == c.fullSize();
}

void AssetSurface::build()
{
    // One submission for every chart: a SuperResolution records any number of restores.
    renderer_->context().submitAndWait([&](VkCommandBuffer cmd) { recordBuild(cmd); });
    // A network that overflows on a chart is an error naming it, never a blank chart.
    if (network_) network_->checkRestores();
    releaseUploads();
}

void AssetSurface::buildEach(const std::function<void(VkCommandBuffer, bool)>& around,
                             const std::function<void()>& after)
{
    if (built_) throw Error("asset surface: built twice");
    if (!groupWeld_.empty()) {
        // Charts welded across one another are built in one submission (the weld needs them all).
        renderer_->context().submitAndWait([&](VkCommandBuffer cmd) {
            around(cmd, true);
            recordBuild(cmd);
            around(cmd, false);
        });
        if (network_) network_->checkRestores();
        after();
        releaseUploads();
        return;
    }
    built_ = true;
    for (size_t c = 0; c < charts_.size(); ++c) {
        GeometryImageSurface& chart = charts_[c];
        SuperResolution* sr = restoredByNetwork(c) ? network_ : nullptr;
        renderer_->context().submitAndWait([&](VkCommandBuffer cmd) {
            around(cmd, true);
            chart.recordBuild(cmd, {sr, residualGains_[c], upsamplingOf(c)});
            around(cmd, false);
        });
        // A network that overflows on this chart is an error naming it, never a blank chart.
        if (network_) network_->checkRestores();
        after();
        chart.releaseUpload();
    }
    releaseUploads();  // the network the surface made, if any
}

void AssetSurface::recordBuild(VkCommandBuffer cmd)
{
    if (built_) throw Error("asset surface: built twice");
    built_ = true;
    // A chart whose stored level the network's factor does not take to its full size is
    // restored bicubically (one network per asset; charts of other factors: asset_surface.h).
    for (size_t c = 0; c < charts_.size(); ++c)
        charts_[c].recordLevels(cmd, {restoredByNetwork(c) ? network_ : nullptr, residualGains_[c], upsamplingOf(c)});
    // The charts of a split component: their shared curves bitwise equal at every drawn level
    // before the geomorph targets are computed from them (ngi::weldGroupSeams on the CPU).
    if (!groupWeld_.empty()) recordGroupWeld(cmd);
    for (GeometryImageSurface& chart : charts_) chart.recordDrawData(cmd);
}

Upsampling AssetSurface::upsamplingOf(size_t chart) const
{
    // Under super-resolution a chart of another factor gets the network's own baseline (its
    // Catmull-Rom skip with a zero residual), as ngi-eval restores it; without, the host's choice.
    if (!network_) return withoutNetwork_;
    return restoredByNetwork(chart) ? Upsampling::bilinear  // unused: the network
                                    : Upsampling::bicubic;
}

void AssetSurface::releaseUploads()
{
    for (GeometryImageSurface& chart : charts_) chart.releaseUpload();
    if (ownNetwork_) {
        // A network that overflows on a chart is an error naming it, never a blank chart.
        ownNetwork_->checkRestores();
        ownNetwork_.reset();
        network_ = nullptr;
    }
}

DrawStats AssetSurface::recordDraw(VkCommandBuffer cmd, const DrawParams& params,
                                   std::optional<VkExtent2D> extent) const
{
    DrawStats total;
    for (size_t c = 0; c < charts_.size(); ++c) {
        const GeometryImageSurface& chart = charts_[c];
        DrawParams p = params;
        if (params.gridSize) {
            p.gridSize = std::max(2u, ((params.gridSize - 1) >> shifts_[c]) + 1);
        } else {
            p.lod = chartLod(c, params.lod);
        }
        const DrawStats stats = renderer_->recordDraw(cmd, chart, p, extent);
        if (c == 0)
            total = stats;
        else {
            total.triangles += stats.triangles;
            total.vertexInvocations += stats.vertexInvocations;
        }
    }
    return total;
}

void AssetSurface::releaseFinestLevels()
{
    for (GeometryImageSurface& chart : charts_) chart.releaseFinestLevel();
}

float AssetSurface::chartLod(size_t i, float lod) const
{
    // The same level index: the same sample density (ngi::chartLevelForAssetLevel).
    return std::clamp(lod, 0.0f, float(charts_.at(i).drawnLevelCount() - 1));
}

glm::vec3 AssetSurface::boundsMin() const
{
    glm::vec3 b = charts_.front().boundsMin();
    for (const GeometryImageSurface& c : charts_) b = glm::min(b, c.boundsMin());
    return b;
}

glm::vec3 AssetSurface::boundsMax() const
{
    glm::vec3 b = charts_.front().boundsMax();
    for (const GeometryImageSurface& c : charts_) b = glm::max(b, c.boundsMax());
    return b;
}

VkDeviceSize AssetSurface::gpuBytes() const
{
    VkDeviceSize total = 0;
    for (const GeometryImageSurface& c : charts_) total += c.gpuBytes();
    return total + (colours_ ? colours_->bytes() : 0);
}

}  // namespace ngi::vk
