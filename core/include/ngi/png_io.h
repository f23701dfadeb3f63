// ngi core: PNG reading and writing through libpng (8- and 16-bit, gray/RGB/RGBA).
// Geometry images are exported as 16-bit RGB PNGs (the paper's storage format for full-
// resolution images); rendered frames as 8-bit RGBA.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace ngi {

// A PNG's samples, interleaved, row-major; bitDepth is 8 or 16. For bitDepth 8 each sample
// still occupies a uint16_t in `samples` (value 0..255) so that one type serves both.
struct PngImage {
    uint32_t width = 0, height = 0;
    uint32_t channels = 0;  // 1 gray, 2 gray+alpha, 3 RGB, 4 RGBA
    uint32_t bitDepth = 16;
    std::vector<uint16_t> samples;
};

// Writes `image` atomically (temporary file + rename). ngi::Error naming the path if the
// image is inconsistent or the file cannot be written.
void writePng(const std::filesystem::path& path, const PngImage& image);

// Writes 8-bit pixels directly (rendered frames): width*height*channels bytes.
void writePng8(const std::filesystem::path& path, uint32_t width, uint32_t height, uint32_t channels,
               const uint8_t* pixels);

// Reads any non-interlaced or interlaced PNG; palette images are expanded to RGB, bit
// depths below 8 to 8. ngi::Error naming the path on a missing, corrupt or truncated file.
PngImage readPng(const std::filesystem::path& path);

// readPng on bytes in memory (an image embedded in another file): `name` starts every
// message, e.g. "NAME: corrupt PNG (...)".
PngImage readPngFromMemory(std::span<const uint8_t> bytes, const std::string& name);

}  // namespace ngi
