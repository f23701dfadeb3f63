// ngi core: the .ngi asset file (DESIGN.md, "The asset contract").
//
// One file per asset, little-endian:
//   magic "\x89NGI\r\n\x1a\n" (8 bytes: catches text-mode mangling like PNG's signature)
//   u32 formatVersion, u32 chunkCount, u32 tableCrc32, u32 reserved (0)
//   chunkCount table entries of 32 bytes:
//     u32 fourcc, u32 encoding (0 raw, 1 zlib of parallelogram-predicted 16-bit samples),
//     u64 offset, u64 storedBytes, u32 crc32 (of the stored bytes), u32 reserved (0)
//   chunk payloads, each starting on an 8-byte boundary.
// Chunks: HEAD (fixed fields + strings), META (free-form JSON text: bake report, seam),
// POSI (stored position level, u16 RGB normalized to [0,1]), NORM (stored normal level,
// u16 RGB = (n + 1) / 2), WGHT (optional per-asset network weights).
//
// Format version history: 1 = this layout.
#pragma once

#include "ngi/geometry_image.h"
#include "ngi/output_files.h"  // writeFileAtomic, used with the readers below by every tool

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace ngi {

inline constexpr uint32_t kAssetFormatVersion = 1;

// A geometry-image asset: the stored low-resolution mip level plus what is needed to
// restore and de-normalize it. Positions and normals are kept exactly as stored on disk
// (16-bit unsigned, RGB interleaved, row-major) so that a write after a read is lossless.
struct Asset {
    std::string sourceName;        // source mesh file name, or "analytic:NAME"
    uint64_t sourceHash = 0;       // FNV-1a 64 of the source file's bytes (0 = analytic)
    glm::vec3 offset{0.0f};        // object-space position = offset + scale * normalized
    glm::vec3 scale{1.0f};         //   (uniform scale: the bbox's longest side maps to [0,1])
    uint32_t fullResolution = 1024;  // cells per side of the full image (power of two)
    uint32_t storedLevel = 3;        // mip level kept; stored samples = (full >> level) + 1
    std::string parameterization;    // "ot", "ricci", "harmonic", "tutte", "authalic", "analytic"
    std::string networkId;           // super-resolution network expected ("" = none)
    uint64_t networkHash = 0;
    std::string metadataJson;        // free-form JSON: bake report, seam description
    std::vector<uint16_t> positions; // storedSize^2 * 3
    std::vector<uint16_t> normals;   // storedSize^2 * 3
    std::vector<uint8_t> weights;    // optional per-asset weights (counted in the bytes)

    uint32_t storedSize() const { return (fullResolution >> storedLevel) + 1; }
    uint32_t fullSize() const { return fullResolution + 1; }
};

// Quantizes a geometry image into the asset's stored level. `positions` must already be
// normalized to [0,1]^3 (values are clamped); `normals` are unit vectors. Both must have
// asset.storedSize() samples per side, else ngi::Error.
void storeGeometryImage(Asset& asset, const GeometryImage& positions, const GeometryImage& normals);

// The stored level as floats: positions in [0,1]^3 (normalized), normals unit length.
GeometryImage storedPositions(const Asset& asset);
GeometryImage storedNormals(const Asset& asset);

// Serializes an asset to bytes. Throws ngi::Error on inconsistent fields (sizes, strings
// longer than 64 KiB, resolution not a power of two, non-finite offset/scale).
std::vector<uint8_t> serializeAsset(const Asset& asset);

// Parses bytes into an asset. `name` is used in error messages (normally the path).
// Rejects bad magic, unknown version, truncation, CRC mismatch, missing or duplicate
// chunks and inconsistent sizes with one ngi::Error "NAME: problem". Never reads out of
// bounds, whatever the input.
Asset parseAsset(std::span<const uint8_t> bytes, const std::string& name);

// Reads and parses a file; errors name the path.
Asset readAsset(const std::filesystem::path& path);

// Writes atomically (writeFileAtomic, ngi/output_files.h): a temporary file in the same
// directory, then rename. On any failure the destination is untouched and no temporary file
// is left behind. A tool writing several files stages each with OutputFiles::stage.
void writeAsset(const Asset& asset, const std::filesystem::path& path);

// Reads a whole file; ngi::Error naming the path if it cannot be opened or read.
std::vector<uint8_t> readFileBytes(const std::filesystem::path& path);

// FNV-1a 64-bit hash (source and network identity, not security).
uint64_t fnv1a64(std::span<const uint8_t> bytes);

} // namespace ngi
