// ngi-render: headless capture of a geometry-image asset at any level of detail to PNG.
// A thin client of the engine library: read asset -> build the GPU mip chain -> draw ->
// read back -> write PNG, and with --compare check it against a reference (frame_compare.h).
#include "frame_compare.h"
#include "label_font.h"

#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/context.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/pipeline_cache.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/printable_text.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/network_catalog.h"
#include "ngi/network_weights.h"
#include "ngi/output_files.h"
#include "ngi/png_io.h"
#include "ngi/stopwatch.h"

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>

namespace {

const char* kUsage =
    "usage: ngi-render ASSET -o OUT.png [--lod F | --grid N | --max-error-px P] [--size WxH] [--yaw DEG] [--pitch "
    "DEG]\n"
    "                  [--look-at X,Y,Z] [--eye X,Y,Z | --distance D | --zoom F] [--fov DEG]\n"
    "                  [--mode shaded|normals|wireframe|lod|colour] [--contact-sheet] [--samples 1|4]\n"
    "                  [--background R,G,B] [--sr [--weights NET.ngiw] [--networks DIR] | --bicubic | --no-sr] "
    "[--device NAME|INDEX]\n"
    "                  [--validation] [--compare REF.png [--max-diff F] [--pixel-threshold T] [--diff DIFF.png]]\n"
    "       ngi-render --list-devices\n"
    "Renders ASSET headless (no window) to a PNG. --lod is continuous (0 = full resolution);\n"
    "--grid draws a fixed N x N vertex grid; --contact-sheet draws every mip level side by side.\n"
    "--max-error-px P draws adaptively: each 4x4-quad tile of each chart at the coarsest level\n"
    "whose error bound, projected, is within P pixels (near and detailed tiles finer, far and\n"
    "flat ones coarser; crack-free; tiles outside the view or facing away culled); --mode lod\n"
    "then colours every tile by its level, --mode colour shows the base colour unlit. An asset\n"
    "with base colours (ngi-bake of a textured or coloured mesh) is drawn so by default, within\n"
    "1 px (the uniform draws --lod, --grid and --contact-sheet show its colours too).\n"
    "--sr restores the full resolution with the super-resolution network: --weights, else the\n"
    "asset's own weights, else the shipped network the asset names (in --networks DIR, else\n"
    "$NGI_NETWORK_DIR, else the assets/ beside the executable); charts of another factor are\n"
    "restored bicubically (said on stdout). --bicubic restores level 0 by Catmull-Rom from the\n"
    "stored level (ngi-eval's --bicubic), --no-sr upsamples it bilinearly. Default (none of the\n"
    "three): --sr when the asset carries weights or the network it names is found and restores\n"
    "it, else (said on stderr when it names one) --bicubic.\n"
    "Camera (points and distances in object space: the coordinates of the mesh the asset was\n"
    "baked from, as ngi-eval mesh writes them): it looks at --look-at (default: the centre of\n"
    "the bounding box) from --yaw/--pitch degrees (default 30, 30) at the distance that frames\n"
    "the whole asset, divided by --zoom, or at --distance; or from the point --eye. --fov is the\n"
    "vertical field of view (default 35, 1..170) and changes the lens, not the camera position.\n"
    "--background is the clear colour, components 0..1 (default 0.11,0.12,0.14).\n"
    "--compare: exit 0 if the frame matches REF.png, 4 if it differs, 1 on a bad reference: it\n"
    "differs when more than --max-diff (default 0.005) of its pixels differ from REF.png by more\n"
    "than --pixel-threshold (default 16 of 255) in some channel; --diff writes a difference image\n"
    "(differing pixels orange to dark red, tolerated ones blue). Exit 3: validation messages.\n";

using ngi::UsageError;

constexpr glm::vec3 kDefaultBackground{0.11f, 0.12f, 0.14f};
constexpr float kDefaultFov = 35.0f;  // OrbitCamera's: the default framing stays as it was

// The exit code of a frame that differs from --compare's reference (0 matches, 1 error,
// 2 usage, 3 validation messages).
constexpr int kExitDiffers = 4;

struct Options {
    std::string asset, output, mode = "shaded", device, weights, networks;
    std::optional<float> lod;
    std::optional<uint32_t> grid;
    std::optional<float> maxErrorPx;  // adaptive LoD
    uint32_t width = 800, height = 800, samples = 4;
    float yaw = 30.0f, pitch = 30.0f;
    bool anglesGiven = false;
    // Camera, object space (see kUsage).
    std::optional<glm::vec3> lookAt, eye;
    std::optional<float> distance, zoom;
    float fov = kDefaultFov;
    glm::vec3 background = kDefaultBackground;
    // Frame comparison.
    std::string compare, diff;
    ngi::FrameCompareOptions compareOptions;
    bool compareOptionGiven = false;
    bool contactSheet = false, listDevices = false, validation = false;
    std::optional<bool> superResolution;  // nullopt: the asset's network when one is found
    bool bicubic = false;                 // --bicubic (superResolution false)
};

constexpr auto parseFloat = ngi::parseFloatOption;
constexpr auto parseVec3 = ngi::parseVec3Option;

Options parse(int argc, char** argv)
{
    Options o;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        const std::string& a = args.flag();
        if (args.is("-o", "--output"))
            o.output = ngi::parseOutputPathOption(a, args.value());
        else if (args.is("--lod"))
            o.lod = parseFloat(a, args.value());
        else if (args.is("--grid"))
            o.grid = ngi::parseUintOption(a, args.value());
        else if (args.is("--max-error-px"))
            o.maxErrorPx = ngi::parseFloatOptionInRange(a, args.value(), 1e-3, 1e4, "pixels");
        else if (args.is("--size"))
            std::tie(o.width, o.height) = ngi::parseSizeOption(a, args.value());
        else if (args.is("--yaw"))
            o.yaw = parseFloat(a, args.value()), o.anglesGiven = true;
        else if (args.is("--pitch"))
            o.pitch = parseFloat(a, args.value()), o.anglesGiven = true;
        else if (args.is("--look-at"))
            o.lookAt = parseVec3(a, args.value());
        else if (args.is("--eye"))
            o.eye = parseVec3(a, args.value());
        else if (args.is("--distance"))
            o.distance = parseFloat(a, args.value());
        else if (args.is("--zoom"))
            o.zoom = parseFloat(a, args.value());
        else if (args.is("--fov"))
            o.fov = parseFloat(a, args.value());
        else if (args.is("--background"))
            o.background = parseVec3(a, args.value());
        else if (args.is("--compare"))
            o.compare = args.value();
        else if (args.is("--diff"))
            o.diff = ngi::parseOutputPathOption(a, args.value()), o.compareOptionGiven = true;
        else if (args.is("--max-diff")) {
            const float f = parseFloat(a, args.value());
            if (f < 0.0f || f > 1.0f)
                throw UsageError("--max-diff is a fraction of the pixels in [0, 1], got " + std::to_string(f));
            o.compareOptions.maxDifferingFraction = f;
            o.compareOptionGiven = true;
        } else if (args.is("--pixel-threshold")) {
            o.compareOptions.pixelThreshold = ngi::parseUintOption(a, args.value());
            if (o.compareOptions.pixelThreshold > 255) throw UsageError("--pixel-threshold is at most 255");
            o.compareOptionGiven = true;
        } else if (args.is("--mode"))
            o.mode = args.value();
        else if (args.is("--samples"))
            o.samples = ngi::parseUintOption(a, args.value());
        else if (args.is("--device"))
            o.device = args.value();
        else if (args.is("--contact-sheet"))
            o.contactSheet = true;
        else if (args.is("--sr"))
            o.superResolution = true, o.bicubic = false;
        else if (args.is("--no-sr"))
            o.superResolution = false, o.bicubic = false;
        else if (args.is("--bicubic"))
            o.superResolution = false, o.bicubic = true;
        else if (args.is("--weights"))
            o.weights = args.value();
        else if (args.is("--networks"))
            o.networks = args.value();
        else if (args.is("--list-devices"))
            o.listDevices = true;
        else if (args.is("--validation"))
            o.validation = true;
        else if (args.is("-h", "--help")) {
            std::cout << kUsage;
            std::exit(0);
        } else if (args.positional() && o.asset.empty())
            o.asset = a;
        else
            throw args.unknown();
    }
    if (o.listDevices) return o;
    if (o.asset.empty()) throw UsageError("no ASSET given");
    if (o.output.empty()) throw UsageError("no output given (-o OUT.png)");
    if (int(bool(o.lod)) + int(bool(o.grid)) + int(bool(o.maxErrorPx)) > 1)
        throw UsageError("--lod, --grid and --max-error-px are exclusive");
    if (o.maxErrorPx && o.contactSheet) throw UsageError("--max-error-px and --contact-sheet are exclusive");
    if (o.samples != 1 && o.samples != 4) throw UsageError("--samples must be 1 or 4");
    if (!o.weights.empty() && o.superResolution != true) throw UsageError("--weights needs --sr");
    if (!o.networks.empty() && o.superResolution == false)
        throw UsageError(std::string("--networks does not apply with ") + (o.bicubic ? "--bicubic" : "--no-sr"));
    if (o.compareOptionGiven && o.compare.empty())
        throw UsageError("--diff, --max-diff and --pixel-threshold need --compare REF.png");
    if (o.eye && (o.anglesGiven || o.distance || o.zoom))
        throw UsageError("--eye places the camera: --yaw, --pitch, --distance and --zoom do not apply with it");
    if (o.distance && o.zoom) throw UsageError("--distance and --zoom are exclusive");
    if (o.distance && !(*o.distance > 0.0f)) throw UsageError("--distance must be positive");
    if (o.zoom && !(*o.zoom > 0.0f)) throw UsageError("--zoom must be positive");
    if (!(o.fov >= 1.0f && o.fov <= 170.0f)) throw UsageError("--fov must be in [1, 170] degrees");
    for (int k = 0; k < 3; ++k)
        if (o.background[k] < 0.0f || o.background[k] > 1.0f)
            throw UsageError("--background components must be in [0, 1]");
    if (o.eye && o.lookAt && glm::length(*o.eye - *o.lookAt) <= 1e-6f * std::max(1.0f, glm::length(*o.lookAt)))
        throw UsageError("--eye and --look-at are the same point: the camera has no direction");
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

// The run's camera in the renderer's world space (the asset's normalized space, where the
// surface is drawn without a world matrix), from the options given in object space. Without
// any camera option it is frameBounds' framing, unchanged, so that existing reference frames
// stay valid. Throws UsageError if the camera has no direction (--eye at the default target).
ngi::vk::OrbitCamera placeCamera(const Options& o, const ngi::Asset& asset, glm::vec3 boundsMin, glm::vec3 boundsMax,
                                 float aspect)
{
    constexpr float kMinDistance = 1e-4f;  // normalized units: a tenth of a sample of a 1025^2 image
    const float unit = asset.scale.x;      // object units per normalized unit (the asset's scale is uniform)
    auto toNormalized = [&](glm::vec3 p) { return (p - asset.offset) / asset.scale; };
    ngi::vk::OrbitCamera camera = ngi::vk::frameBounds(boundsMin, boundsMax, o.yaw, o.pitch, aspect);
    camera.fovYDegrees = o.fov;
    if (!o.lookAt && !o.eye && !o.distance && !o.zoom) return camera;
    if (o.lookAt) camera.target = toNormalized(*o.lookAt);
    if (o.eye) {
        const glm::vec3 toEye = toNormalized(*o.eye) - camera.target;
        camera.distance = glm::length(toEye);
        if (!(camera.distance >= kMinDistance))
            throw UsageError(std::string("--eye is the camera's target") +
                             (o.lookAt ? "" : " (the centre of the bounding box)") +
                             ": it must be at least 1e-4 of the asset's size away from it");
        camera.yawDegrees = glm::degrees(std::atan2(toEye.x, toEye.z));
        camera.pitchDegrees = glm::degrees(std::asin(std::clamp(toEye.y / camera.distance, -1.0f, 1.0f)));
    } else if (o.distance) {
        camera.distance = *o.distance / unit;
    } else if (o.zoom) {
        camera.distance /= *o.zoom;  // frameBounds' distance: the whole asset fits the view
    }
    if (!(camera.distance >= kMinDistance))
        throw UsageError(std::string(o.distance ? "--distance" : "--zoom") +
                         " puts the camera closer to its target than 1e-4 of the asset's size");
    // Depth range: everything of the asset (its bounding sphere) lies between the planes; the
    // near plane stays at a small fraction of the target distance when the eye is inside it.
    const glm::vec3 centre = 0.5f * (boundsMin + boundsMax);
    const float radius = 0.5f * glm::length(boundsMax - boundsMin) * 1.01f;
    const float eyeToCentre = glm::length(camera.eye() - centre);
    camera.farPlane = std::max(eyeToCentre + radius, 1.01f * camera.distance);
    camera.nearPlane = std::max(eyeToCentre - radius, 1e-3f * camera.distance);
    return camera;
}

int run(Options o)
{
    // Checked before any work: the PNG's directory exists and -o is neither an input (the
    // asset, the weights) nor a directory. The PNG replaces -o only once it is complete.
    // The reference is an input too: it can never be -o or --diff.
    ngi::OutputFiles outputs({o.output, o.diff}, {o.asset, o.weights, o.compare});
    const ngi::Asset asset = ngi::readAsset(o.asset);
    // An asset with base colours (textured content), given no level, is drawn adaptively
    // within 1 px: what a viewer of such content expects, at its triangles' cost.
    const bool coloured = asset.hasBaseColors();
    if (coloured && !o.lod && !o.grid && !o.maxErrorPx && !o.contactSheet) o.maxErrorPx = 1.0f;
    // The reference is read (and, for a single frame, its size checked) before any GPU work.
    std::optional<ngi::Rgba8Image> reference;
    auto checkReferenceSize = [&](uint32_t width, uint32_t height) {
        if (reference->width != width || reference->height != height)
            throw ngi::Error(o.compare + ": the reference is " + std::to_string(reference->width) + "x" +
                             std::to_string(reference->height) + " pixels, the frame " + std::to_string(width) + "x" +
                             std::to_string(height) + " (render the reference with the same --size and layout)");
    };
    if (!o.compare.empty()) {
        reference = ngi::readRgba8Png(o.compare);
        if (!o.contactSheet) checkReferenceSize(o.width, o.height);
    }
    const glm::vec4 background(o.background, 1.0f);
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
    // --sr's network; by default the surface finds the asset's own (RestoreOptions).
    std::unique_ptr<ngi::vk::SuperResolution> network;
    // The network's pipelines go through a cache kept on disk (pipeline_cache.h): drivers that
    // compile at pipeline creation start fast the second time.
    std::unique_ptr<ngi::vk::PipelineCacheFile> pipelineCache;
    // Network files that do not read are skipped (the asset's own network may be beside them);
    // each is said once.
    std::set<std::string> warned;
    auto warnSkipped = [&](const std::vector<std::string>& skipped) {
        for (const std::string& file : skipped)
            if (warned.insert(file).second)
                std::fprintf(stderr, "ngi-render: warning: skipped a network file that does not read: %s\n",
                             file.c_str());
    };
    // The library's default restore (the network the asset carries or names when it is found
    // and restores a chart, else bicubic) unless --sr or --no-sr / --bicubic decide.
    ngi::vk::RestoreOptions restore;
    if (o.superResolution == false) {
        restore.findNetwork = false;
        restore.withoutNetwork = o.bicubic ? ngi::vk::Upsampling::bicubic : ngi::vk::Upsampling::bilinear;
    } else {
        pipelineCache =
            std::make_unique<ngi::vk::PipelineCacheFile>(*context, ngi::vk::defaultPipelineCachePath(*context));
        restore.networkDir = o.networks;
        restore.networkOptions.pipelineCache = pipelineCache->handle();
    }
    if (o.superResolution == true) {
        // --weights (its own errors name it), else the asset's WGHT chunk, else the shipped
        // network the asset names (ngi/network_catalog.h).
        std::vector<std::string> skipped;
        std::string mismatch;
        ngi::NetworkWeights weights =
            o.weights.empty() ? ngi::NetworkWeights{} : ngi::networkForRestore(asset, o.weights, {}, mismatch, skipped);
        if (!mismatch.empty())
            std::fprintf(stderr, "ngi-render: warning: %s: %s (--weights overrides it)\n", o.asset.c_str(),
                         mismatch.c_str());
        network = forAsset([&] {
            if (o.weights.empty()) {
                weights = ngi::networkForRestore(asset, "", ngi::networkSearchPath(o.networks), mismatch, skipped);
                warnSkipped(skipped);
            }
            // One network per asset: it restores the charts of its factor, the others are
            // restored bicubically (AssetSurface::build); a network that restores none is an error.
            bool restoresAny = false;
            for (const ngi::AssetChart& chart : asset.charts) restoresAny |= ngi::networkRestoresChart(weights, chart);
            for (size_t c = 0; c < asset.charts.size() && !restoresAny; ++c) {
                const ngi::AssetChart& chart = asset.charts[c];
                const std::string which =
                    asset.charts.size() == 1 ? "this asset's" : "chart " + std::to_string(c) + "'s";
                if (chart.storedLevel == 0 || chart.storedLevel > 16 || weights.scaleFactor != 1u << chart.storedLevel)
                    throw ngi::Error(
                        "the x" + std::to_string(weights.scaleFactor) + " network " + ngi::networkLabel(weights) +
                        " restores " + std::to_string(chart.storedSize()) + " samples per side to " +
                        std::to_string((chart.storedSize() - 1) * weights.scaleFactor + 1) + ", but " + which +
                        " full resolution is " + std::to_string(chart.fullSize()) +
                        (chart.storedLevel ? " (it needs a x" + std::to_string(1u << chart.storedLevel) + " network)"
                                           : " (it stores its full resolution: nothing to restore)"));
            }
            return std::make_unique<ngi::vk::SuperResolution>(*context, weights, restore.networkOptions);
        });
        restore.network = network.get();
    }
    // Every chart; weights that overflow restore NaN positions: the build's error names the
    // network (SuperResolution::checkRestores), never a blank image.
    bool restoredWithNetwork = false;
    auto surfacePointer = forAsset([&] {
        // The adaptive draw reads the levels alone: no geomorph targets, no quad diagonals.
        auto built = std::make_unique<ngi::vk::AssetSurface>(renderer, asset, restore,
                                                             o.maxErrorPx ? ngi::vk::SurfaceDraws::adaptiveOnly
                                                                          : ngi::vk::SurfaceDraws::uniformAndAdaptive);
        warnSkipped(built->skippedNetworkFiles());
        const ngi::vk::SuperResolution* used = built->restoreNetwork();
        if (!used && !o.superResolution && !asset.networkId.empty())
            std::fprintf(stderr,
                         "ngi-render: warning: %s: %s: restoring without it (bicubic; --sr makes this an error)\n",
                         o.asset.c_str(), built->restoreProblem().c_str());
        if (used) {
            restoredWithNetwork = true;
            std::printf("super-resolution: network %s (x%u)\n", used->label().c_str(), used->scaleFactor());
            for (size_t c = 0; c < asset.charts.size(); ++c)
                if (!built->restoredByNetwork(c))
                    std::printf(
                        "super-resolution: chart %zu (x%u) is not restored by the x%u network: bicubic upsampling\n", c,
                        1u << asset.charts[c].storedLevel, used->scaleFactor());
        }
        built->build();
        return built;
    });
    if (restoredWithNetwork) {
        try {
            pipelineCache->save();
        } catch (const ngi::Error& e) {
            std::fprintf(stderr, "ngi-render: warning: %s (the pipeline cache is not kept)\n", e.what());
        }
    }
    const ngi::vk::AssetSurface& surface = *surfacePointer;
    if (network) network->releaseTensors();
    if (o.grid && (*o.grid < 2 || *o.grid > surface.fullSize()))
        throw ngi::Error("--grid " + std::to_string(*o.grid) + " is outside [2, " + std::to_string(surface.fullSize()) +
                         "]");
    const float maxLod = float(surface.levelCount() - 1);
    if (o.lod && (*o.lod < 0.0f || *o.lod > maxLod))
        throw ngi::Error("--lod " + std::to_string(*o.lod) + " is outside [0, " + std::to_string(int(maxLod)) + "]");

    ngi::vk::OffscreenTarget target(renderer, o.width, o.height);
    const float aspect = float(o.width) / float(o.height);
    const ngi::vk::OrbitCamera camera = placeCamera(o, asset, surface.boundsMin(), surface.boundsMax(), aspect);
    {
        const glm::vec3 eye = asset.offset + asset.scale * camera.eye(),
                        at = asset.offset + asset.scale * camera.target;
        std::printf("camera (object space): eye %g,%g,%g look-at %g,%g,%g distance %g fov %g\n", eye.x, eye.y, eye.z,
                    at.x, at.y, at.z, camera.distance * asset.scale.x, camera.fovYDegrees);
    }

    uint32_t sharedCharts = 0;  // charts the last frame drew with shared vertices (expanded for it)
    auto renderAt = [&](std::optional<float> lod, std::optional<uint32_t> grid, ngi::vk::DrawStats& stats) {
        ngi::vk::DrawParams p;
        p.viewProjection = camera.viewProjection(aspect);
        p.eye = camera.eye();
        p.lod = lod.value_or(0.0f);
        p.gridSize = grid.value_or(0);
        p.mode = mode;
        p.wireWidth = 1.0f;
        // The grid expansion before the pass (compute) lets the draw share vertices: the same
        // pixels as the per-quad way, fewer vertex invocations; it records nothing where the
        // draw stays per quad (wireframe, --grid off the level sizes).
        return target.render(
            [&](VkCommandBuffer cmd) { stats = surface.recordDraw(cmd, p, target.extent()); }, background,
            [&](VkCommandBuffer cmd) { sharedCharts = renderer.recordGridExpansion(cmd, surface, p); });
    };
    // --compare: the frame against the reference; --diff written whatever the verdict.
    bool differs = false;
    auto compareWithReference = [&](const std::vector<uint8_t>& frame, uint32_t width, uint32_t height) {
        if (!reference) return;
        checkReferenceSize(width, height);
        const ngi::FrameComparison c =
            ngi::compareFrames(frame.data(), reference->pixels.data(), width, height, o.compareOptions);
        if (!o.diff.empty()) {
            const std::vector<uint8_t> image = ngi::differenceImage(frame.data(), reference->pixels.data(), width,
                                                                    height, o.compareOptions.pixelThreshold);
            outputs.writeWith(o.diff,
                              [&](const auto& staged) { ngi::writePng8(staged, width, height, 4, image.data()); });
        }
        differs = !c.matches;
        std::printf("compare %s: %s: %s\n", o.compare.c_str(), ngi::describe(c, o.compareOptions).c_str(),
                    c.matches ? "matches" : "DIFFERS");
    };

    // Labels in a light grey, or a dark one on a bright --background.
    const bool brightBackground = glm::dot(o.background, glm::vec3(0.2126f, 0.7152f, 0.0722f)) > 0.5f;
    const uint8_t labelColour[3] = {uint8_t(brightBackground ? 30 : 235), uint8_t(brightBackground ? 30 : 235),
                                    uint8_t(brightBackground ? 30 : 235)};
    if (o.maxErrorPx) {
        const ngi::StopwatchClock::time_point prepareStart = ngi::StopwatchClock::now();
        ngi::vk::AdaptiveSurface adaptive(renderer, surface, asset);
        const double prepareSeconds = ngi::secondsSince(prepareStart);
        ngi::AdaptiveView view;
        view.camera = true;
        view.clipFromNormalized = camera.viewProjection(aspect);  // world space is normalized space here
        view.eye = camera.eye();
        view.viewportHeight = float(o.height);
        view.maxErrorPixels = *o.maxErrorPx;
        const ngi::StopwatchClock::time_point selectStart = ngi::StopwatchClock::now();
        const ngi::TileSelection selection = adaptive.select(view);
        const double selectSeconds = ngi::secondsSince(selectStart);
        ngi::vk::DrawParams p;
        p.viewProjection = view.clipFromNormalized;
        p.eye = view.eye;
        p.mode = mode;
        ngi::vk::AdaptiveDrawStats stats;
        std::vector<uint8_t> pixels = target.render(
            [&](VkCommandBuffer cmd) { stats = adaptive.recordDraw(cmd, selection, p, target.extent()); }, background);
        compareWithReference(pixels, o.width, o.height);
        outputs.writeWith(o.output,
                          [&](const auto& staged) { ngi::writePng8(staged, o.width, o.height, 4, pixels.data()); });
        outputs.commit();
        std::printf("wrote %s: adaptive within %g px, %u tiles (%u drawn, %u culled, %u forced splits), %llu triangles "
                    "in %u draws; tile bounds %.0f ms (read back + CPU), selection %.2f ms CPU (%s, %s)\n",
                    o.output.c_str(), double(*o.maxErrorPx), stats.tiles, stats.drawnTiles, stats.culled,
                    stats.forcedSplits, (unsigned long long)stats.triangles, stats.drawCalls, 1e3 * prepareSeconds,
                    1e3 * selectSeconds, context->properties.deviceName, asset.sourceName.c_str());
    } else if (!o.contactSheet) {
        ngi::vk::DrawStats stats;
        std::vector<uint8_t> pixels = renderAt(o.lod, o.grid, stats);
        compareWithReference(pixels, o.width, o.height);
        outputs.writeWith(o.output,
                          [&](const auto& staged) { ngi::writePng8(staged, o.width, o.height, 4, pixels.data()); });
        outputs.commit();
        std::printf("wrote %s: level %u, %ux%u grid, morph %.2f, %llu triangles, shared vertices in %u of %zu charts, "
                    "%s restore (%s, %s)\n",
                    o.output.c_str(), stats.level, stats.gridSize, stats.gridSize, stats.morph,
                    (unsigned long long)stats.triangles, sharedCharts, surface.chartCount(),
                    restoredWithNetwork                                                      ? "super-resolution"
                        : surface.upsamplingWithoutNetwork() == ngi::vk::Upsampling::bicubic ? "bicubic"
                                                                                             : "bilinear",
                    context->properties.deviceName, ngi::printableText(asset.sourceName).c_str());
    } else {
        const uint32_t levels = surface.levelCount();
        const uint32_t columns = std::min<uint32_t>(levels, 4), rows = (levels + columns - 1) / columns;
        const uint32_t labelHeight = 40, tileW = o.width, tileH = o.height + labelHeight;
        const uint32_t sheetW = tileW * columns, sheetH = tileH * rows;
        std::vector<uint8_t> sheet(size_t(sheetW) * sheetH * 4);
        for (size_t i = 0; i < sheet.size(); i += 4) {
            sheet[i] = uint8_t(background.r * 255);
            sheet[i + 1] = uint8_t(background.g * 255);
            sheet[i + 2] = uint8_t(background.b * 255);
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
                std::memcpy(&sheet[((size_t(oy) + y) * sheetW + ox) * 4], &tile[size_t(y) * o.width * 4],
                            size_t(o.width) * 4);
            const std::string text = label(l);
            ngi::drawLabel(sheet, sheetW, sheetH, int(ox) + (int(tileW) - ngi::labelWidth(text, scale)) / 2,
                           int(oy + o.height + (labelHeight - 7 * scale) / 2), text, scale, labelColour);
        }
        compareWithReference(sheet, sheetW, sheetH);
        outputs.writeWith(o.output,
                          [&](const auto& staged) { ngi::writePng8(staged, sheetW, sheetH, 4, sheet.data()); });
        outputs.commit();
        std::printf("wrote %s: contact sheet of %u levels (%s, %s)\n", o.output.c_str(), levels,
                    context->properties.deviceName, ngi::printableText(asset.sourceName).c_str());
    }
    const auto messages = context->validationMessages();
    for (const auto& m : messages) std::fprintf(stderr, "ngi-render: %s\n", m.c_str());
    return !messages.empty() ? 3 : differs ? kExitDiffers : 0;
}

}  // namespace

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
