// ngi-render: headless capture of a geometry-image asset at any level of detail to PNG.
// A thin client of the engine library: read asset -> build the GPU mip chain -> draw ->
// read back -> write PNG.
#include "label_font.h"

#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/context.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/pipeline_cache.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/network_weights.h"
#include "ngi/output_files.h"
#include "ngi/png_io.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

namespace {

const char* kUsage =
    "usage: ngi-render ASSET -o OUT.png [--lod F | --grid N] [--size WxH] [--yaw DEG] [--pitch DEG]\n"
    "                  [--mode shaded|normals|wireframe|lod] [--contact-sheet] [--samples 1|4]\n"
    "                  [--sr [--weights NET.ngiw] | --no-sr] [--device NAME|INDEX] [--validation]\n"
    "       ngi-render --list-devices\n"
    "Renders ASSET headless (no window) to a PNG. --lod is continuous (0 = full resolution);\n"
    "--grid draws a fixed N x N vertex grid; --contact-sheet draws every mip level side by side.\n"
    "--sr restores the full resolution with the super-resolution network (the asset's own\n"
    "weights, or --weights); --no-sr (default) upsamples the stored level bilinearly.\n";

using ngi::UsageError;

struct Options {
    std::string asset, output, mode = "shaded", device, weights;
    std::optional<float> lod;
    std::optional<uint32_t> grid;
    uint32_t width = 800, height = 800, samples = 4;
    float yaw = 30.0f, pitch = 30.0f;
    bool contactSheet = false, listDevices = false, validation = false, superResolution = false;
};

constexpr auto parseFloat = ngi::parseFloatOption;
constexpr auto parseUint = ngi::parseUintOption;

Options parse(int argc, char** argv)
{
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(a + " needs a value");
            return argv[++i];
        };
        if (a == "-o" || a == "--output") o.output = value();
        else if (a == "--lod") o.lod = parseFloat(a, value());
        else if (a == "--grid") o.grid = parseUint(a, value());
        else if (a == "--size") {
            const std::string v = value();
            const auto x = v.find('x');
            if (x == std::string::npos) throw UsageError("--size expects WxH, got '" + v + "'");
            o.width = parseUint(a, v.substr(0, x));
            o.height = parseUint(a, v.substr(x + 1));
            if (o.width == 0 || o.height == 0) throw UsageError("--size must be positive");
        } else if (a == "--yaw") o.yaw = parseFloat(a, value());
        else if (a == "--pitch") o.pitch = parseFloat(a, value());
        else if (a == "--mode") o.mode = value();
        else if (a == "--samples") o.samples = parseUint(a, value());
        else if (a == "--device") o.device = value();
        else if (a == "--contact-sheet") o.contactSheet = true;
        else if (a == "--sr") o.superResolution = true;
        else if (a == "--no-sr") o.superResolution = false;
        else if (a == "--weights") o.weights = value();
        else if (a == "--list-devices") o.listDevices = true;
        else if (a == "--validation") o.validation = true;
        else if (a == "-h" || a == "--help") {
            std::cout << kUsage;
            std::exit(0);
        } else if (!a.empty() && a[0] == '-') throw UsageError("unknown option " + a);
        else if (o.asset.empty()) o.asset = a;
        else throw UsageError("unexpected argument " + a);
    }
    if (o.listDevices) return o;
    if (o.asset.empty()) throw UsageError("no ASSET given");
    if (o.output.empty()) throw UsageError("no output given (-o OUT.png)");
    if (o.lod && o.grid) throw UsageError("--lod and --grid are exclusive");
    if (o.samples != 1 && o.samples != 4) throw UsageError("--samples must be 1 or 4");
    if (!o.weights.empty() && !o.superResolution) throw UsageError("--weights needs --sr");
    return o;
}

int listDevices()
{
    for (const auto& d : ngi::vk::listDevices())
        std::printf("%u: %s (%s, Vulkan %u.%u)%s%s\n", d.index, d.name.c_str(), d.type.c_str(),
                    VK_API_VERSION_MAJOR(d.apiVersion), VK_API_VERSION_MINOR(d.apiVersion),
                    d.suitable ? "" : " -- unsuitable: ", d.unsuitableBecause.c_str());
    return 0;
}

constexpr glm::vec4 kBackground{0.11f, 0.12f, 0.14f, 1.0f};

