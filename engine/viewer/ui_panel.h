// ngi-view: the ImGui panel (LoD, view mode, stats, asset info, open, screenshot), the F1
// help overlay and the keyboard shortcuts. Reads and edits ViewerSettings; returns what the
// user asked for this frame as UiRequests, which the app carries out.
#pragma once

#include "flat_image.h"
#include "loaded_asset.h"
#include "presenter.h"

#include "ngi/engine/adaptive_draw.h"
#include "ngi/engine/renderer.h"

#include <cstdint>
#include <string>

namespace ngi::view {

enum class ViewMode : uint32_t { Shaded = 0, Normals, Wireframe, Lod, GeometryImage, BaseColour };

// "shaded", "normals", "wireframe", "lod", "image"; ngi::Error otherwise.
ViewMode parseViewMode(const std::string& name);

struct ViewerSettings {
    bool adaptive = true;          // adaptive LoD: each tile at its own level (adaptive_draw.h)
    float maxErrorPixels = 1.0f;   // adaptive: the screen-space error budget, pixels
    float lod = 0.0f;              // continuous LoD when not automatic
    bool autoLod = false;          // pick the LoD from the projected size
    bool superResolution = false;  // draw the network's restoration instead of the bilinear one
    float pixelsPerEdge = 4.0f;    // auto LoD: target triangle edge length, pixels
    ViewMode mode = ViewMode::Shaded;
    FlatChannel flatChannel = FlatChannel::Positions;
    float wireWidth = 1.0f;
    bool vsync = true;
    bool showPanel = true;
    bool showHelp = false;
    std::string openPath;        // the path field
    std::string screenshotPath;  // empty: next to the asset
    std::string error;           // the last failure (open, screenshot), shown in red
    std::string status;          // the last success message
};

// What the panel shows about the frame that was just drawn.
struct FrameReport {
    vk::DrawStats draw;
    bool adaptiveDrawn = false;  // the frame was drawn adaptively
    vk::AdaptiveDrawStats adaptive;
    float lodDrawn = 0.0f;
    double cpuFrameMs = 0.0;   // wall clock between frames (includes waiting for vsync)
    double cpuRecordMs = 0.0;  // CPU time to build the UI and record the frame
    GpuFrameTimes gpu;
    bool gpuTimestamps = false;
    VkExtent2D extent{};
    const char* presentMode = "";
    uint32_t swapchains = 0;
    std::string device;
    bool validation = false;
    size_t validationMessages = 0;
    bool flatView = false;  // the geometry image was drawn flat (one textured quad)
    uint32_t flatLevel = 0, flatSize = 0;
    std::string superResolutionProblem;  // why the switch is disabled ("" = enabled)
    bool superResolutionActive = false;  // the restored surface was drawn
};

struct UiRequests {
    bool open = false;  // open settings.openPath
    bool screenshot = false;
    bool resetCamera = false;
    bool vsyncChanged = false;
    bool quit = false;
};

// Width of the panel in pixels (0 when hidden); the 3D view uses the rest of the window.
float panelWidth(const ViewerSettings& settings, VkExtent2D extent);

// Builds this frame's UI (between ImGuiLayer::newFrame and ImGui::Render). `loaded` may be null.
UiRequests buildUi(ViewerSettings& settings, const LoadedAsset* loaded, const FrameReport& report);

}  // namespace ngi::view
