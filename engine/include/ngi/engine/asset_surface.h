// ngi engine: a whole asset on the GPU, one GeometryImageSurface per chart (one chart per
// connected part of the input mesh), drawn at ONE level of detail: every chart draws the same
// level index (ngi::chartLevelForAssetLevel; the bake sizes charts by the square root of their
// area), so every part keeps the same sample density on the surface, a smaller chart stops at
// its own coarsest level, and nothing is dropped.
#pragma once

#include "ngi/asset.h"
#include "ngi/engine/color_images.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/surface.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace ngi::vk {

// How an AssetSurface restores each chart's finer levels from its stored level. The default
// is the tools' default: the asset's network when one is found and restores a chart, else
// bicubic.
struct RestoreOptions {
    // The network to restore with, owned by the caller, who keeps it alive and checks its
    // restores (SuperResolution::checkRestores) once the build has run. Null: see findNetwork.
    SuperResolution* network = nullptr;
    // Without `network`: restore with the network the asset carries (its WGHT chunk) or names
    // (the shipped network found in ngi::networkSearchPath(networkDir)), when it restores at
    // least one chart (ngi::defaultRestoreNetwork, as ngi-render and ngi-view do by default).
    // The surface makes, checks and frees that one itself. false: no network.
    bool findNetwork = true;
    std::filesystem::path networkDir;
    // For the network the surface makes (e.g. a pipeline cache).
    SuperResolutionOptions networkOptions;
    // The restore of every chart when no network restores: bicubic (Catmull-Rom from the stored
    // level: what ngi-eval and the bake's rate control measure) or bilinear (ngi-render --no-sr;
    // cheaper, farther from the input). Under a network, the charts of another factor are
    // always bicubic.
    Upsampling withoutNetwork = Upsampling::bicubic;
};

class AssetSurface {
public:
    // Creates the GPU images of every chart of `asset` and stages their uploads; with
    // restore.findNetwork and no restore.network, looks up the asset's network and makes it
    // (reads the network file, uploads the weights and waits: a load-time call). A network
    // that is not found is not an error: restoreProblem() says why, the charts are restored
    // without one. ngi::Error on bad sizes, when a chart exceeds the device's image limit, or
    // for an asset's WGHT chunk that does not parse.
    // `draws` as GeometryImageSurface's: adaptiveOnly keeps about a quarter of the memory and
    // can be drawn only by an AdaptiveSurface.
    // An asset with base colours (AssetChart::baseColor) gets them on the GPU here, with their
    // mip chains (ChartColorImages: uploaded and waited for), bound to every chart's uniform
    // draw (GeometryImageSurface::setBaseColour) and shared with an AdaptiveSurface made from it.
    AssetSurface(const Renderer& renderer, const Asset& asset, const RestoreOptions& restore = {},
                 SurfaceDraws draws = SurfaceDraws::uniformAndAdaptive);

    // Builds every chart (upload, restore, mip chain, seam weld, geomorph targets) in ONE
    // submission on the renderer's context's queue and WAITS for it (a load-time call; a
    // host that must not block its queue uses recordBuild), then releaseUploads(). With a
    // network (restoreNetwork()), every chart whose stored level its scale factor takes to the
    // chart's full size is restored by it (restoredByNetwork); the other charts (another
    // factor: a multi-chart asset whose small charts store a finer level) are restored
    // bicubically in one pass (Upsampling::bicubic: the network's
    // Catmull-Rom baseline, as ngi-eval restores them). Without a network every chart is
    // restored by RestoreOptions::withoutNetwork. Each chart's restore applies its residual
    // gain (AssetChart::residualGain). ngi::Error naming the network when a restore produced
    // non-finite values (SuperResolution::checkRestores). Call once.
    void build();
    // The network that restores (RestoreOptions::network, or the one the surface found and
    // made; null: none, or after releaseUploads() freed the one it made).
    SuperResolution* restoreNetwork() const { return network_; }
    // Why the surface restores without the asset's network ("" when it restores with one, or
    // when it did not look: RestoreOptions::network given or findNetwork false).
    const std::string& restoreProblem() const { return restoreProblem_; }
    // Network files in the search path that did not read and were skipped ("FILE: PROBLEM").
    const std::vector<std::string>& skippedNetworkFiles() const { return skippedNetworkFiles_; }
    // Whether chart i is restored by the network (its factor takes the stored level to the
    // chart's full size); false without one.
    bool restoredByNetwork(size_t i) const;
    // How chart i's finer levels are restored when the network does not restore it: bicubic
    // under a network; without one, RestoreOptions::withoutNetwork.
    Upsampling upsamplingOf(size_t i) const;
    Upsampling upsamplingWithoutNetwork() const { return withoutNetwork_; }
    // build() one submission per chart, with hooks: `around(cmd, true)` / `around(cmd, false)`
    // are recorded before and after each chart's build (e.g. timestamps), `after()` runs once
    // each has completed (benchmarks time every chart this way). Waits for each submission.
    void buildEach(const std::function<void(VkCommandBuffer, bool)>& around, const std::function<void()>& after);