int run(const Options& o)
{
    // Checked before any work: the PNG's directory exists and -o is neither an input (the
    // asset, the weights) nor a directory. The PNG replaces -o only once it is complete.
    ngi::OutputFiles outputs({o.output}, {o.asset, o.weights});
    const ngi::Asset asset = ngi::readAsset(o.asset);
    const ngi::vk::ShadingMode mode = ngi::vk::parseShadingMode(o.mode);
    auto context = ngi::vk::Context::create({.validation = o.validation, .device = o.device});
    ngi::vk::RendererOptions ro;
    ro.samples = o.samples == 4 ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT;
    ngi::vk::Renderer renderer(*context, ro);
    // Errors of the restore name the asset (and, from the network's side, the network:
    // the --weights path or "the asset's WGHT chunk"). The weights file's own errors name it.
    auto forAsset = [&](auto&& step) {
        try {
            return step();
        } catch (const ngi::Error& e) {
            throw ngi::Error(o.asset + ": " + e.what());
        }
    };
    std::unique_ptr<ngi::vk::SuperResolution> network;
    // The network's pipelines go through a cache kept on disk (pipeline_cache.h): drivers that
    // compile at pipeline creation start fast the second time.
    std::unique_ptr<ngi::vk::PipelineCacheFile> pipelineCache;
    if (o.superResolution) {
        pipelineCache = std::make_unique<ngi::vk::PipelineCacheFile>(*context, ngi::vk::defaultPipelineCachePath(*context));
        if (o.weights.empty() && asset.weights.empty())
            throw ngi::Error(o.asset + ": --sr needs a network: this asset carries no weights; give --weights NET.ngiw");
        ngi::NetworkWeights weights = o.weights.empty() ? ngi::NetworkWeights{} : ngi::readNetworkWeights(o.weights);
        network = forAsset([&] {
            if (o.weights.empty()) weights = ngi::parseNetworkWeights(asset.weights, "the asset's WGHT chunk");
            for (size_t c = 0; c < asset.charts.size(); ++c) {  // one network restores every chart
                const ngi::AssetChart& chart = asset.charts[c];
                const std::string which = asset.charts.size() == 1 ? "this asset's" : "chart " + std::to_string(c) + "'s";
                if (chart.storedLevel == 0 || chart.storedLevel > 16 || weights.scaleFactor != 1u << chart.storedLevel)
                    throw ngi::Error("the x" + std::to_string(weights.scaleFactor) + " network " + ngi::networkLabel(weights) +
                                     " restores " + std::to_string(chart.storedSize()) + " samples per side to " +
                                     std::to_string((chart.storedSize() - 1) * weights.scaleFactor + 1) + ", but " + which +
                                     " full resolution is " + std::to_string(chart.fullSize()) +
                                     (chart.storedLevel ? " (it needs a x" + std::to_string(1u << chart.storedLevel) + " network)"
                                                        : " (it stores its full resolution: nothing to restore)"));
            }
            ngi::vk::SuperResolutionOptions srOptions;
            srOptions.pipelineCache = pipelineCache->handle();
            return std::make_unique<ngi::vk::SuperResolution>(*context, weights, srOptions);
        });
        try {
            pipelineCache->save();
        } catch (const ngi::Error& e) {
            std::fprintf(stderr, "ngi-render: warning: %s (the pipeline cache is not kept)\n", e.what());
        }
    }
    // Every chart; weights that overflow restore NaN positions: the build's error names the
    // network (SuperResolution::checkLastRestore), never a blank image.
    auto surfacePointer = forAsset([&] {
        auto built = std::make_unique<ngi::vk::AssetSurface>(renderer, asset);
        built->build(network.get());
        return built;
    });
    const ngi::vk::AssetSurface& surface = *surfacePointer;
    if (network) network->releaseTensors();
    if (o.grid && (*o.grid < 2 || *o.grid > surface.fullSize()))
        throw ngi::Error("--grid " + std::to_string(*o.grid) + " is outside [2, " + std::to_string(surface.fullSize()) + "]");
    const float maxLod = float(surface.levelCount() - 1);
    if (o.lod && (*o.lod < 0.0f || *o.lod > maxLod))
        throw ngi::Error("--lod " + std::to_string(*o.lod) + " is outside [0, " + std::to_string(int(maxLod)) + "]");

    ngi::vk::OffscreenTarget target(renderer, o.width, o.height);
    const float aspect = float(o.width) / float(o.height);
    const ngi::vk::OrbitCamera camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), o.yaw, o.pitch, aspect);

    auto renderAt = [&](std::optional<float> lod, std::optional<uint32_t> grid, ngi::vk::DrawStats& stats) {
        ngi::vk::DrawParams p;
        p.viewProjection = camera.viewProjection(aspect);
        p.eye = camera.eye();
        p.lod = lod.value_or(0.0f);
        p.gridSize = grid.value_or(0);
        p.mode = mode;
        p.wireWidth = 1.0f;
        return target.render([&](VkCommandBuffer cmd) { stats = surface.recordDraw(cmd, p, target.extent()); },
                             kBackground);
    };

    const uint8_t white[3] = {235, 235, 235};
    if (!o.contactSheet) {
        ngi::vk::DrawStats stats;
        std::vector<uint8_t> pixels = renderAt(o.lod, o.grid, stats);
        outputs.writeWith(o.output, [&](const auto& staged) { ngi::writePng8(staged, o.width, o.height, 4, pixels.data()); });
        outputs.commit();
        std::printf("wrote %s: level %u, %ux%u grid, morph %.2f, %llu triangles, %s restore (%s, %s)\n",
                    o.output.c_str(), stats.level, stats.gridSize, stats.gridSize, stats.morph,
                    (unsigned long long)stats.triangles, network ? "super-resolution" : "bilinear",
                    context->properties.deviceName, asset.sourceName.c_str());
    } else {
        const uint32_t levels = surface.levelCount();
        const uint32_t columns = std::min<uint32_t>(levels, 4), rows = (levels + columns - 1) / columns;
        const uint32_t labelHeight = 40, tileW = o.width, tileH = o.height + labelHeight;
        const uint32_t sheetW = tileW * columns, sheetH = tileH * rows;
        std::vector<uint8_t> sheet(size_t(sheetW) * sheetH * 4);
        for (size_t i = 0; i < sheet.size(); i += 4) {
            sheet[i] = uint8_t(kBackground.r * 255);
            sheet[i + 1] = uint8_t(kBackground.g * 255);
            sheet[i + 2] = uint8_t(kBackground.b * 255);
            sheet[i + 3] = 255;
        }
        auto label = [&](uint32_t level) {
            const uint32_t n = surface.chart(0).levelSize(level);
            uint64_t triangles = 0;  // every chart at its level for this LoD
            for (size_t c = 0; c < surface.chartCount(); ++c) {
                const ngi::vk::GeometryImageSurface& chart = surface.chart(c);
                const uint32_t l = std::min(level - std::min(level, surface.levelShift(c)), chart.levelCount() - 1);
                triangles += ngi::gridTriangleCount(chart.levelSize(l));
            }
            return "L" + std::to_string(level) + "  " + std::to_string(n) + "X" + std::to_string(n) + "  " +
                   std::to_string(triangles) + " TRIS";
        };
        int scale = 3;  // one size for every label: the largest at which the longest (level 0) fits
        while (scale > 1 && ngi::labelWidth(label(0), scale) > int(tileW) - 8) --scale;
        for (uint32_t l = 0; l < levels; ++l) {
            ngi::vk::DrawStats stats;
            const std::vector<uint8_t> tile = renderAt(float(l), std::nullopt, stats);
            const uint32_t ox = (l % columns) * tileW, oy = (l / columns) * tileH;
            for (uint32_t y = 0; y < o.height; ++y)
                std::memcpy(&sheet[((size_t(oy) + y) * sheetW + ox) * 4], &tile[size_t(y) * o.width * 4], size_t(o.width) * 4);
            const std::string text = label(l);
            ngi::drawLabel(sheet, sheetW, sheetH, int(ox) + (int(tileW) - ngi::labelWidth(text, scale)) / 2,
                           int(oy + o.height + (labelHeight - 7 * scale) / 2), text, scale, white);
        }
        outputs.writeWith(o.output, [&](const auto& staged) { ngi::writePng8(staged, sheetW, sheetH, 4, sheet.data()); });
        outputs.commit();
        std::printf("wrote %s: contact sheet of %u levels (%s, %s)\n", o.output.c_str(), levels,
                    context->properties.deviceName, asset.sourceName.c_str());
    }
    const auto messages = context->validationMessages();
    for (const auto& m : messages) std::fprintf(stderr, "ngi-render: %s\n", m.c_str());
    return messages.empty() ? 0 : 3;
}

} // namespace

int main(int argc, char** argv)
{
    try {
        const Options o = parse(argc, argv);
        if (o.listDevices) return listDevices();
        return run(o);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "ngi-render: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-render: error: %s\n", e.what());
        return 1;
    }
}
