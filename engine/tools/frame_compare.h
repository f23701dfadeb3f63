// ngi-render --compare: a rendered frame against a reference PNG, for CI.
//
// The metric is the one of perceptual-diff tools such as pixelmatch and Mozilla's reftest
// "fuzzy" annotations: a per-pixel threshold plus an allowed fraction of differing pixels.
// Two conformant Vulkan implementations (lavapipe and a GPU, or two GPU drivers) do not
// draw bit-identical frames: sample positions, rasterization rules at exact pixel centres
// and float rounding in shading move silhouette and edge pixels by up to a full step and
// interior pixels by a few 8-bit levels. An exact or RMS-only test either fails on every
// machine change or hides a real change in a small region; a count of pixels that moved
// by more than a threshold is robust to the first and sensitive to the second.
//
// Definitions (8-bit units, channels R, G, B, A):
//   d(p)              = max over the four channels of |frame(p) - reference(p)|
//   p differs         <=> d(p) > pixelThreshold
//   differingFraction = (pixels that differ) / (width * height)
//   the frame matches <=> differingFraction <= maxDifferingFraction
// Also reported: max d(p) and the RMS of (frame - reference) over every channel of every
// pixel, for the log; neither decides the verdict.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace ngi {

// Defaults, measured on lavapipe with assets/default.ngi (docs/frame-comparison.md):
// 16 of 255 (6%) is above shading-rounding differences between drivers (1..3 levels) and
// below a visible change of the headlight's shading; with it, rendering without MSAA (every
// edge rasterized differently) moves 0.04% of an 800x800 frame's pixels and 0.21% of a
// 256x256 one's, while a camera turned by 1 degree moves 1.2..1.3% and LoD 4 instead of 0
// 0.6..0.7%: 0.5% passes the first with a margin and fails the others.
struct FrameCompareOptions {
    uint32_t pixelThreshold = 16;         // 0..255
    double maxDifferingFraction = 0.005;  // 0..1
};

struct FrameComparison {
    uint64_t pixels = 0;             // width * height
    uint64_t differingPixels = 0;    // d(p) > pixelThreshold
    double differingFraction = 0.0;  // differingPixels / pixels
    uint32_t maxDifference = 0;      // max d(p), 0..255
    double rmsDifference = 0.0;      // over every channel, 8-bit units
    bool matches = true;             // differingFraction <= maxDifferingFraction
};

// An 8-bit RGBA image, row-major, 4 bytes a pixel.
struct Rgba8Image {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> pixels;
};

// Reads any PNG that ngi::readPng reads (gray, gray+alpha, RGB, RGBA; 8 or 16 bits) as
// RGBA8: gray is replicated to R, G, B; a missing alpha is 255; 16-bit samples are rounded
// to 8 bits (v * 255 / 65535). Throws ngi::Error "PATH: problem" on a missing, corrupt or
// truncated file.
Rgba8Image readRgba8Png(const std::filesystem::path& path);

// Compares two RGBA8 images of width x height pixels (4 * width * height bytes each) by
// the definitions above. Throws std::invalid_argument on an option outside its range.
FrameComparison compareFrames(const uint8_t* frame, const uint8_t* reference, uint32_t width, uint32_t height,
                              const FrameCompareOptions& options = {});

// The difference image of compareFrames, RGBA8, width x height: pixels with d(p) == 0 show
// the reference's luminance faded towards white (context); tolerated differences
// (0 < d <= threshold) are blue, stronger with d; differing pixels (d > threshold) go from
// orange (just above the threshold) to dark red (d = 255). So a reviewer sees where the
// frame moved, and whether by a tolerated or an intolerable amount.
std::vector<uint8_t> differenceImage(const uint8_t* frame, const uint8_t* reference, uint32_t width, uint32_t height,
                                     uint32_t pixelThreshold);

// One line for the log: "N of M pixels (F%) differ by more than T/255 (allowed A%); max
// difference X/255, RMS R/255".
std::string describe(const FrameComparison& comparison, const FrameCompareOptions& options);

}  // namespace ngi
