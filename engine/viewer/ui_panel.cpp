// The panel, the help overlay and the shortcuts.
#include "ui_panel.h"

#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/printable_text.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_stdlib.h>

#include <algorithm>
#include <bit>
#include <cstdarg>
#include <cstdio>

namespace ngi::view {
namespace {

constexpr float kPanelWidth = 360.0f;
constexpr float kLabelColumn = 118.0f;
const char* kModeNames[] = {
    "Shaded", "Normals", "Wireframe", "LoD colouring", "Geometry image (flat)", "Base colour (unlit)"};

std::string formatBytes(double bytes)
{
    char text[64];
    if (bytes < 1024.0)
        std::snprintf(text, sizeof(text), "%.0f B", bytes);
    else if (bytes < 1024.0 * 1024.0)
        std::snprintf(text, sizeof(text), "%.1f KiB", bytes / 1024.0);
    else
        std::snprintf(text, sizeof(text), "%.1f MiB", bytes / (1024.0 * 1024.0));
    return text;
}

std::string withThousands(uint64_t n)
{
    const std::string digits = std::to_string(n);
    std::string out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out.push_back(',');
        out.push_back(digits[i]);
    }
    return out;
}

void row(const char* label, const char* format, ...) IM_FMTARGS(2);
void row(const char* label, const char* format, ...)
{
    ImGui::TextDisabled("%s", label);
    ImGui::SameLine(kLabelColumn);
    va_list args;
    va_start(args, format);
    ImGui::TextV(format, args);
    va_end(args);
}

struct Shortcut {
    const char* keys;
    const char* action;
};
const Shortcut kShortcuts[] = {
    {"Left drag", "orbit"},
    {"Middle / right drag", "pan"},
    {"Wheel", "zoom"},
    {"R", "reset the view"},
    {"T", "adaptive LoD on/off (each tile at its own level)"},
    {"PageUp / PageDown", "LoD finer / coarser by 0.25 (uniform LoD)"},
    {"Home / End", "full resolution / coarsest level"},
    {"A", "auto LoD on/off"},
    {"S", "super-resolution on/off (needs a network)"},
    {"1 .. 6", "shaded, normals, wireframe, LoD colouring, geometry image, base colour (unlit; adaptive LoD)"},
    {"V", "vsync on/off"},
    {"F12 or P", "screenshot (PNG next to the asset, or the path in the panel)"},
    {"Tab", "show/hide the panel"},
    {"Drop a file", "open another .ngi asset"},
    {"F1", "this help"},
    {"Esc", "close the help; quit when it is closed"},
};

void handleShortcuts(ViewerSettings& s, const LoadedAsset* loaded, UiRequests& r)
{
    const ImGuiIO& io = ImGui::GetIO();
    if (io.WantCaptureKeyboard) return;
    const float maxLod = loaded ? float(loaded->surface->levelCount() - 1) : 0.0f;
    if (ImGui::IsKeyPressed(GLFW_KEY_F1, false)) s.showHelp = !s.showHelp;
    if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) {
        if (s.showHelp)
            s.showHelp = false;
        else
            r.quit = true;
    }
    if (ImGui::IsKeyPressed(GLFW_KEY_R, false)) r.resetCamera = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_F12, false) || ImGui::IsKeyPressed(GLFW_KEY_P, false)) r.screenshot = true;
    if (ImGui::IsKeyPressed(GLFW_KEY_TAB, false)) s.showPanel = !s.showPanel;
    if (ImGui::IsKeyPressed(GLFW_KEY_A, false)) s.autoLod = !s.autoLod;
    if (ImGui::IsKeyPressed(GLFW_KEY_T, false)) s.adaptive = !s.adaptive;
    if (ImGui::IsKeyPressed(GLFW_KEY_S, false)) s.superResolution = !s.superResolution;
    if (ImGui::IsKeyPressed(GLFW_KEY_V, false)) {
        s.vsync = !s.vsync;
        r.vsyncChanged = true;
    }
    for (int m = 0; m < 6; ++m)
        if (ImGui::IsKeyPressed(GLFW_KEY_1 + m, false)) s.mode = ViewMode(m);
    auto setLod = [&](float lod) {
        s.autoLod = false;
        s.adaptive = false;
        s.lod = std::clamp(lod, 0.0f, maxLod);
    };
    if (ImGui::IsKeyPressed(GLFW_KEY_PAGE_UP)) setLod(s.lod - 0.25f);
    if (ImGui::IsKeyPressed(GLFW_KEY_PAGE_DOWN)) setLod(s.lod + 0.25f);
    if (ImGui::IsKeyPressed(GLFW_KEY_HOME, false)) setLod(0.0f);
    if (ImGui::IsKeyPressed(GLFW_KEY_END, false)) setLod(maxLod);
}

