// ngi-view: the command line.
#pragma once

#include "ngi/command_line.h"

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace ngi::view {

using ngi::UsageError;

// A scripted event for unattended runs (tests, demos): at frame `frame`, open `path` as if
// it had been dropped onto the window, or resize the window.
struct ScriptedOpen {
    uint32_t frame = 0;
    std::string path;
};
struct ScriptedResize {
    uint32_t frame = 0;
    uint32_t width = 0, height = 0;
};

struct Options {
    std::string asset;
    std::string device;
    uint32_t width = 1280, height = 800;
    uint32_t samples = 0;  // 0: 4 on GPUs, 1 on CPU devices (MSAA is costly on lavapipe)
    std::string weights;   // super-resolution network (.ngiw)
    // --sr (true: required), --no-sr (false); unset: on when a network restores the asset.
    std::optional<bool> superResolution;
    std::string networks;  // --networks DIR: where the shipped networks are
    std::optional<float> lod;
    std::optional<float> maxErrorPx;     // adaptive LoD with this budget (the default mode, 1 px)
    std::vector<float> lodSequence;      // scripted: spread over --frames, the last one in the screenshot
    std::optional<float> autoLodPixels;  // start with auto LoD at N pixels per edge
    std::string mode = "shaded";
    bool validation = false;
    bool vsync = true;
    bool hidePanel = false;
    bool showHelp = false;  // start with the F1 overlay open
    bool help = false;
    uint32_t frames = 0;     // > 0: render this many frames, then exit
    std::string screenshot;  // with --frames: the last frame, written as PNG
    std::vector<ScriptedOpen> opens;
    std::vector<ScriptedResize> resizes;
};

extern const char* kUsage;

// UsageError with one message for anything malformed.
Options parseOptions(int argc, char** argv);

}  // namespace ngi::view
