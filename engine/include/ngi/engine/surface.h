// ngi engine: one geometry image on the GPU, its full nested mip chain and geomorph
// targets, ready to be drawn at any level of detail by a Renderer.
//
// Every level is an RGBA32UI image (xyz = position bits, w = octahedral normal; see
// shaders/ngi_shared.h), in VK_IMAGE_LAYOUT_GENERAL throughout. The stored level (the
// asset's, ngi/stored_level.h) is uploaded at its own level; finer levels are restored from
// it, either bilinearly level by level (shaders/mip_upsample.comp) or, with a
// SuperResolution network, level 0 at once and the levels between as nested subsamples of
// it; coarser levels are nested subsamples, and each level gets its geomorph targets
// (shaders/morph_targets.comp) and per-quad diagonal choice (shaders/quad_diagonals.comp,
// RGBA32F, one texel per quad).
#pragma once

#include "ngi/asset.h"
#include "ngi/engine/resources.h"
#include "ngi/geometry_image.h"

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace ngi::vk {

class Renderer;
class SuperResolution;

// What a surface is built to be drawn by: the uniform draw (Renderer::recordDraw, DrawBatch)
// needs each level's geomorph targets and quad diagonals (three quarters of the memory); the
// adaptive draw (adaptive_draw.h) reads the levels alone.
enum class SurfaceDraws { uniformAndAdaptive, adaptiveOnly };

// How a surface restores its finer levels from its stored level without a network: bicubic
// writes level 0 in one pass by Catmull-Rom from the stored level (shaders/mip_cubic_restore.comp:
// ngi::nn::cubicSkip's positions, the normals as the network's output pass writes them) and
// levels 1 .. storedLevel - 1 as its nested subsamples, the restore ngi-eval --bicubic and the
// bake's rate control measure; bilinear interpolates every finer level from the next coarser
// one (positions and normals, the normals renormalized): cheaper, farther from the input.
enum class Upsampling { bilinear, bicubic };

// How GeometryImageSurface::recordBuild restores a chart. The default is the tools' default
// without a network: bicubic.
struct ChartRestore {
    // The network that writes level 0 (its positions; the stored normals interpolated by
    // Catmull-Rom and renormalized, shaders/sr_output.comp), levels 1 .. storedLevel - 1 then
    // its nested subsamples. Its scale factor must take the stored level to the full size
    // (ngi::Error otherwise); see SuperResolution::record for its lifetime rule. Null: none.
    SuperResolution* network = nullptr;
    // The chart's AssetChart::residualGain, passed to network->record.
    float residualGain = 1.0f;
    // The restore without a network.
    Upsampling withoutNetwork = Upsampling::bicubic;
};

class GeometryImageSurface {
public:
    // `positions` (normalized to [0,1]^3) and `normals` (unit) at the same size, which must be
    // one of the nested level sizes of `fullSize` (2^k + 1). Creates the GPU images and stages
    // the upload; call recordBuild before drawing. With a matched `seams` (ngi/seam.h), every
    // restored level the seam is aligned to is welded after the restore and only the levels
    // down to its coarsest watertight one are drawn. ngi::Error on bad sizes or seams.
    // `draws`: adaptiveOnly makes no geomorph targets and quad diagonals; the uniform draw of
    // such a surface is then ngi::Error.
    GeometryImageSurface(const Renderer& renderer, const GeometryImage& positions, const GeometryImage& normals,
                         uint32_t fullSize, const ChartSeams& seams = {},
                         SurfaceDraws draws = SurfaceDraws::uniformAndAdaptive);

    // One chart of the asset (its stored level, restored to the chart's full size); an
    // AssetSurface (asset_surface.h) holds every chart. ngi::Error for a missing chart.
    static GeometryImageSurface fromAsset(const Renderer& renderer, const Asset& asset, size_t chart = 0,
                                          SurfaceDraws draws = SurfaceDraws::uniformAndAdaptive);
    // Whether the uniform draw can draw it (not built adaptiveOnly).
    bool uniformDrawable() const { return draws_ == SurfaceDraws::uniformAndAdaptive; }

    // Every GPU object is held by an owner (UniqueImage, ...), so a constructor that throws
    // half-way frees what it made and a moved-from surface holds nothing.
    ~GeometryImageSurface() = default;
    GeometryImageSurface(GeometryImageSurface&& other) noexcept = default;
    GeometryImageSurface& operator=(GeometryImageSurface&&) = delete;
    GeometryImageSurface(const GeometryImageSurface&) = delete;

    // Records upload, restoration of the finer levels (`restore`), the mip chain and the
    // geomorph targets, ending with a barrier that makes them visible to vertex shaders.
    // Record once.
    void recordBuild(VkCommandBuffer cmd, const ChartRestore& restore = {});
    // recordBuild in two halves, for a caller that changes the levels in between (AssetSurface
    // welds the charts of a split component across charts): recordLevels uploads, restores and
    // builds every level (seam welds within the chart included); recordDrawData then computes
    // what the draw reads from them (geomorph targets, quad diagonals). Same arguments and errors.
    void recordLevels(VkCommandBuffer cmd, const ChartRestore& restore = {});
    void recordDrawData(VkCommandBuffer cmd);
    // The chart's base colour for the uniform draw's fragment stage (set 0, binding
    // NGI_DRAW_BINDING_BASE_COLOUR of every level; sRGB, sampled by the chart uv as
    // shaders/chart_colour.glsl does, in SHADER_READ_ONLY_OPTIMAL layout, e.g. a
    // ChartColorImages view). The caller keeps the image alive while the surface is drawn.
    // Without it, the surface binds its own 1 x 1 stand-in (ngi's grey; recordDrawData clears
    // it). Call before recording any draw of the surface (it rewrites the draw sets).
    // `cutsOut`: the colour's alpha is below 1 somewhere (ChartColorImages::cutsOut), so ngi's
    // own shading draws the surface with the alpha test (cutsOut()).
    // ngi::Error for a surface built for the adaptive draw alone, or a null view or sampler.
    void setBaseColour(VkImageView view, VkSampler sampler, bool cutsOut = false);
    bool cutsOut() const { return cutsOut_; }
    // Level l's image (GENERAL layout after recordLevels), for a weld across charts.
    VkImageView levelView(uint32_t l) const { return level(l).view; }

    // Frees the staging buffer once the build has completed on the GPU.
    void releaseUpload();
    // Frees level 0's images (its texels, geomorph targets and quad diagonals: about three
    // quarters of the surface's memory) and its expanded grid, if any, for a surface
    // only drawn far away; draws then clamp
    // the LoD to 1 or coarser (finestLevel()). Only once the GPU has finished the build and
    // every draw recorded before; irreversible (build a new surface to draw level 0 again).
    void releaseFinestLevel();
    // The finest level drawn: 0, or 1 after releaseFinestLevel.
    uint32_t finestLevel() const { return finestLevel_; }

    uint32_t fullSize() const { return fullSize_; }
    uint32_t levelCount() const { return levelCount_; }
    // Levels drawn (0 .. drawnLevelCount() - 1): all of them without a matched seam; with one,
    // down to the 5 x 5 level or the seam's coarsest watertight level if coarser (see
    // AssetChart::coarsestDrawnLevel). Renderer::recordDraw clamps the LoD to them.
    uint32_t drawnLevelCount() const { return drawnLevelCount_; }
    // Levels with a weld pass (0 .. weldedLevelCount() - 1 of the restored levels the seam is
    // aligned to; 0 without a matched seam). The bilinear restore welds each of them, the
    // network level 0 only (the others are its nested subsamples).
    uint32_t weldedLevelCount() const { return uint32_t(weldSets_.size()); }
    uint32_t storedLevel() const { return storedLevel_; }
    uint32_t levelSize(uint32_t level) const;
    VkDescriptorSet drawSet(uint32_t level) const { return drawSets_.at(level); }
    // Bounding box of the stored samples (normalized space), for framing a camera.
    glm::vec3 boundsMin() const { return boundsMin_; }
    glm::vec3 boundsMax() const { return boundsMax_; }
    // Normalized -> object space of the asset the surface came from (offset + scale * p,
    // Asset::offset/scale); identity for a surface made from images. DrawParams::world
    // starts from object space.
    const glm::mat4& objectFromNormalized() const { return objectFromNormalized_; }
    // Device memory held by the surface's images (bytes).
    VkDeviceSize gpuBytes() const;
    // VkDeviceMemory allocations the surface holds now: its images' (two on ngi's devices,
    // ImagePool; one after releaseFinestLevel), the seam's weld pairs (if welded), the
    // upload until releaseUpload and one per expanded level (expandedGrid).
    uint32_t deviceAllocationCount() const;

    // The grid expansion (Renderer::recordGridExpansion): each level drawn with shared
    // vertices gets, on its first expansion, an index buffer of 6 (N - 1)^2 16-bit indices
    // in chunks of gridChunkRows(N) quad rows (the vertex shader geomorphs the samples
    // itself): 12 bytes per quad, 12 MiB for a 1025^2 level, written at run time and never
    // part of the asset. It is mutable state behind a const surface,
    // tracked on the CPU in recording order: record the expansions and draws of one surface
    // from one thread, into command buffers submitted to one queue in the order they were
    // recorded.
    struct ExpandedGrid {
        VkBuffer indices = VK_NULL_HANDLE;  // VK_INDEX_TYPE_UINT16, quad by quad, in chunks; drawn with drawSet(level)
        uint32_t gridSize = 0;              // N
        uint32_t chunkRows = 0;             // gridChunkRows(N)
    };
    // Quad rows per chunk of an N-grid's expanded index buffer: each chunk is drawn with
    // vertexOffset = its first row * N, so that its vertices fit 16-bit indices below 0xFFFF
    // ((rows + 1) N <= 65535; GridExpansionPushConstants in ngi_shared.h).
    static uint32_t gridChunkRows(uint32_t gridSize);
    // `level`'s expanded grid if the last expansion recorded for that level was for
    // geomorph factor `morph`; nothing otherwise.
    std::optional<ExpandedGrid> expandedGrid(uint32_t level, float morph) const;
    // Device memory held by expanded grids now (bytes; not in gpuBytes()).
    VkDeviceSize gridExpansionBytes() const;
    // Frees every expanded grid (the next expansion of a level makes its buffers again).
    // Only once the GPU has finished every command buffer recorded with them.
    void releaseGridExpansions() const;

    // Reads a level's texels (or its geomorph targets) back to the host; waits for the GPU.
    // For tests and tools, not for frames.
    std::vector<glm::uvec4> readLevel(uint32_t level, bool morphTargets) const;
    // Reads a level's expanded grid back: its 6 (size - 1)^2 indices (quad by quad, as the
    // vertex numbers j * size + i they draw, chunk offsets added); ngi::Error if the level
    // has none. Waits for the GPU; for tests and tools.
    std::vector<uint32_t> readGridIndices(uint32_t level) const;
    // Reads a level's quad diagonals (C, B, A, 0) back, (size - 1)^2 texels.
    std::vector<glm::vec4> readQuadDiagonals(uint32_t level) const;

private:
    friend class Renderer;  // records the grid expansions into expansions_
    // One level's expanded grid and what it holds (see expandedGrid).
    struct GridExpansion {
        UniqueBuffer indices;                         // 6 (N - 1)^2 16-bit indices, device-local
        VkDescriptorSet computeSet = VK_NULL_HANDLE;  // grid_expansion.comp's: diagonals, indices
        float morph = 0.0f;                           // the geomorph factor of the last recorded expansion
        bool recorded = false;                        // an expansion was recorded into the buffer
    };
    // Makes level l's index buffer and writes it into its compute set (never used before, or
    // only before releaseGridExpansions, whose rule makes rewriting them safe).
    GridExpansion& allocateExpansion(uint32_t level) const;
    const Renderer* renderer_;
    bool cutsOut_ = false;  // setBaseColour
    uint32_t fullSize_ = 0;
    uint32_t storedLevel_ = 0;
    // Every image in two allocations (ImagePool): level 0's images (its texels, geomorph
    // targets and quad diagonals: three quarters of the memory) apart, so that
    // releaseFinestLevel can free them, and every other level's.
    ImagePool fineImages_;  // [0] level 0, [1] its geomorph targets, [2] its quad diagonals
    ImagePool images_;      // levels 1..L-1 [0, L-1), their geomorph targets [L-1, 2L-3), quad diagonals [2L-3, 3L-4)
    uint32_t levelCount_ = 0;
    uint32_t finestLevel_ = 0;
    const Image& level(uint32_t l) const { return l == 0 ? fineImages_[0] : images_[l - 1]; }
    void recordMipPass(VkCommandBuffer cmd, VkPipeline pipeline, VkDescriptorSet set, uint32_t fine, uint32_t coarse,
                       uint32_t extent) const;
    const Image& morphTarget(uint32_t l) const { return l == 0 ? fineImages_[1] : images_[levelCount_ - 1 + l - 1]; }
    const Image& quadDiagonal(uint32_t l) const
    {
        return l == 0 ? fineImages_[2] : images_[2 * levelCount_ - 3 + l - 1];
    }
    const Image& standInColour() const { return images_[images_.size() - 1]; }  // uniform draws only
    UniqueBuffer upload_;
    UniqueDescriptorPool pool_;
    std::vector<VkDescriptorSet> pairSets_;          // [l]: level l (binding 0), level l + 1 (binding 1)
    VkDescriptorSet cubicSet_ = VK_NULL_HANDLE;      // level 0 (binding 0), the stored level (binding 1)
    std::vector<VkDescriptorSet> morphSets_;         // [l]: level l, its morph targets
    std::vector<VkDescriptorSet> quadSets_;          // [l]: level l, morph targets (or itself), quad diagonals
    std::vector<VkDescriptorSet> drawSets_;          // [l]: level l, morph targets (itself if coarsest), quad diagonals
    std::vector<VkDescriptorSet> weldSets_;          // [l]: level l, the weld pairs
    mutable std::vector<GridExpansion> expansions_;  // [l]: level l's, buffers made on its first expansion
    std::vector<uint32_t> weldOffsets_;              // [l]: first pair of level l; [levels]: the total
    UniqueBuffer weldPairs_;                         // uvec2 (destination, source) perimeter indices
    uint32_t drawnLevelCount_ = 0;
    glm::vec3 boundsMin_{0.0f}, boundsMax_{1.0f};
    glm::mat4 objectFromNormalized_{1.0f};
    bool built_ = false;
    SurfaceDraws draws_ = SurfaceDraws::uniformAndAdaptive;
};

}  // namespace ngi::vk
