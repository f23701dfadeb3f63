// Opening an asset: read, upload, GPU build with timestamps, panel facts.
#include "loaded_asset.h"

#include "ngi/network_catalog.h"

#include "ngi/engine/lod.h"

#include "ngi/engine/resources.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/metadata_text.h"
#include "ngi/stored_level.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

namespace ngi::view {
namespace {

bool hasTimestamps(const vk::Context& context)
{
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice, &count, families.data());
    return families[context.queueFamily].timestampValidBits > 0 && context.properties.limits.timestampPeriod > 0.0f;
}

glm::vec3 texelPosition(const glm::uvec4& t)
{
    glm::vec3 p;
    std::memcpy(&p.x, &t.x, 4);
    std::memcpy(&p.y, &t.y, 4);
    std::memcpy(&p.z, &t.z, 4);
    return p;
}

// Mean length of a row and of a column of a level (normalized units), averaged.
float meanSpan(const std::vector<glm::uvec4>& texels, uint32_t size)
{
    double rows = 0.0, columns = 0.0;
    for (uint32_t a = 0; a < size; ++a)
        for (uint32_t b = 0; b + 1 < size; ++b) {
            rows += glm::length(texelPosition(texels[a * size + b + 1]) - texelPosition(texels[a * size + b]));
            columns += glm::length(texelPosition(texels[(b + 1) * size + a]) - texelPosition(texels[b * size + a]));
        }
    return float((rows + columns) / (2.0 * size));
}

// Every chart of `asset` built (with `network` when given, else the library's restore without
// one; one submission per chart) and waited for; `gpuMs` is the GPU build time summed over the
// charts (< 0 without timestamps). The viewer keeps both restores to switch between them.
std::unique_ptr<vk::AssetSurface> buildSurface(const vk::Renderer& renderer, const Asset& asset,
                                               vk::SuperResolution* network, double& gpuMs)
{
    const vk::Context& context = renderer.context();
    auto surface = std::make_unique<vk::AssetSurface>(renderer, asset,
                                                      vk::RestoreOptions{.network = network, .findNetwork = false});
    vk::UniqueQueryPool queries(context.device);  // destroyed on every path
    if (hasTimestamps(context)) {
        VkQueryPoolCreateInfo info{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
        info.queryType = VK_QUERY_TYPE_TIMESTAMP;
        info.queryCount = 2;
        NGI_VK_CHECK(vkCreateQueryPool(context.device, &info, nullptr, queries.out()));
    }
    gpuMs = queries ? 0.0 : -1.0;
    surface->buildEach(
        [&](VkCommandBuffer cmd, bool begin) {
            if (!queries) return;
            if (begin) {
                vkCmdResetQueryPool(cmd, queries.get(), 0, 2);
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries.get(), 0);
            } else {
                vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries.get(), 1);
            }
        },
        [&] {
            uint64_t ticks[2] = {};
            if (queries &&
                vkGetQueryPoolResults(context.device, queries.get(), 0, 2, sizeof(ticks), ticks, sizeof(uint64_t),
                                      VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS)
                gpuMs += double(ticks[1] - ticks[0]) * context.properties.limits.timestampPeriod * 1e-6;
        });
    return surface;
}

}  // namespace

vk::SuperResolution* networkFor(const LoadedAsset& loaded, vk::SuperResolution* shared)
{
    return loaded.ownNetwork ? loaded.ownNetwork.get() : shared ? shared : loaded.namedNetwork.get();
}

std::string superResolutionProblem(const LoadedAsset& loaded, vk::SuperResolution* shared)
{
    const vk::SuperResolution* network = networkFor(loaded, shared);
    if (!network) {
        std::string why = "No network: start ngi-view with --weights FILE.ngiw";
        if (!loaded.ownNetworkError.empty())
            why += " (the asset's own weights are unusable: " + loaded.ownNetworkError + ")";
        else if (!loaded.namedNetworkProblem.empty())
            why += " (this asset carries no weights; " + loaded.namedNetworkProblem + ").";
        else
            why += " (this asset carries no weights and names no network).";
        return why;
    }
    // The network restores the charts of its factor; the others are restored bicubically.
    // A network that restores none is a problem (the first chart's mismatch is named).
    std::string first;
    for (size_t c = 0; c < loaded.asset.charts.size(); ++c) {
        const AssetChart& a = loaded.asset.charts[c];
        if (a.storedLevel > 0 && network->outputSize(a.storedSize()) == a.fullSize()) return "";
        if (!first.empty()) continue;
        const std::string chart = loaded.asset.charts.size() == 1 ? "this asset" : "chart " + std::to_string(c);
        if (a.storedLevel == 0)
            first = "The asset stores the full resolution of " + chart + ": nothing to restore.";
        else
            first = "The network " + network->label() + " upsamples x" + std::to_string(network->scaleFactor()) + "; " +
                chart + " needs x" + std::to_string(restoreFactor(a.storedLevel)) + " (" +
                std::to_string(a.storedSize()) + " -> " + std::to_string(a.fullSize()) + " samples).";
    }
    return first;
}

