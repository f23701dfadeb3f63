// ngi-view: the interactive viewer. Opens an asset in a GLFW window, draws its surface at a
// continuous LoD with the engine's Renderer (dynamic rendering) and a Dear ImGui panel on
// top (a render pass), and carries out what the panel and the shortcuts ask for.
#include "camera_input.h"
#include "flat_image.h"
#include "imgui_layer.h"
#include "loaded_asset.h"
#include "options.h"
#include "presenter.h"
#include "ui_panel.h"
#include "window.h"

#include "ngi/engine/context.h"
#include "ngi/engine/renderer.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/network_catalog.h"
#include "ngi/network_weights.h"
#include "ngi/output_files.h"
#include "ngi/png_io.h"
#include "ngi/printable_text.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

namespace ngi::view {
namespace {

constexpr glm::vec4 kBackground{0.11f, 0.12f, 0.14f, 1.0f};  // as ngi-render

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point t)
{
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// The window's VkSurfaceKHR, destroyed before the instance.
struct SurfaceHandle {
    VkInstance instance;
    VkSurfaceKHR surface;
    ~SurfaceHandle() { vkDestroySurfaceKHR(instance, surface, nullptr); }
};

std::filesystem::path nextScreenshotPath(const LoadedAsset* loaded)
{
    const std::filesystem::path dir = loaded ? loaded->path.parent_path() : std::filesystem::current_path();
    const std::string stem = loaded ? loaded->path.stem().string() : "ngi-view";
    for (int i = 1;; ++i) {
        std::filesystem::path p = dir / (stem + "-view-" + std::to_string(i) + ".png");
        if (!std::filesystem::exists(p)) return p;
    }
}

std::string windowTitle(const LoadedAsset* loaded)
{
    return loaded ? "ngi-view - " + loaded->path.filename().string() : "ngi-view";
}

int run(const Options& o)
{
    const bool scripted = o.frames > 0;
    // A scripted --screenshot is checked before the window opens (directory exists, not a
    // directory, not the asset or the weights); declaring it writes nothing.
    if (scripted && !o.screenshot.empty()) OutputFiles({o.screenshot}, {o.asset, o.weights});
    Window window(int(o.width), int(o.height), "ngi-view");
    vk::ContextOptions co;
    co.validation = o.validation;
    co.device = o.device;
    co.instanceExtensions = Window::requiredInstanceExtensions();
    co.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
    co.queueFamilyFilter = Window::presentationSupport;
    const auto context = vk::Context::create(co);
    const bool validation = !context->validationMessages().empty() || o.validation || std::getenv("NGI_VALIDATION");
    SurfaceHandle surface{context->instance, window.createSurface(context->instance)};
    const uint32_t samples = o.samples                                  ? o.samples
        : context->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU ? 1
                                                                        : 4;
    Presenter presenter(*context, surface.surface, window.framebufferSize(), o.vsync,
                        samples == 4 ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT);
    vk::Renderer renderer(*context, {presenter.colorFormat(), presenter.depthFormat(), presenter.samples()});
    FlatImageView flat(renderer);
    ImGuiLayer imgui(window.handle(), *context, presenter);
    std::unique_ptr<vk::SuperResolution> network;
    if (!o.weights.empty())
        network = std::make_unique<vk::SuperResolution>(*context, readNetworkWeights(o.weights),
                                                        vk::SuperResolutionOptions{.profile = true});

    ViewerSettings settings;
    settings.vsync = o.vsync;
    settings.showPanel = !o.hidePanel;
    settings.showHelp = o.showHelp;
    settings.mode = parseViewMode(o.mode);
    settings.superResolution = o.superResolution.value_or(false);
    // Where the shipped network an asset names is looked up (ngi/network_catalog.h).
    const std::vector<std::filesystem::path> networkDirs = networkSearchPath(o.networks);
    // SR on by default when a network restores the asset (--sr / --no-sr decide otherwise);
    // what restores it, and the charts it leaves to bicubic upsampling, are printed.
    auto chooseRestore = [&](const LoadedAsset& a) {
        const std::string problem = superResolutionProblem(a, network.get());
        if (!o.superResolution.has_value()) settings.superResolution = problem.empty();
        if (!settings.superResolution)
            std::printf("ngi-view: finer levels restored by bicubic upsampling (%s)\n",
                        problem.empty() ? "super-resolution off" : "no network restores this asset");
        if (!problem.empty()) return;
        const vk::SuperResolution* used = networkFor(a, network.get());
        if (!a.ownNetwork && network)
            if (const std::string mismatch = networkMismatch(a.asset, network->network()); !mismatch.empty())
                std::fprintf(stderr, "ngi-view: warning: %s (--weights overrides it)\n", mismatch.c_str());
        std::printf("ngi-view: super-resolution %s: network %s\n", settings.superResolution ? "on" : "available (off)",
                    used->label().c_str());
        for (size_t c = 0; c < a.asset.charts.size(); ++c)
            if (!networkRestoresChart(used->network(), a.asset.charts[c]))
                std::printf("ngi-view: chart %zu (x%u) is not restored by the x%u network: bicubic upsampling\n", c,
                            1u << a.asset.charts[c].storedLevel, used->scaleFactor());
    };
    settings.adaptive = !o.lod && !o.autoLodPixels && o.lodSequence.empty();
    if (o.maxErrorPx) settings.maxErrorPixels = *o.maxErrorPx;
    if (o.autoLodPixels) {
        settings.autoLod = true;
        settings.pixelsPerEdge = *o.autoLodPixels;
    }
    std::unique_ptr<LoadedAsset> loaded;
    uint64_t assetGeneration = 0;
    CameraController camera;
    auto frameCamera = [&] {
        const VkExtent2D e = presenter.extent();
        const float region = std::max(float(e.width) - panelWidth(settings, e), 1.0f);
        camera.frame(loaded->surface->boundsMin(), loaded->surface->boundsMax(),
                     region / float(std::max(e.height, 1u)));
    };
    auto warnSkipped = [](const LoadedAsset& a) {
        for (const std::string& file : a.skippedNetworkFiles)
            std::fprintf(stderr, "ngi-view: warning: skipped a network file that does not read: %s\n", file.c_str());
    };
    if (!o.asset.empty()) {
        loaded = loadAsset(renderer, o.asset, networkDirs);
        warnSkipped(*loaded);
        ++assetGeneration;
        const float maxLod = float(loaded->surface->levelCount() - 1);
        if (o.lod && (*o.lod < 0.0f || *o.lod > maxLod))
            throw Error("--lod " + std::to_string(*o.lod) + " is outside [0, " + std::to_string(int(maxLod)) + "]");
        settings.lod = o.lod.value_or(std::min(2.0f, maxLod));
        if (o.superResolution.value_or(false))
            if (const std::string problem = superResolutionProblem(*loaded, network.get()); !problem.empty())
                throw Error("--sr: " + problem);
        chooseRestore(*loaded);
        frameCamera();
        window.setTitle(windowTitle(loaded.get()));
        std::printf("ngi-view: opened %s (%s, %u levels) on %s; GPU build %.2f ms\n", o.asset.c_str(),
                    printableText(loaded->asset.sourceName).c_str(), loaded->surface->levelCount(),
                    context->properties.deviceName, loaded->buildGpuMs);
    }

    auto openAsset = [&](const std::string& path) {
        try {
            std::unique_ptr<LoadedAsset> next = loadAsset(renderer, path, networkDirs);
            warnSkipped(*next);
            vkDeviceWaitIdle(context->device);  // frames in flight may still draw the old surface
            loaded = std::move(next);
            ++assetGeneration;
            settings.lod = std::min(settings.lod, float(loaded->surface->levelCount() - 1));
            settings.error.clear();
            settings.status = "opened " + path;
            frameCamera();
            window.setTitle(windowTitle(loaded.get()));
            std::printf("ngi-view: opened %s\n", path.c_str());
            chooseRestore(*loaded);
        } catch (const std::exception& e) {
            settings.error = std::string("cannot open: ") + e.what() + (loaded ? " (kept the previous asset)" : "");
            settings.status.clear();
            std::fprintf(stderr, "ngi-view: %s\n", settings.error.c_str());
        }
    };

    FrameReport report;
    report.device = context->properties.deviceName;
    report.validation = validation;
    report.gpuTimestamps = presenter.timestamps();
    report.extent = presenter.extent();
    bool screenshotRequested = false;
    uint32_t frameIndex = 0;
    uint64_t adaptiveFrame = 0;  // frames drawn adaptively (residency counts them)
    double cpuFrameSum = 0.0, gpuSceneSum = 0.0;
    uint32_t timedFrames = 0, gpuTimedFrames = 0;
    Clock::time_point lastFrame = Clock::now();
    float lastPrintedLod = -1.0f;
    int exitCode = 0;

    while (!window.shouldClose()) {
        glfwPollEvents();
        VkExtent2D size = window.framebufferSize();
        if (size.width == 0 || size.height == 0) {  // minimized: wait, draw nothing
            glfwWaitEventsTimeout(0.1);
            continue;
        }
        const Clock::time_point frameStart = Clock::now();
        for (const ScriptedResize& r : o.resizes)
            if (r.frame == frameIndex) {
                window.setSize(int(r.width), int(r.height));
                glfwPollEvents();
                size = window.framebufferSize();
            }
        for (const ScriptedOpen& s : o.opens)
            if (s.frame == frameIndex) openAsset(s.path);
        if (auto dropped = window.takeDroppedFiles(); !dropped.empty()) {
            settings.openPath = dropped.back();
            openAsset(dropped.back());
        }

        imgui.newFrame();
        const ImGuiIO& io = ImGui::GetIO();
        MouseInput mouse;
        mouse.delta = {io.MouseDelta.x, io.MouseDelta.y};
        if (!std::isfinite(mouse.delta.x) || !std::isfinite(mouse.delta.y) || io.MouseDelta.x < -1e5f)
            mouse.delta = {0, 0};
        mouse.wheel = io.MouseWheel;
        for (int b = 0; b < 3; ++b) {
            mouse.down[b] = io.MouseDown[b];
            mouse.pressed[b] = ImGui::IsMouseClicked(b);
        }
        mouse.overUi = io.WantCaptureMouse;
        camera.update(mouse, float(size.height));

        const UiRequests requests = buildUi(settings, loaded.get(), report);
        float lod = settings.lod;
        if (loaded) {
            const float maxLod = float(loaded->surface->levelCount() - 1);
            if (!o.lodSequence.empty()) {
                const size_t k =
                    std::min(o.lodSequence.size() - 1, size_t(frameIndex) * o.lodSequence.size() / o.frames);
                lod = settings.lod = std::clamp(o.lodSequence[k], 0.0f, maxLod);
            } else if (settings.autoLod) {
                lod = autoLod(*loaded, camera.distance(), camera.camera().fovYDegrees, float(size.height),
                              settings.pixelsPerEdge);
            }
            lod = std::clamp(lod, 0.0f, maxLod);
        }
        ImGui::Render();

        const float panel = panelWidth(settings, size);
        report.superResolutionProblem = loaded ? superResolutionProblem(*loaded, network.get()) : "";
        if (loaded && settings.superResolution && report.superResolutionProblem.empty() && !loaded->restored) {
            try {
                buildRestored(*loaded, renderer, network.get());
                std::printf("ngi-view: super-resolution: forward pass %.2f ms, surface build %.2f ms (GPU)\n",
                            loaded->superResolutionMs, loaded->restoredBuildGpuMs);
            } catch (const std::exception& e) {
                settings.error = std::string("super-resolution failed: ") + e.what();
                std::fprintf(stderr, "ngi-view: %s\n", settings.error.c_str());
                if (scripted) exitCode = 1;
            }
        }
        if (!loaded || !report.superResolutionProblem.empty() || !loaded->restored) settings.superResolution = false;
        report.superResolutionActive = settings.superResolution;
        const vk::AssetSurface* drawn = !loaded ? nullptr
            : settings.superResolution          ? loaded->restored.get()
                                                : loaded->surface.get();
        if (loaded && settings.mode == ViewMode::GeometryImage) {
            const uint32_t level = selectLod(loaded->surface->levelCount(), loaded->surface->fullSize(), lod).level;
            flat.show(drawn->chart(0), assetGeneration * 2 + (settings.superResolution ? 1 : 0), level,
                      settings.flatChannel);
            report.flatLevel = level;
            report.flatSize = flat.size();
        }
        const bool capture = (scripted && !o.screenshot.empty() && frameIndex + 1 == o.frames) || screenshotRequested;
        if (const auto frame = presenter.begin(size)) {
            const bool drawSurface = loaded && settings.mode != ViewMode::GeometryImage;
            vk::DrawParams p;
            vk::AdaptiveSurface* adaptive = nullptr;
            if (drawSurface && settings.adaptive) {
                try {
                    adaptive = &adaptiveFor(*loaded, renderer, *drawn, Presenter::kFramesInFlight);
                } catch (const std::exception& e) {
                    settings.adaptive = false;
                    settings.error = std::string("adaptive LoD unavailable: ") + e.what();
                    std::fprintf(stderr, "ngi-view: %s\n", settings.error.c_str());
                }
            }
            report.adaptiveDrawn = adaptive != nullptr;
            if (drawSurface) {
                p.viewProjection = camera.viewProjection(frame->extent, panel);
                p.eye = camera.camera().eye();
                p.lod = lod;
                p.mode = settings.mode == ViewMode::Normals ? vk::ShadingMode::Normals
                    : settings.mode == ViewMode::Wireframe  ? vk::ShadingMode::Wireframe
                    : settings.mode == ViewMode::Lod        ? vk::ShadingMode::Lod
                    : settings.mode == ViewMode::BaseColour ? vk::ShadingMode::BaseColour
                                                            : vk::ShadingMode::Shaded;
                p.wireWidth = settings.wireWidth;
                // Before the scene pass (compute): the draw then shares vertices. Cached while
                // the LoD (its level and morph) holds, so a still slider records nothing;
                // wireframe records nothing and stays per quad.
                if (!adaptive) renderer.recordGridExpansion(frame->cmd, *drawn, p);
            }
            // The adaptive tiles, and (before the scene pass) the upload of a level 0 they draw
            // that is not resident, or the give-back of one no frame has drawn for a while.
            std::optional<TileSelection> selection;
            if (adaptive && !(loaded && settings.mode == ViewMode::GeometryImage)) {
                AdaptiveView view;
                view.camera = true;
                view.clipFromNormalized = p.viewProjection;  // the viewer's world space is normalized space
                view.eye = p.eye;
                view.viewportHeight = float(frame->extent.height);
                view.maxErrorPixels = settings.maxErrorPixels;
                selection = adaptive->select(view);
                const TileSelection* drawnNow[1] = {&*selection};
                adaptive->recordResidency(frame->cmd, drawnNow, ++adaptiveFrame);
            }
            presenter.beginScene(*frame, kBackground);
            if (loaded && settings.mode == ViewMode::GeometryImage) {
                flat.record(frame->cmd, frame->extent, panel);
                const LodSelection sel = selectLod(loaded->surface->levelCount(), loaded->surface->fullSize(), lod);
                report.draw = vk::DrawStats{sel.level, sel.morph, sel.gridSize, 2};
            } else if (adaptive) {
                adaptive->clear(frame->slot);
                report.adaptive = adaptive->recordDraw(frame->cmd, *selection, p, frame->extent);
                report.draw = vk::DrawStats{};
                report.draw.triangles = report.adaptive.triangles;
            } else if (drawSurface) {
                report.draw = drawn->recordDraw(frame->cmd, p, frame->extent);
            }
            presenter.endScene(*frame);
            presenter.beginOverlay(*frame);
            imgui.record(frame->cmd);
            presenter.endOverlay(*frame);
            report.cpuRecordMs = millisecondsSince(frameStart);
            const std::vector<uint8_t> pixels = presenter.end(*frame, capture);
            if (capture) {
                screenshotRequested = false;
                const std::filesystem::path out = scripted && !o.screenshot.empty()
                    ? std::filesystem::path(o.screenshot)
                    : !settings.screenshotPath.empty() ? std::filesystem::path(settings.screenshotPath)
                                                       : nextScreenshotPath(loaded.get());
                try {
                    if (pixels.empty()) throw Error("this swapchain cannot be read back (no transfer-source usage)");
                    // The path typed in the panel may name the open asset: refused, never overwritten.
                    OutputFiles files({out}, {o.asset, o.weights, loaded ? loaded->path : std::filesystem::path()});
                    files.writeWith(out, [&](const std::filesystem::path& staged) {
                        writePng8(staged, frame->extent.width, frame->extent.height, 4, pixels.data());
                    });
                    files.commit();
                    settings.status = "wrote " + out.string();
                    settings.error.clear();
                    std::printf("ngi-view: wrote %s (%ux%u)\n", out.string().c_str(), frame->extent.width,
                                frame->extent.height);
                } catch (const std::exception& e) {
                    settings.error = std::string("screenshot failed: ") + e.what();
                    std::fprintf(stderr, "ngi-view: %s\n", settings.error.c_str());
                    if (scripted) exitCode = 1;
                }
            }
            report.lodDrawn = lod;
            report.flatView = loaded && settings.mode == ViewMode::GeometryImage;
            report.extent = frame->extent;
            if (scripted && loaded && lod != lastPrintedLod) {
                std::printf("ngi-view: frame %u: LoD %.2f -> level %u, %ux%u grid, morph %.2f, %llu triangles%s%s\n",
                            frameIndex, lod, report.draw.level, report.draw.gridSize, report.draw.gridSize,
                            report.draw.morph, (unsigned long long)report.draw.triangles,
                            settings.superResolution ? " (super-resolution)" : "",
                            report.draw.sharedVertices ? ", shared vertices" : "");
                lastPrintedLod = lod;
            }
        }
        report.gpu = presenter.lastGpuTimes();
        report.presentMode = presenter.presentModeName();
        report.swapchains = presenter.swapchainGeneration();
        report.validationMessages = context->validationMessages().size();

        if (requests.open) openAsset(settings.openPath);
        if (requests.screenshot) screenshotRequested = true;
        if (requests.resetCamera && loaded) frameCamera();
        if (requests.vsyncChanged) presenter.setVsync(settings.vsync);
        if (requests.quit) window.requestClose();

        const double frameMs = millisecondsSince(lastFrame);
        lastFrame = Clock::now();
        report.cpuFrameMs = report.cpuFrameMs == 0.0 ? frameMs : 0.9 * report.cpuFrameMs + 0.1 * frameMs;
        if (frameIndex > 0) {  // the first frame includes pipeline warm-up
            cpuFrameSum += frameMs;
            ++timedFrames;
            if (report.gpu.valid) {
                gpuSceneSum += report.gpu.sceneMs;
                ++gpuTimedFrames;
            }
        }
        ++frameIndex;
        if (scripted && frameIndex >= o.frames) break;
    }
    vkDeviceWaitIdle(context->device);

    if (scripted) {
        std::printf("ngi-view: %u frames at %ux%u, %u swapchain(s); mean CPU frame %.2f ms", frameIndex,
                    report.extent.width, report.extent.height, presenter.swapchainGeneration(),
                    timedFrames ? cpuFrameSum / timedFrames : 0.0);
        if (gpuTimedFrames) std::printf(", mean GPU surface pass %.2f ms", gpuSceneSum / gpuTimedFrames);
        std::printf(" (%s)\n", context->properties.deviceName);
        std::printf("ngi-view: panel at x 0..%.0f\n", panelWidth(settings, report.extent));
    }
    const auto messages = context->validationMessages();
    for (const auto& m : messages) std::fprintf(stderr, "ngi-view: %s\n", m.c_str());
    if (!messages.empty()) return 3;
    return exitCode;
}

}  // namespace
}  // namespace ngi::view

int main(int argc, char** argv)
{
    using namespace ngi::view;
    try {
        const Options o = parseOptions(argc, argv);
        if (o.help) {
            std::cout << kUsage;
            return 0;
        }
        return run(o);
    } catch (const UsageError& e) {
        std::fprintf(stderr, "ngi-view: %s\n%s", e.what(), kUsage);
        return 2;
    } catch (const NoDisplayError& e) {
        std::fprintf(
            stderr,
            "ngi-view: %s.\nngi-view needs a display (X11 or Wayland); run it under Xvfb (xvfb-run ngi-view ...), "
            "or use ngi-render for headless capture: ngi-render ASSET -o OUT.png [--lod F]\n",
            e.what());
        return 4;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-view: error: %s\n", e.what());
        return 1;
    }
}
