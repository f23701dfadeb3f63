// Frame comparison for CI: per-pixel threshold + allowed fraction of differing pixels
// (the pixelmatch / reftest "fuzzy" metric; definitions in frame_compare.h).
#include "frame_compare.h"

#include "ngi/error.h"
#include "ngi/png_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace ngi {

Rgba8Image readRgba8Png(const std::filesystem::path& path)
{
    const PngImage png = readPng(path);
    if (png.channels < 1 || png.channels > 4 || (png.bitDepth != 8 && png.bitDepth != 16))
        throw Error(path.string() + ": unsupported PNG layout (" + std::to_string(png.channels) + " channels, " +
                    std::to_string(png.bitDepth) + " bits)");
    Rgba8Image image;
    image.width = png.width;
    image.height = png.height;
    const size_t count = size_t(png.width) * png.height;
    image.pixels.resize(count * 4);
    auto to8 = [&](uint16_t v) { return uint8_t(png.bitDepth == 16 ? (uint32_t(v) * 255 + 32767) / 65535 : v); };
    const bool colour = png.channels >= 3, alpha = png.channels == 2 || png.channels == 4;
    for (size_t i = 0; i < count; ++i) {
        const uint16_t* s = &png.samples[i * png.channels];
        uint8_t* d = &image.pixels[i * 4];
        d[0] = to8(s[0]);
        d[1] = to8(colour ? s[1] : s[0]);
        d[2] = to8(colour ? s[2] : s[0]);
        d[3] = alpha ? to8(s[png.channels - 1]) : 255;
    }
    return image;
}

namespace {

uint32_t pixelDifference(const uint8_t* a, const uint8_t* b)
{
    uint32_t d = 0;
    for (int c = 0; c < 4; ++c) d = std::max<uint32_t>(d, uint32_t(std::abs(int(a[c]) - int(b[c]))));
    return d;
}

}  // namespace

FrameComparison compareFrames(const uint8_t* frame, const uint8_t* reference, uint32_t width, uint32_t height,
                              const FrameCompareOptions& options)
{
    if (options.pixelThreshold > 255) throw std::invalid_argument("pixel threshold above 255");
    if (!(options.maxDifferingFraction >= 0.0 && options.maxDifferingFraction <= 1.0))
        throw std::invalid_argument("allowed fraction of differing pixels outside [0, 1]");
    FrameComparison r;
    r.pixels = uint64_t(width) * height;
    double squares = 0.0;
    for (uint64_t i = 0; i < r.pixels; ++i) {
        const uint8_t* a = frame + i * 4;
        const uint8_t* b = reference + i * 4;
        const uint32_t d = pixelDifference(a, b);
        r.maxDifference = std::max(r.maxDifference, d);
        r.differingPixels += d > options.pixelThreshold;
        for (int c = 0; c < 4; ++c) squares += double(int(a[c]) - int(b[c])) * double(int(a[c]) - int(b[c]));
    }
    if (r.pixels) {
        r.differingFraction = double(r.differingPixels) / double(r.pixels);
        r.rmsDifference = std::sqrt(squares / double(r.pixels * 4));
    }
    r.matches = r.differingFraction <= options.maxDifferingFraction;
    return r;
}

std::vector<uint8_t> differenceImage(const uint8_t* frame, const uint8_t* reference, uint32_t width, uint32_t height,
                                     uint32_t pixelThreshold)
{
    const size_t count = size_t(width) * height;
    std::vector<uint8_t> out(count * 4);
    auto mix = [](float a, float b, float t) { return a + (b - a) * t; };
    for (size_t i = 0; i < count; ++i) {
        const uint8_t* a = frame + i * 4;
        const uint8_t* b = reference + i * 4;
        const uint32_t d = pixelDifference(a, b);
        // Context: the reference's luminance (Rec. 709), faded to a quarter of its contrast.
        const float luminance = 0.2126f * b[0] + 0.7152f * b[1] + 0.0722f * b[2];
        const float context = 255.0f - 0.25f * (255.0f - luminance);
        float rgb[3] = {context, context, context};
        if (d > pixelThreshold) {  // orange (255, 160, 0) just above the threshold -> dark red (150, 0, 0) at 255
            const float t = pixelThreshold >= 255 ? 1.0f : float(d - pixelThreshold) / float(255 - pixelThreshold);
            rgb[0] = mix(255.0f, 150.0f, t);
            rgb[1] = mix(160.0f, 0.0f, t);
            rgb[2] = 0.0f;
        } else if (d > 0) {  // tolerated: the context tinted blue (40, 90, 255), 30% at d = 1 -> 100% at the threshold
            const float t = 0.3f + 0.7f * float(d) / float(std::max(pixelThreshold, 1u));
            rgb[0] = mix(context, 40.0f, t);
            rgb[1] = mix(context, 90.0f, t);
            rgb[2] = mix(context, 255.0f, t);
        }
        for (int c = 0; c < 3; ++c) out[i * 4 + c] = uint8_t(std::lround(std::clamp(rgb[c], 0.0f, 255.0f)));
        out[i * 4 + 3] = 255;
    }
    return out;
}

std::string describe(const FrameComparison& c, const FrameCompareOptions& options)
{
    char line[256];
    std::snprintf(
        line, sizeof line,
        "%llu of %llu pixels (%.3f%%) differ by more than %u/255 (allowed %.3f%%); max difference %u/255, RMS %.2f/255",
        (unsigned long long)c.differingPixels, (unsigned long long)c.pixels, 100.0 * c.differingFraction,
        options.pixelThreshold, 100.0 * options.maxDifferingFraction, c.maxDifference, c.rmsDifference);
    return line;
}

}  // namespace ngi