void buildRestored(LoadedAsset& loaded, const vk::Renderer& renderer, vk::SuperResolution* shared)
{
    if (loaded.restored) return;
    const std::string problem = superResolutionProblem(loaded, shared);
    if (!problem.empty()) throw Error(problem);
    vk::SuperResolution* network = networkFor(loaded, shared);
    double gpuMs = -1.0;
    std::unique_ptr<vk::AssetSurface> restored = buildSurface(renderer, loaded.asset, network, gpuMs);
    network->releaseTensors();  // each chart's restore was checked for non-finite values by the build
    loaded.restored = std::move(restored);
    loaded.restoredBuildGpuMs = gpuMs;
    double forward = 0.0;
    const std::vector<vk::SrOpTiming> ops = network->profile();
    for (const vk::SrOpTiming& op : ops) forward += op.milliseconds;
    loaded.superResolutionMs = ops.empty() ? -1.0 : forward;
}

double LoadedAsset::compressionRatio() const
{
    double full = 0.0, stored = 0.0;
    for (const AssetChart& c : asset.charts) {
        const double s = double(c.fullResolution >> c.storedLevel);
        full += double(c.fullResolution) * c.fullResolution;
        stored += s * s;
    }
    return stored > 0.0 ? full / stored : 0.0;
}

std::unique_ptr<LoadedAsset> loadAsset(const vk::Renderer& renderer, const std::filesystem::path& path,
                                       std::span<const std::filesystem::path> networkDirs)
{
    const auto start = std::chrono::steady_clock::now();
    auto loaded = std::make_unique<LoadedAsset>();
    loaded->path = path;
    loaded->asset = readAsset(path);
    std::error_code ec;
    loaded->fileBytes = std::filesystem::file_size(path, ec);
    const Asset& asset = loaded->asset;

    double gpuMs = -1.0;
    loaded->surface = buildSurface(renderer, asset, nullptr, gpuMs);
    loaded->buildGpuMs = gpuMs;
    loaded->buildCpuMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

    // Span from a level of about 33 samples per side: fine enough for a size estimate.
    const vk::GeometryImageSurface& surface = loaded->surface->chart(0);  // the largest chart
    uint32_t level = 0;
    while (level + 1 < surface.levelCount() && surface.levelSize(level) > 33) ++level;
    loaded->surfaceSpan = std::max(meanSpan(surface.readLevel(level, false), surface.levelSize(level)), 1e-4f);

    loaded->metadataPretty = indentedMetadata(asset.metadataJson);  // bounded: META comes from the file
    if (!asset.weights.empty()) {
        try {
            const NetworkWeights weights = parseNetworkWeights(asset.weights, path.string() + " (WGHT chunk)");
            loaded->ownNetwork = std::make_unique<vk::SuperResolution>(renderer.context(), weights,
                                                                       vk::SuperResolutionOptions{.profile = true});
        } catch (const std::exception& e) {
            loaded->ownNetworkError = e.what();
        }
    } else if (!asset.networkId.empty()) {
        try {
            std::string problem;
            if (std::optional<NetworkWeights> named =
                    findAssetNetwork(asset, networkDirs, problem, loaded->skippedNetworkFiles))
                loaded->namedNetwork = std::make_unique<vk::SuperResolution>(
                    renderer.context(), *named, vk::SuperResolutionOptions{.profile = true});
            else
                loaded->namedNetworkProblem = problem;
        } catch (const std::exception& e) {
            loaded->namedNetworkProblem = e.what();
        }
    }
    return loaded;
}

float autoLod(const LoadedAsset& loaded, float distance, float fovYDegrees, float viewportHeight, float pixelsPerEdge)
{
    // The engine's LoD helper with the grid edge as the error: level l's edges are
    // span * 2^l / (full - 1) long, each drawn `pixelsPerEdge` pixels long on screen at the
    // orbit target's distance.
    const vk::AssetSurface& surface = *loaded.surface;
    std::vector<float> edges(surface.levelCount());
    for (uint32_t l = 0; l < edges.size(); ++l)
        edges[l] = loaded.surfaceSpan * float(1u << l) / float(surface.fullSize() - 1);
    const float pixelsPerUnit =
        viewportHeight / (2.0f * std::max(distance, 1e-6f) * std::tan(glm::radians(fovYDegrees) * 0.5f));
    return lodForScreenError(edges, pixelsPerUnit, std::max(pixelsPerEdge, 0.25f));
}

vk::AdaptiveSurface& adaptiveFor(LoadedAsset& loaded, const vk::Renderer& renderer, const vk::AssetSurface& drawn,
                                 uint32_t framesInFlight)
{
    std::unique_ptr<vk::AdaptiveSurface>& adaptive =
        &drawn == loaded.restored.get() ? loaded.adaptiveRestored : loaded.adaptive;
    if (!adaptive)
        adaptive =
            std::make_unique<vk::AdaptiveSurface>(renderer, drawn, loaded.asset, 1u << 12, framesInFlight, false);
    return *adaptive;
}

}  // namespace ngi::view