void helpOverlay(ViewerSettings& s, float left)
{
    // Centred on the 3D view (right of the panel).
    const ImGuiIO& io = ImGui::GetIO();
    ImGui::SetNextWindowPos(ImVec2(left + (io.DisplaySize.x - left) * 0.5f, io.DisplaySize.y * 0.5f), ImGuiCond_Always,
                            ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowBgAlpha(0.92f);
    if (ImGui::Begin("Keyboard and mouse (F1)", &s.showHelp,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoSavedSettings)) {
        if (ImGui::BeginTable("shortcuts", 2, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV)) {
            for (const Shortcut& k : kShortcuts) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(k.keys);
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(k.action);
            }
            ImGui::EndTable();
        }
    }
    ImGui::End();
}

void lodSection(ViewerSettings& s, const LoadedAsset* loaded, const FrameReport& f)
{
    if (!ImGui::CollapsingHeader("Level of detail", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const float maxLod = loaded ? float(loaded->surface->levelCount() - 1) : 0.0f;
    ImGui::Checkbox("Adaptive (T)", &s.adaptive);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Each tile of the grid at its own level: the coarsest whose error,\nprojected, stays within the budget "
            "(near and detailed finer,\nfar and flat coarser). View mode 'lod' colours the tiles by level.");
    if (s.adaptive) {
        ImGui::SliderFloat("max error (px)", &s.maxErrorPixels, 0.1f, 32.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
        if (loaded && f.adaptiveDrawn) {
            row("tiles", "%u drawn of %u (%u culled, %u balanced)", f.adaptive.drawnTiles, f.adaptive.tiles,
                f.adaptive.culled, f.adaptive.forcedSplits);
            row("draw calls", "%u", f.adaptive.drawCalls);
        }
    }
    ImGui::BeginDisabled(s.adaptive);
    ImGui::Checkbox("Auto LoD (A)", &s.autoLod);
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip(
            "Picks the LoD from the surface's projected size so that\ntriangle edges stay about N pixels long.");
    if (s.autoLod)
        ImGui::SliderFloat("px / edge (N)", &s.pixelsPerEdge, 1.0f, 32.0f, "%.1f", ImGuiSliderFlags_Logarithmic);
    ImGui::BeginDisabled(s.autoLod || !loaded);
    float shown = s.autoLod ? f.lodDrawn : s.lod;
    if (ImGui::SliderFloat("LoD", &shown, 0.0f, maxLod, "%.2f") && !s.autoLod) s.lod = shown;
    ImGui::EndDisabled();
    ImGui::EndDisabled();
    ImGui::TextDisabled("0 = full resolution, %.0f = coarsest", maxLod);
    if (loaded && !f.adaptiveDrawn) {
        row("drawn", "level %u, morph %.2f", f.draw.level, f.draw.morph);
        row("grid", "%u x %u vertices", f.draw.gridSize, f.draw.gridSize);
    }
    // Super-resolution: compare the network's restoration with bicubic upsampling.
    const bool available = loaded && f.superResolutionProblem.empty();
    ImGui::BeginDisabled(!available);
    ImGui::Checkbox("Super-resolution (S)", &s.superResolution);
    ImGui::EndDisabled();
    if (loaded && !available) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.9f, 0.75f, 0.4f, 1.0f));
        ImGui::TextWrapped("Unavailable. %s Finer levels are restored by bicubic upsampling.",
                           f.superResolutionProblem.c_str());
        ImGui::PopStyleColor();
    } else if (loaded) {
        ImGui::TextDisabled("finer levels: %s", f.superResolutionActive ? "network restoration" : "bicubic upsampling");
    }
}

void viewSection(ViewerSettings& s, const FrameReport& f, UiRequests& r)
{
    if (!ImGui::CollapsingHeader("View", ImGuiTreeNodeFlags_DefaultOpen)) return;
    int mode = int(s.mode);
    if (ImGui::Combo("Mode (1-6)", &mode, kModeNames, IM_ARRAYSIZE(kModeNames))) s.mode = ViewMode(mode);
    if (s.mode == ViewMode::Wireframe) ImGui::SliderFloat("Line width", &s.wireWidth, 0.5f, 4.0f, "%.1f px");
    if (s.mode == ViewMode::GeometryImage) {
        int channel = int(s.flatChannel);
        ImGui::RadioButton("Positions as RGB", &channel, 0);
        ImGui::SameLine();
        ImGui::RadioButton("Normals", &channel, 1);
        s.flatChannel = FlatChannel(channel);
        ImGui::TextDisabled("level %u: %u x %u samples", f.flatLevel, f.flatSize, f.flatSize);
    }
    if (ImGui::Button("Reset view (R)")) r.resetCamera = true;
    ImGui::SameLine();
    if (ImGui::Checkbox("Vsync (V)", &s.vsync)) r.vsyncChanged = true;
}

