// ngi core: the .ngi asset file (docs/DESIGN.md, "The asset contract").
//
// One file per asset, little-endian:
//   magic "\x89NGI\r\n\x1a\n" (8 bytes: catches text-mode mangling like PNG's signature)
//   u32 formatVersion, u32 chunkCount, u32 tableCrc32, u32 reserved (0)
//   chunkCount table entries of 32 bytes:
//     u32 fourcc, u32 encoding (0 raw, 1 zlib of parallelogram-predicted 16-bit samples,
//     2 POSI of one chart coded across the nested pyramid, 3 NORM predicted from the decoded
//     positions, 4 the POSI of every chart level by level; ngi/pyramid_codec.h; 5 one WebP
//     BCOL, 6 packed SEAM/XSEM and 7 the packed BCOL of format 9, below),
//     u64 offset, u64 storedBytes, u32 crc32 (of the stored bytes), u32 chart index
//     (POSI before format 5, NORM, SEAM and BCOL before format 9: the chart the chunk belongs
//     to; 0 otherwise)
//   chunk payloads, each starting on an 8-byte boundary.
// Chunks: HEAD (fixed fields + strings), CHRT (the chart table: per chart u32 full
// resolution, u32 stored level, u32 stored size; format 6: + f32 residual gain), META (free-form JSON text: bake report,
// seams), POSI and NORM once per chart (stored position level, u16 RGB normalized to
// [0,1]; stored normal level, u16 RGB = (n + 1) / 2; format 5: one POSI for every chart and
// NORM only with a normal residual, below), SEAM once per chart whose border the
// bake matched (u32 coarsest watertight level, u32 segment count, count x {u32 a, u32 b,
// u32 length}; see ngi/seam.h), WGHT (optional network weights).
//
// Format version history. Every version is read; ngi writes 9. "Written when" below is what
// the builds of its time wrote, which ngi/asset_legacy.h still writes for the readers' tests
// (formats 3-8; 1 and 2 only as test bytes).
//   1 = one chart; HEAD holds its resolution and stored level; no CHRT. Still read.
//   2 = several charts (one per connected component of the input): CHRT, per-chart
//       POSI/NORM, HEAD without the per-chart fields. Still read.
//   3 = version 2 plus the optional per-chart SEAM chunk (matched seams). Written when
//       Asset::coding.pyramid is false.
//   4 = version 3 plus encodings 2 (POSI) and 3 (NORM). Written when Asset::coding.pyramid
//       and not coding.progressive. Still read.
//   5 = progressive (streaming): any prefix of the file that ends on a level boundary is a
//       coarser asset (ngi/asset_prefix.h). The chunks in this order: HEAD, CHRT, META, the
//       SEAMs, ONE POSI (chart index 0, encoding 4) holding every chart, then the optional
//       rest: NORM of a chart only where it has a normal residual (encoding 3; without one
//       the normals are the prediction from the positions), WGHT. Written when
//       coding.pyramid and coding.progressive (the default).
//   6 = version 3, 4 or 5 (the one chart 0's POSI encoding names: 1 -> 3, 2 -> 4, 4 -> 5, whose
//       rules then apply) with 16-byte CHRT entries: + f32 residual gain in [0, 1] (AssetChart::
//       residualGain). Written instead of 3/4/5 only when some chart's gain is not 1, so every
//       asset without one keeps its bytes; readers of 1-5 reject it by its version.
//   7 = version 6 plus the XSEM chunk (chart field 0, raw, a description chunk: before POSI in
//       format 5's order): the curves charts share (Asset::crossSeams, seam.h CrossSeamSegment),
//       u32 count, count x {u32 chartA, u32 a, u32 chartB, u32 b, u32 length}. Written only when
//       an asset has cross-chart seams (a split component, ngi-bake --split-pieces);
//       readers of 1-6 reject it by its version, and an XSEM in a file below 7 is rejected.
//   8 = version 7 plus the BCOL chunk, once per chart that has a base colour (chart field: the
//       chart, encoding 5: WebP; after POSI in format 5's order, so a prefix has the geometry
//       first): u32 level (the level of the chart's full image whose grid the colour image
//       samples, AssetChart::baseColor), then one WebP image of (full >> level) + 1 texels per
//       side, 8-bit sRGB, RGB or RGBA. Written only when a chart has a base colour; readers of
//       1-7 reject it by its version, and a BCOL in a file below 8 is rejected.
//   9 = version 8's chunks and rules with the per-chart chunks packed, written for every asset
//       (serializeAsset): 16-byte CHRT entries always; ONE SEAM chunk (chart field 0) for
//       every chart, present when some chart has a matched seam, and XSEM, both with encoding 6:
//       u32 unpacked bytes, then zlib of LEB128 fields. SEAM: per chart m (0: no matched seam,
//       else 1 + its coarsest watertight level), then where m > 0 the segment count and per
//       segment a, b, length. XSEM: the count, then per segment chartA, a, chartB, b, length.
//       ONE BCOL chunk (chart field 0, encoding 7, after POSI) when a chart has a colour: per
//       chart LEB128 m (0: no colour, else 1 + its colour level), then where m > 0 LEB128 n and
//       n bytes of the WebP image. Readers of 1-8 reject it by its version; a SEAM, XSEM or BCOL
//       of format 9 in another encoding, or a packed one below 9, is rejected.
//
// Format 5's POSI (encoding 4): the charts' positions by pyramid codec 2 (one flushed
// stream per level, ngi/pyramid_codec.h), in rounds: round r holds level r (0: the 2 x 2
// corners) of every chart with more than r levels, in chart order, so every chart's
// coarsest level comes first, then every chart's next level, ... (a chart of half the
// resolution stores one level fewer and is complete one round earlier; at every round all
// charts have the same number of samples per side, so a prefix's smaller charts are denser
// than its largest until they are complete).
//   u8 1 (layout version), u8 R (rounds: the most levels of any chart)
//   per chart: u8 flags (bit 0: the normal prediction's sign is flipped), the codec-2 header
//              (3 + 2 x levels bytes: codec version 2, levels, tangent scale, u16 steps)
//   R LEB128 lengths: the bytes of each round
//   R u32 CRC32s: of each round's bytes
//   u32 CRC32 of everything above (the level table)
//   the rounds, back to back (within a round the chart streams have no lengths: each
//   decoder finds the end of its own).
// A level boundary is the end of a round: the POSI chunk's offset + the level table + the
// rounds so far. Streaming costs the level table, 6 + sum over charts (4 + 2 x levels) + 5 to
// 7 bytes per round, and the flushes, about 3 bytes per chart and level; format 5 leaves out
// the prediction-only NORM chunks (docs/FORMAT.md gives the cost on bunny00).
#pragma once

