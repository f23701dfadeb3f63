// ngi offline: decoding the textures a mesh refers to (private to ngi_mesh's readers).
// PNG through core's png_io (libpng), JPEG through libjpeg(-turbo), WebP through libwebp
// where ngi was built with it; the format is told by the bytes' signature, never the name.
#pragma once

#include "ngi/mesh/appearance.h"

#include <cstdint>
#include <span>
#include <string>

namespace ngi::mesh_io {

// The largest texture accepted, read from the image's header before anything is decoded: a
// 100000 x 100000 PNG header costs nothing to write and 40 GB to decode.
constexpr uint32_t kMaxTextureSide = 16384;
constexpr uint64_t kMaxTexturePixels = uint64_t(1) << 28;

// Decodes an image into 8-bit RGBA, top row first (grey and RGB expanded, a missing alpha is
// 255, 16-bit samples rounded to 8 bits); `imageName` becomes TextureImage::name. Throws one
// ngi::Error "<meshName>: texture <imageName>: <problem>": not a PNG, JPEG or WebP ("unsupported
// image format", naming what it looks like), a side over kMaxTextureSide or more than
// kMaxTexturePixels pixels, corrupt or truncated data (a truncated JPEG too, which libjpeg
// alone would pad with grey), out of memory.
TextureImage decodeTexture(std::span<const uint8_t> bytes, const std::string& meshName, const std::string& imageName);

}  // namespace ngi::mesh_io