void statsSection(const LoadedAsset* loaded, const FrameReport& f)
{
    if (!ImGui::CollapsingHeader("Stats", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (loaded && f.flatView) {
        row("drawn", "one textured quad (flat view)");
    } else if (loaded) {
        if (f.adaptiveDrawn) {
            row("triangles", "%s (adaptive)", withThousands(f.adaptive.triangles).c_str());
            row("vertices", "%s shaded", withThousands(f.adaptive.vertexInvocations).c_str());
        } else {
            row("triangles", "%s", withThousands(f.draw.triangles).c_str());
            row("vertices", "%s grid, %s shaded", withThousands(uint64_t(f.draw.gridSize) * f.draw.gridSize).c_str(),
                withThousands(f.draw.vertexInvocations).c_str());
        }
    }
    row("CPU frame", "%.2f ms (%.1f fps)", f.cpuFrameMs, f.cpuFrameMs > 0 ? 1000.0 / f.cpuFrameMs : 0.0);
    row("CPU record", "%.2f ms", f.cpuRecordMs);
    if (!f.gpuTimestamps)
        row("GPU", "no timestamps on this device");
    else if (f.gpu.valid)
        row("GPU", "%.2f ms (surface %.2f)", f.gpu.frameMs, f.gpu.sceneMs);
    if (loaded) {
        if (loaded->buildGpuMs >= 0)
            row("GPU build", "%.2f ms", loaded->buildGpuMs);
        else
            row("GPU build", "n/a (no timestamps)");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip(
                "Upload of the stored level, restoration to full resolution,\nmip chain, geomorph targets "
                "and quad diagonals (once per asset).\nOpen (read + build): %.1f ms wall clock.",
                loaded->buildCpuMs);
        if (loaded->superResolutionMs >= 0)
            row("SR time", "%.2f ms (build %.2f ms)", loaded->superResolutionMs, loaded->restoredBuildGpuMs);
        else
            row("SR time", "%s", f.superResolutionProblem.empty() ? "not run yet" : "n/a (no usable network)");
        const double surfaceBytes =
            double(loaded->surface->gpuBytes()) + (loaded->restored ? double(loaded->restored->gpuBytes()) : 0.0);
        // The adaptive draws keep their own compact levels (made on first use).
        double adaptiveBytes = 0.0;
        for (const vk::AdaptiveSurface* a : {loaded->adaptive.get(), loaded->adaptiveRestored.get()})
            if (a) adaptiveBytes += double(a->gpuBytes());
        row("GPU memory", "%s + %s adaptive", formatBytes(surfaceBytes).c_str(), formatBytes(adaptiveBytes).c_str());
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("%s drawn one LoD at a time, then the adaptive draws' compact levels,\n"
                              "base colours and tile records.",
                              loaded->restored ? "The asset's surface and the network's restore,"
                                               : "The asset's surface,");
    }
    row("swapchain", "%u x %u, %s", f.extent.width, f.extent.height, f.presentMode);
    row("device", "%s", f.device.substr(0, f.device.find(" (")).c_str());
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", f.device.c_str());
    if (f.validation) row("validation", "%zu message(s)", f.validationMessages);
}

void assetSection(const LoadedAsset* loaded)
{
    if (!ImGui::CollapsingHeader("Asset", ImGuiTreeNodeFlags_DefaultOpen)) return;
    if (!loaded) {
        ImGui::TextWrapped("No asset open. Drop a .ngi file onto the window or type its path below.");
        return;
    }
    const Asset& a = loaded->asset;
    const AssetChart& largest = a.charts.at(0);
    const uint32_t stored = largest.fullResolution >> largest.storedLevel;
    row("file", "%s", loaded->path.filename().string().c_str());
    row("source", "%s", printableText(a.sourceName).c_str());
    row("mapping", "%s", printableText(a.parameterization).c_str());
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("parameterization of the mesh onto the square");
    if (a.crossSeams.empty())
        row("charts", "%zu (one per part of the mesh)", a.charts.size());
    else
        row("charts", "%zu (parts split, %zu shared curves)", a.charts.size(), a.crossSeams.size());
    row("full", "%u x %u cells%s", largest.fullResolution, largest.fullResolution,
        a.charts.size() > 1 ? " (largest chart)" : "");
    row("stored", "%u x %u cells (level %u)", stored, stored, largest.storedLevel);
    row("CR", "%.0f  (full^2 / stored^2 over all charts)", loaded->compressionRatio());
    if (a.charts.size() > 1 && ImGui::TreeNode("Charts")) {
        for (size_t c = 0; c < a.charts.size(); ++c) {
            const AssetChart& k = a.charts[c];
            ImGui::Text("chart %zu: %u^2 cells, stored %u^2, %u levels, residual gain %.3f", c, k.fullResolution,
                        k.storedSize(), uint32_t(std::countr_zero(k.fullResolution)) + 1, double(k.residualGain));
        }
        ImGui::TreePop();
    }
    row("bytes on disk", "%s (%s)", withThousands(loaded->fileBytes).c_str(),
        formatBytes(double(loaded->fileBytes)).c_str());
    row("network", "%s", a.networkId.empty() ? "none" : a.networkId.c_str());
    // The restore's blend of the bicubic and the network (AssetChart::residualGain; 1: the network).
    if (a.charts.size() == 1) row("residual gain", "%.3f", double(a.charts[0].residualGain));
    row("weights", "%s in the file", withThousands(a.weights.size()).c_str());
    if (ImGui::TreeNode("Bake metadata (JSON)")) {
        ImGui::BeginChild("metadata", ImVec2(0, 180), true, ImGuiWindowFlags_HorizontalScrollbar);
        ImGui::TextUnformatted(loaded->metadataPretty.c_str());
        ImGui::EndChild();
        ImGui::TreePop();
    }
}

void fileSection(ViewerSettings& s, UiRequests& r)
{
    if (!ImGui::CollapsingHeader("Open / screenshot", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::SetNextItemWidth(-60.0f);
    if (ImGui::InputTextWithHint("##open", "path/to/asset.ngi", &s.openPath, ImGuiInputTextFlags_EnterReturnsTrue))
        r.open = true;
    ImGui::SameLine();
    if (ImGui::Button("Open")) r.open = true;
    ImGui::TextDisabled("or drop a file onto the window");
    ImGui::SetNextItemWidth(-60.0f);
    ImGui::InputTextWithHint("##shot", "screenshot.png (empty: next to the asset)", &s.screenshotPath);
    ImGui::SameLine();
    if (ImGui::Button("Save")) r.screenshot = true;
    if (!s.error.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.4f, 0.35f, 1.0f));
        ImGui::TextWrapped("%s", s.error.c_str());
        ImGui::PopStyleColor();
    }
    if (!s.status.empty()) ImGui::TextWrapped("%s", s.status.c_str());
}

}  // namespace

ViewMode parseViewMode(const std::string& name)
{
    if (name == "shaded") return ViewMode::Shaded;
    if (name == "normals") return ViewMode::Normals;
    if (name == "wireframe") return ViewMode::Wireframe;
    if (name == "lod") return ViewMode::Lod;
    if (name == "image") return ViewMode::GeometryImage;
    if (name == "colour" || name == "color") return ViewMode::BaseColour;
    throw Error("unknown view mode '" + name + "' (valid: shaded, normals, wireframe, lod, image, colour)");
}

float panelWidth(const ViewerSettings& settings, VkExtent2D extent)
{
    return settings.showPanel ? std::min(kPanelWidth, 0.6f * float(extent.width)) : 0.0f;
}

UiRequests buildUi(ViewerSettings& s, const LoadedAsset* loaded, const FrameReport& f)
{
    UiRequests r;
    handleShortcuts(s, loaded, r);
    const ImGuiIO& io = ImGui::GetIO();
    if (s.showPanel) {
        ImGui::SetNextWindowPos(ImVec2(0, 0), ImGuiCond_Always);
        ImGui::SetNextWindowSize(ImVec2(panelWidth(s, f.extent), io.DisplaySize.y), ImGuiCond_Always);
        ImGui::Begin("ngi-view", nullptr,
                     ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
                         ImGuiWindowFlags_NoSavedSettings);
        ImGui::PushItemWidth(-110.0f);
        lodSection(s, loaded, f);
        viewSection(s, f, r);
        fileSection(s, r);
        statsSection(loaded, f);
        assetSection(loaded);
        ImGui::PopItemWidth();
        ImGui::Separator();
        ImGui::TextDisabled("F1: keyboard and mouse help");
        ImGui::End();
    }
    if (s.showHelp) helpOverlay(s, panelWidth(s, f.extent));
    return r;
}

}  // namespace ngi::view