#include "ngi/geometry_image.h"
#include "ngi/seam.h"
#include "ngi/output_files.h"  // writeFileAtomic, used with the readers below by every tool

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace ngi {

inline constexpr uint32_t kAssetFormatVersion = 9;  // the newest version read, and the one written

// Largest full resolution any tool accepts (cells per side; a power of two). A 4096^2
// image restores to 4097^2 float samples (~200 MB of positions + normals on the CPU,
// ~550 MB of GPU images with its mip chain): the most a 2-core CI machine on lavapipe
// renders; the paper uses 1024. Readers check it against the header before allocating.
inline constexpr uint32_t kMaxFullResolution = 4096;
// Most charts in one asset, and most full-resolution samples of all charts together
// (twice one 4096^2 chart): the bound on what a reader lets an asset make it allocate.
inline constexpr uint32_t kMaxCharts = 1024;
inline constexpr uint64_t kMaxTotalFullSamples = 2ull * (kMaxFullResolution + 1) * (kMaxFullResolution + 1);

// One chart: a square geometry image of one connected part of the surface, kept at its
// stored mip level. Samples are kept exactly as stored on disk (16-bit unsigned, RGB
// interleaved, row-major) so that a write after a read is lossless.
struct AssetChart {
    uint32_t fullResolution = 1024;   // cells per side of the full image (power of two)
    uint32_t storedLevel = 3;         // mip level kept; stored samples = (full >> level) + 1
    std::vector<uint16_t> positions;  // storedSize^2 * 3, normalized with the asset's offset/scale
    std::vector<uint16_t> normals;    // storedSize^2 * 3
    ChartSeams seams;                 // which border samples are one surface point (seam.h)
    // The chart's base colour over its own square (the square is its texture atlas: no stored
    // texture coordinates): 8-bit sRGB RGBA, row-major, texel (x, y) the colour of the surface at
    // the full image's sample ((x, y) << baseColorLevel), so a grid vertex at uv samples it at uv.
    // Empty: the chart has no colour of its own (drawn with the default material).
    std::vector<uint8_t> baseColor;
    uint32_t baseColorLevel = 0;  // level of the full image whose grid baseColor covers
    // The super-resolution restore of this chart is c + residualGain * (n - c): n the network's
    // output, c the Catmull-Rom (bicubic) upsampling of the stored level by the network's factor.
    // In [0, 1]; 0 restores the bicubic (never worse than it in image RMS), 1 the network as
    // trained (every asset before format 6). ngi-bake sets it per chart by least squares against
    // the full image (ngi/nn/residual_gain.h).
    float residualGain = 1.0f;

    uint32_t storedSize() const { return (fullResolution >> storedLevel) + 1; }
    // Texels per side of baseColor: (fullResolution >> baseColorLevel) + 1.
    uint32_t baseColorSize() const { return (fullResolution >> baseColorLevel) + 1; }
    uint32_t fullSize() const { return fullResolution + 1; }
    // Mip levels of the full image (full size down to 2 x 2).
    uint32_t levelCount() const;
    // The coarsest level drawn: for a matched seam its coarsest watertight level (the 5 x 5
    // level for most charts, finer where the cut has many nodes: no drawn level opens); else
    // the 2 x 2 level (levelCount() - 1).
    uint32_t coarsestDrawnLevel() const;
};

// How the stored levels are coded on disk (serializeAsset; parseAsset reports what it read).
struct AssetCoding {
    // False: zlib of parallelogram-predicted samples (lossless, format 3). True: positions
    // across the nested pyramid with a quantization step, normals predicted from the decoded
    // positions (format 5, or 4, ngi/pyramid_codec.h): lossy, the samples the reader gets are
    // those of applyAssetCoding.
    bool pyramid = false;
    // With pyramid: true writes format 5 (progressive: every level-boundary prefix of the file
    // decodes, ngi/asset_prefix.h), false format 4 (one stream per chart, a few bytes per level
    // smaller, no prefix decodes). The decoded samples are the same. The reader reports it.
    bool progressive = true;
    uint32_t positionStep = 64;         // step in 1/65536 of the bounding box (64: 2^-10), in [1, 4096]
    uint32_t positionTangentScale = 0;  // 0: xyz residuals; T: normal/tangent frame, tangent step T x step
    // Each coarser level's step is this many times finer (pyramid_codec.h gradedLevelSteps); 1:
    // every level at positionStep; in [1, 4], or 0 (= 1). ngi's writers use 1 or sqrt 2
    // (kPyramidStepGrades); the reader reports which made the file (0: per-level steps no ngi
    // writer makes, which a rewrite codes at positionStep everywhere).
    double positionStepGrade = 1.0;
    uint32_t normalBits = 0;  // octahedral residual bits over the prediction (0: none), <= 16
    // The charts' base colour images (chunk BCOL): WebP quality in [0, 100], 101 lossless.
    // The reader cannot tell the quality from the file and leaves it as it is.
    uint32_t colorQuality = 90;
};

// A geometry-image asset: one chart per connected part of the input, all normalized into
// one frame, plus what is needed to restore and de-normalize them.
struct Asset {
    std::string sourceName;        // source mesh file name, or "analytic:NAME"
    uint64_t sourceHash = 0;       // FNV-1a 64 of the source file's bytes (0 = analytic)
    glm::vec3 offset{0.0f};        // object-space position = offset + scale * normalized
    glm::vec3 scale{1.0f};         //   (uniform scale: the bbox's longest side maps to [0,1])
    std::string parameterization;  // "ot", "ricci", "harmonic", "tutte", "authalic", "analytic"
    std::string networkId;         // super-resolution network expected ("" = none)
    uint64_t networkHash = 0;
    std::string metadataJson;        // free-form JSON: bake report, seam descriptions
    std::vector<AssetChart> charts;  // at least one; charts[0] is the largest
    // Curves two charts share (a component split into charts): their samples are one surface
    // point at every level down to both charts' coarsest watertight level (seam.h). Empty for
    // every asset whose charts are separate components.
    std::vector<CrossSeamSegment> crossSeams;
    std::vector<uint8_t> weights;  // optional per-asset weights (counted in the bytes)
    AssetCoding coding;            // how serializeAsset codes the stored levels

    // The largest full resolution of any chart: the asset's LoD 0 grid (lodOffset).
    uint32_t fullResolution() const;
    // Whether some chart has a base colour (AssetChart::baseColor).
    bool hasBaseColors() const;
};

// The level chart `chart` draws when the asset is drawn at level `assetLevel` of its
// largest chart: the same sample density on the surface. The bake gives a chart a
// resolution proportional to the square root of its area (a chart of a quarter of the area
// has half the resolution), so that is the same level index: assetLevel (the caller clamps it
// to the chart's own levels; a smaller chart has fewer and stops at its coarsest). A fixed
// grid of N samples scales the same way: ((N - 1) >> log2(asset / chart resolution)) + 1.
int chartLevelForAssetLevel(const Asset& asset, const AssetChart& chart, int assetLevel);

// Quantizes a geometry image into the chart's stored level. `positions` must already be
// normalized to [0,1]^3 (values are clamped); `normals` are unit vectors. Both must have
// chart.storedSize() samples per side, else ngi::Error.
void storeGeometryImage(AssetChart& chart, const GeometryImage& positions, const GeometryImage& normals);

// The stored level as floats: positions in [0,1]^3 (normalized), normals unit length.
GeometryImage storedPositions(const AssetChart& chart);
GeometryImage storedNormals(const AssetChart& chart);

// Replaces every chart's positions and normals by what a reader of serializeAsset(asset)
// gets (positions and normals: a no-op unless asset.coding.pyramid; base colours: decoded
// from their WebP coding at coding.colorQuality), so the in-memory asset matches its file.
// With xyz residuals (positionTangentScale 0) coding decoded samples again gives the same
// samples and bytes; with the residual frame it may not (keep the uncoded samples to write
// the same file twice).
void applyAssetCoding(Asset& asset);

// Serializes an asset to bytes in the current format, 9 (the positions coded as `asset.coding`
// says; the older formats' writer, for the readers' tests: ngi/asset_legacy.h). Throws
// ngi::Error on inconsistent fields (no chart, more than kMaxCharts, sizes, strings longer than
// 64 KiB, a resolution that is not a power of two or above kMaxFullResolution, non-finite
// offset/scale, a residual gain outside [0, 1], a base colour whose size is not
// baseColorSize()^2 x 4 or whose level is not one of the chart's, a colorQuality above 101).
std::vector<uint8_t> serializeAsset(const Asset& asset);

// Parses a whole file (format version 1 to 9) into an asset. `name` is used in error messages
// (normally the path). Rejects bad magic, unknown version, truncation (any prefix, even one
// that readAssetPrefix decodes), CRC mismatch,
// missing or duplicate chunks, inconsistent sizes and values beyond the limits above
// (checked before anything is allocated for them) with one ngi::Error "NAME: problem".
// Never reads out of bounds, whatever the input.
Asset parseAsset(std::span<const uint8_t> bytes, const std::string& name);

// One entry of an asset's chunk table (assetChunkSizes).
struct AssetChunkSize {
    std::string name;  // the chunk's fourcc: "HEAD", "CHRT", "POSI", ...
    // The chart a per-chart chunk belongs to (NORM; SEAM and BCOL before format 9; POSI before 5);
    // else 0.
    uint32_t chart = 0;
    uint64_t offset = 0;  // where its payload starts in the file
    uint64_t bytes = 0;   // its stored bytes
    // How its payload is coded: the table entry's encoding field (docs/FORMAT.md; 0 where the
    // chunk has one coding).
    uint32_t encoding = 0;
};

// The chunk table of a whole asset file, in table order (the order of the payloads in every
// file ngi writes): each chunk's name, chart, offset and stored bytes. The file's header, its
// table and the alignment between payloads are no chunk's. Reads the table with parseAsset's
// checks (magic, version, table CRC, every chunk inside the file, its CRC, no duplicate) but
// decodes no payload. Throws ngi::Error "NAME: problem" on a malformed or truncated file.
std::vector<AssetChunkSize> assetChunkSizes(std::span<const uint8_t> file, const std::string& name = "asset");

// Reads and parses a file; errors name the path.
Asset readAsset(const std::filesystem::path& path);

// Writes atomically (writeFileAtomic, ngi/output_files.h): a temporary file in the same
// directory, then rename. On any failure the destination is untouched and no temporary file
// is left behind. A tool writing several files stages each with OutputFiles::stage.
void writeAsset(const Asset& asset, const std::filesystem::path& path);

// Reads a whole file: the one input-file opener of the project (every tool's assets, meshes,
// weights, PNGs and lists go through it). Only regular files (or symbolic links to one) are
// read; anything else is refused before it is read, without blocking (a FIFO with no
// writer never hangs it). Throws ngi::Error naming the path: "PATH: is a FIFO, not a
// regular file" (a directory, a character device, ...), "PATH: cannot open file (No such
// file or directory)" and other reasons, "PATH: read failed (REASON)".
std::vector<uint8_t> readFileBytes(const std::filesystem::path& path);

// FNV-1a 64-bit hash (source and network identity, not security).
uint64_t fnv1a64(std::span<const uint8_t> bytes);

}  // namespace ngi
