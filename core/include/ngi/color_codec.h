// ngi core: the coding of a chart's colour image in the asset (chunk BCOL, format 8):
// WebP (libwebp, Debian's libwebp-dev), lossy at a quality or lossless, RGB where every
// alpha is 255 and RGBA otherwise. Google's WebP container: RIFF, VP8 / VP8L / VP8X + ALPH.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ngi {

// Codes `rgba` (size x size texels, 8-bit sRGB RGBA, row-major) as one WebP image: lossy at
// `quality` in [0, 100], lossless at 101. Deterministic (the same input gives the same bytes).
// Throws ngi::Error naming `where` if libwebp refuses (size 0 or above 16383).
std::vector<uint8_t> encodeColorImage(std::span<const uint8_t> rgba, uint32_t size, uint32_t quality,
                                      const std::string& where);

// Decodes a WebP image that must be size x size texels into 8-bit RGBA. Throws ngi::Error
// "WHERE: problem" on anything malformed or of another size (checked from the header before
// the pixels are decoded).
std::vector<uint8_t> decodeColorImage(std::span<const uint8_t> bytes, uint32_t size, const std::string& where);

}  // namespace ngi
