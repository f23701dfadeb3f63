// ngi engine: every chart of an asset on the GPU, drawn at one LoD (see asset_surface.h).
#include "ngi/engine/asset_surface.h"

#include "ngi/engine/super_resolution.h"
#include "ngi/error.h"

#include <glm/common.hpp>

#include <algorithm>
#include <bit>

namespace ngi::vk {

AssetSurface::AssetSurface(const Renderer& renderer, const Asset& asset) : renderer_(&renderer)
{
    if (asset.charts.empty()) throw Error("asset '" + asset.sourceName + "' has no chart");
    const int largest = std::countr_zero(asset.fullResolution());
    charts_.reserve(asset.charts.size());
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        charts_.push_back(GeometryImageSurface::fromAsset(renderer, asset, c));
        residualGains_.push_back(asset.charts[c].residualGain);
        shifts_.push_back(uint32_t(largest - std::countr_zero(asset.charts[c].fullResolution)));
    }
    // The largest chart first: its levels are the asset's LoD range.
    if (shifts_.front() != 0) throw Error("asset '" + asset.sourceName + "': chart 0 is not the largest chart");
}

bool AssetSurface::restoredBy(size_t i, const SuperResolution& superResolution) const
{
    const GeometryImageSurface& c = charts_.at(i);
    const uint32_t stored = ((c.fullSize() - 1) >> c.sourceLevel()) + 1;
    return c.sourceLevel() > 0 && superResolution.outputSize(stored) == c.fullSize();
}

void AssetSurface::build(SuperResolution* superResolution)
{
    // One submission for every chart: a SuperResolution records any number of restores.
    renderer_->context().submitAndWait([&](VkCommandBuffer cmd) { recordBuild(cmd, superResolution); });
    // A network that overflows on a chart is an error naming it, never a blank chart.
    if (superResolution) superResolution->checkRestores();
    releaseUploads();
}

void AssetSurface::buildEach(SuperResolution* superResolution, const std::function<void(VkCommandBuffer, bool)>& around,
                             const std::function<void()>& after)
{
    if (built_) throw Error("asset surface: built twice");
    built_ = true;
    for (size_t c = 0; c < charts_.size(); ++c) {
        GeometryImageSurface& chart = charts_[c];
        SuperResolution* sr = superResolution && restoredBy(c, *superResolution) ? superResolution : nullptr;
        renderer_->context().submitAndWait([&](VkCommandBuffer cmd) {
            around(cmd, true);
            chart.recordBuild(cmd, sr, residualGains_[c], upsamplingOf(c, superResolution));
            around(cmd, false);
        });
        // A network that overflows on this chart is an error naming it, never a blank chart.
        if (superResolution) superResolution->checkRestores();
        after();
        chart.releaseUpload();
    }
}

void AssetSurface::recordBuild(VkCommandBuffer cmd, SuperResolution* superResolution)
{
    if (built_) throw Error("asset surface: built twice");
    built_ = true;
    // A chart whose stored level the network's factor does not take to its full size is
    // restored bicubically (one network per asset; charts of other factors: asset_surface.h).
    for (size_t c = 0; c < charts_.size(); ++c)
        charts_[c].recordBuild(cmd, superResolution && restoredBy(c, *superResolution) ? superResolution : nullptr,
                               residualGains_[c], upsamplingOf(c, superResolution));
}

GeometryImageSurface::Upsampling AssetSurface::upsamplingOf(size_t chart, const SuperResolution* superResolution) const
{
    // Under super-resolution a chart of another factor gets the network's own baseline (its
    // Catmull-Rom skip with a zero residual), as ngi-eval restores it; without, the host's choice.
    if (!superResolution) return withoutNetwork_;
    return restoredBy(chart, *superResolution) ? GeometryImageSurface::Upsampling::bilinear  // unused: the network
                                               : GeometryImageSurface::Upsampling::bicubic;
}

void AssetSurface::releaseUploads()
{
    for (GeometryImageSurface& chart : charts_) chart.releaseUpload();
}

DrawStats AssetSurface::recordDraw(VkCommandBuffer cmd, const DrawParams& params, std::optional<VkExtent2D> extent) const
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
        if (c == 0) total = stats;
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
    return total;
}

} // namespace ngi::vk