    // Records the builds of every chart into the host's `cmd` (no submission, no wait): what
    // build() submits. Once the work has completed the host calls releaseUploads(); with a
    // network of its own (RestoreOptions::network: any number of restores fit one command
    // buffer) it first calls network->checkRestores() (ngi::Error for a non-finite restore)
    // and keeps the network alive until then. Call once (ngi::Error if built twice).
    void recordBuild(VkCommandBuffer cmd);
    // Frees the uploads, and the network the surface made after checking its restores
    // (ngi::Error naming it for a non-finite restore). Only after the build has completed.
    void releaseUploads();
    // releaseFinestLevel of every chart (GeometryImageSurface): about three quarters of the
    // GPU memory back for an asset only drawn at LoD >= 1 (each chart then draws its level 1
    // or coarser). Same rule: after the GPU finished the build and the draws recorded before.
    void releaseFinestLevels();

    // Records the draw of every chart at params.lod (each chart at its own level for that
    // LoD, clamped to its levels) or params.gridSize (scaled by each chart's resolution).
    // Same rules as Renderer::recordDraw. Returns the largest chart's level, morph and grid
    // size with triangles and vertex invocations summed over the charts.
    DrawStats recordDraw(VkCommandBuffer cmd, const DrawParams& params,
                         std::optional<VkExtent2D> extent = std::nullopt) const;

    size_t chartCount() const { return charts_.size(); }
    // Chart i's continuous LoD for the asset's `lod`: lod - levelShift(i), clamped to the
    // chart's drawn levels (what recordDraw and DrawBatch draw it at).
    float chartLod(size_t i, float lod) const;
    const GeometryImageSurface& chart(size_t i) const { return charts_.at(i); }
    // log2 of the largest chart's resolution over chart i's: its level offset.
    uint32_t levelShift(size_t i) const { return shifts_.at(i); }
    // The largest chart's full size and drawn level count (down to its coarsest watertight
    // level): the asset's LoD range is [0, levelCount() - 1].
    uint32_t fullSize() const { return charts_.front().fullSize(); }
    uint32_t levelCount() const { return charts_.front().drawnLevelCount(); }
    // Bounding box of every chart's stored samples (normalized space).
    glm::vec3 boundsMin() const;
    glm::vec3 boundsMax() const;
    // The charts' base colours (null when no chart has one): shared, so that an AdaptiveSurface
    // keeps them after this surface is gone.
    const std::shared_ptr<const ChartColorImages>& baseColours() const { return colours_; }
    // Device memory of the charts and their base colours (shared with an AdaptiveSurface made
    // from this one, which counts them too: while both live, do not add the two).
    VkDeviceSize gpuBytes() const;

private:
    const Renderer* renderer_;
    std::vector<GeometryImageSurface> charts_;
    std::vector<uint32_t> shifts_;
    std::vector<float> residualGains_;  // per chart: the restore's s + gain r (AssetChart::residualGain)
    Upsampling withoutNetwork_ = Upsampling::bicubic;
    std::shared_ptr<const ChartColorImages> colours_;  // null: no chart has a base colour
    std::unique_ptr<SuperResolution> ownNetwork_;      // the asset's network, found and made by the constructor
    SuperResolution* network_ = nullptr;               // the network that restores: the caller's or ownNetwork_
    std::string restoreProblem_;
    std::vector<std::string> skippedNetworkFiles_;
    bool built_ = false;
    // The weld across the charts of split components (Asset::crossSeams, seam.h groupWeldPlan),
    // at every level its charts draw: per level and chart a gather and a scatter run of pairs
    // in one buffer, the value slots in another, one descriptor set per (level, chart).
    struct GroupWeldRun {
        uint32_t chart = 0, level = 0, offset = 0, count = 0, scatter = 0;
        VkDescriptorSet set = VK_NULL_HANDLE;
    };
    std::vector<GroupWeldRun> groupWeld_;  // in recording order: per level, every gather, then every scatter
    UniqueBuffer groupPairs_, groupValues_;
    UniqueDescriptorPool groupPool_;
    void prepareGroupWeld(const Asset& asset);
    void recordGroupWeld(VkCommandBuffer cmd) const;
};

}  // namespace ngi::vk
