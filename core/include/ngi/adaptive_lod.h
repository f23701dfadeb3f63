// ngi core: adaptive level of detail over a geometry image: each tile of each chart's grid
// draws its own level, chosen by its own error bound (object space, or projected for a
// camera), crack-free across tiles and seams, geomorphed continuously. This is the one
// definition of the adaptive surface on the CPU (ngi-eval exports it; the GPU mirrors it).
//
// Tiles form a quadtree per chart (CDLOD, Strugar 2009, "Continuous Distance-Dependent
// Level of Detail for Rendering Heightmaps"): a tile of level l covers kTileQuads x
// kTileQuads quads of mip level l, i.e. kTileQuads << l cells of the full image; its four
// children cover its quarters at level l - 1. The root is the level whose grid is one tile.
//
// The grid of every level is split by alternating diagonals (quad (X, Y) of a level along
// a-c when X + Y is even, else b-d: the 4-8 mesh of restricted quadtree triangulations,
// Lindstrom et al. 1996, Pajarola 1998). With it, a level's grid geomorphed to its targets
// (morph 1) lies on the next coarser level's triangles for ANY tile layout, and the
// diagonal of a quad never depends on the morph, so no per-quad data is stored. The geomorph
// target of a sample is the next coarser level's surface at its uv (fitted_levels.h:
// coarserSurfaceAt), so the levels need not be nested: fitCoarseLevels' approximating levels
// morph into each other as exactly as nested ones.
//
// Error bounds: for tile T of level l, `error` bounds the distance between the full surface
// and the level-l surface over T (border included), both ways: the larger, over T's full
// resolution samples, of a sample's distance to the level's triangles over its quad and of
// the level's point at the sample's uv to the full-resolution triangles around it (upper
// bounds of point-to-surface distances, which do not count samples sliding along the surface:
// the metrics measure point to surface too); `errorUp` the same for level l + 1 (>= error).
// A tile drawn at morph t lies between the two surfaces.

// Selection: a tile is refined while its error, projected, exceeds the budget, or while it
// is coarser than the chart allows (the seam's coarsest watertight level on the chart's
// border, the coarsest drawn level anywhere). Tiles that share a vertex, across seams too,
// are then balanced to differ by at most one level (forced splits). Each tile's morph t
// runs 0 -> 1 as its projected error moves from `error` to `errorUp` (log-linear), so a
// parent replaces its four children exactly when they are fully morphed: no pop.
//
// Cracks: every vertex on a tile border gets ONE state (level, morph), the largest over all
// tiles that hold it, or an edge through it, or the same for one of its seam mates (they are
// the same surface point). A tile
// draws its border vertices by that state; where the state is one level coarser than the
// tile, the tile's odd border vertices are dropped (their triangles re-point to the even
// neighbour: the alternating diagonals make that exactly the coarser edge), so both sides
// of every border draw the same vertices at the same positions: no T-junction, no gap.
#pragma once

#include "ngi/error.h"
#include "ngi/lod_grid.h"
#include "ngi/seam.h"

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <glm/vec3.hpp>

#include <cstdint>

#include <vector>

namespace ngi {

// Quads per side of one tile at its own level (a multiple of 4, so tile borders are even
// lines of the next coarser level too). NGI_TILE_QUADS in shaders/ngi_shared.h.
inline constexpr uint32_t kTileQuads = 4;
// Morph factors are multiples of 1 / kMorphSteps (15 bits per border vertex on the GPU).
inline constexpr uint32_t kMorphSteps = 32767;
// `morph` clamped to [0, 1] (NaN: 0) and rounded to a multiple of 1 / kMorphSteps.
float quantizeMorph(float morph);

// Bounds of one tile, normalized asset space.
// buildTileTree keeps each bound as its 16-byte code stands for (ngi/tile_bound_code.h: rounded
// conservatively, so it still bounds), the numbers the selection on the GPU decides on.
struct TileBound {
    float error = 0.0f;      // max distance, full-resolution samples -> this level's surface
    float errorUp = 0.0f;    // the same for the next coarser level (>= error)
    glm::vec3 centre{0.0f};  // bounding sphere of the tile's full-resolution samples
    float radius = 0.0f;
    glm::vec3 coneAxis{0.0f, 0.0f, 1.0f};  // normal cone of its full-resolution quads
    float coneCos = -1.0f;                 // cos of the cone's half angle; <= 0: no backface cull
};

// The tile quadtree of one chart.
struct TileTree {
    uint32_t resolution = 0;      // R: cells per side of the full image
    uint32_t levelCount = 0;      // mip levels of the chart (full size down to 2 x 2)
    uint32_t rootLevel = 0;       // level of the single root tile: log2(R / kTileQuads)
    uint32_t coarsestLevel = 0;   // no tile is drawn coarser (the chart's coarsest drawn level)
    uint32_t perimeterLevel = 0;  // no tile touching the square's border is drawn coarser
    // [level][y * tilesPerSide(level) + x] for levels 0 .. rootLevel.
    std::vector<std::vector<TileBound>> tiles;
    uint32_t tilesPerSide(uint32_t level) const { return 1u << (rootLevel - level); }
    const TileBound& tile(uint32_t level, uint32_t x, uint32_t y) const
    {
        return tiles[level][size_t(y) * tilesPerSide(level) + x];
    }
};

// Measures the tile bounds of a chart's restored pyramid (its full image and nested levels).
// `coarsestLevel`: the chart's coarsest drawn level; `perimeterLevel`: the coarsest level a
// tile on the border may draw (the seam's coarsest watertight level; = coarsestLevel for a
// chart without matched seam). ngi::Error if the full resolution is not a power of two of
// at least kTileQuads. About 10 ns per full-resolution sample and
// level on one core; rows of tiles are measured on every core (the result does not depend on
// their number).
TileTree buildTileTree(const SurfacePyramid& pyramid, uint32_t coarsestLevel, uint32_t perimeterLevel);

// One chart of an adaptive surface: its restored pyramid, its tile tree and its seams.
struct AdaptiveChart {
    const SurfacePyramid* pyramid = nullptr;
    const TileTree* tree = nullptr;
    ChartSeams seams;
};

// Which border samples of which charts are one surface point: every chart's own seam
// mates and the cross seams between charts (seam.h), closed transitively.
struct SurfaceMates {
    // [chart][perimeter index t of the full resolution]: a key shared by exactly the samples
    // that are one surface point.
    std::vector<std::vector<uint64_t>> perimeterKey;
    // [chart]: every border sample has a mate (no boundary of the input runs along the
    // border). Only such charts are culled by their normal cones: ngi draws both sides of a
    // surface, and the inside of an open one can face the camera.
    std::vector<bool> closed;
};
// ngi::Error as seamWeldTable / groupWeldPlan.
SurfaceMates buildSurfaceMates(const std::vector<AdaptiveChart>& charts,
                               const std::vector<CrossSeamSegment>& crossSeams);

// What the selection must meet.
struct AdaptiveView {
    // false: a uniform object-space bound `maxError` (normalized units, the asset's longest
    // side = 1), every tile at morph 0. true: a camera, `maxErrorPixels` on screen.
    bool camera = false;
    float maxError = 0.01f;
    glm::mat4 clipFromNormalized{1.0f};  // normalized asset space -> Vulkan clip space
    glm::vec3 eye{0.0f};                 // camera position in normalized space (backface culling)
    float viewportHeight = 720.0f;       // pixels
    float maxErrorPixels = 1.0f;
    bool cull = true;  // camera only: mark tiles outside the frustum or back-facing
                       // (the latter on closed charts only, SurfaceMates::closed)
};

// What the selection derives from a camera view's matrix (selectTiles; the GPU selection gets
// the same values): the frustum's planes (Gribb and Hartmann 2001, Vulkan's 0 <= z <= w,
// inward unit normals; a degenerate plane such as an infinite far plane is left out), |d w /
// d position| and |d y_clip / d position|, and whether it is orthographic (w constant).
struct ViewFrustum {
    glm::vec4 planes[6]{};
    uint32_t planeCount = 0;
    float gradW = 0.0f, rowY = 0.0f;
    bool orthographic = false;
};
ViewFrustum viewFrustum(const glm::mat4& clipFromNormalized);

// Checks an AdaptiveView: maxError (object space) or maxErrorPixels and viewportHeight
// (camera) finite and > 0, the matrix finite. ngi::Error naming the field otherwise.
void validateAdaptiveView(const AdaptiveView& view);

struct SelectedTile {
    uint32_t chart = 0, level = 0, x = 0, y = 0;  // tile (x, y) of its level
    float morph = 0.0f;                           // towards level + 1, in [0, 1]
    bool culled = false;                          // outside the frustum or back-facing (not drawn)
};

// A border vertex's state: the level and morph it is drawn at.
struct BorderState {
    uint32_t level = 0;
    float morph = 0.0f;
};

// A hash map from vertex keys (vertexKey) to values, open addressing with linear probing: the
// selection touches tens of keys per tile every frame, where node-based maps allocate.
template <class Value> class VertexKeyMap {
public:
    static constexpr uint64_t kEmpty = ~uint64_t(0);  // never a vertex key
    void clear() { keys_.clear(), values_.clear(), size_ = 0; }
    void reserve(size_t count)
    {
        if (2 * count <= keys_.size()) return;
        size_t capacity = 64;
        while (capacity < 2 * count) capacity *= 2;
        rehash(capacity);
    }
    // The value of `key`, inserted as `value` if absent; `inserted` says which.
    Value& tryEmplace(uint64_t key, const Value& value, bool& inserted)
    {
        if (2 * (size_ + 1) > keys_.size()) rehash(keys_.empty() ? 64 : 2 * keys_.size());
        size_t i = slot(key);
        inserted = keys_[i] == kEmpty;
        if (inserted) keys_[i] = key, values_[i] = value, ++size_;
        return values_[i];
    }
    const Value* find(uint64_t key) const
    {
        if (keys_.empty()) return nullptr;
        const size_t i = slot(key);
        return keys_[i] == key ? &values_[i] : nullptr;
    }
    // The value of a key that must be present; ngi::Error otherwise.
    const Value& at(uint64_t key) const
    {
        const Value* value = find(key);
        if (!value) throw Error("adaptive LoD: a tile border vertex has no state");
        return *value;
    }
    size_t size() const { return size_; }

private:
    size_t slot(uint64_t key) const
    {
        const size_t mask = keys_.size() - 1;
        size_t i = size_t((key * 0x9E3779B97F4A7C15ull) >> 20) & mask;
        while (keys_[i] != key && keys_[i] != kEmpty) i = (i + 1) & mask;
        return i;
    }
    void rehash(size_t capacity)
    {
        std::vector<uint64_t> keys(capacity, kEmpty);
        std::vector<Value> values(capacity);
        keys.swap(keys_);
        values.swap(values_);
        size_ = 0;
        bool inserted;
        for (size_t i = 0; i < keys.size(); ++i)
            if (keys[i] != kEmpty) tryEmplace(keys[i], values[i], inserted);
    }
    std::vector<uint64_t> keys_;
    std::vector<Value> values_;
    size_t size_ = 0;
};

// Which selected tile covers each part of one chart's square: cells of kTileQuads <<
// finestLevel full-resolution cells, the finest level any of the chart's tiles has.
struct ChartTileCover {
    uint32_t resolution = 0;      // R of the chart
    uint32_t finestLevel = 0;     // the cells' level
    uint32_t side = 0;            // cells per side: R / (kTileQuads << finestLevel)
    std::vector<uint32_t> tiles;  // [cy * side + cx]: index into TileSelection::tiles
};

struct TileSelection {
    std::vector<SelectedTile> tiles;
    std::vector<ChartTileCover> cover;          // per chart
    VertexKeyMap<BorderState> perimeterStates;  // the chart borders' vertices, by vertex key
    uint32_t forcedSplits = 0;                  // tiles split by the balance, not by their error
    uint32_t culledFrustum = 0, culledBackface = 0;
    uint64_t triangles = 0;  // drawn (culled tiles excluded), stitched borders counted

    // The state of full-resolution sample (x, y) of chart `chart` (the one selectTiles made
    // `mates` for), a border vertex of one of its tiles: the coarsest level of the tiles that
    // hold it (or one of its seam mates) on their border, the largest morph of those there.
    // ngi::Error for a sample no tile border holds.
    BorderState borderState(const SurfaceMates& mates, uint32_t chart, uint32_t x, uint32_t y) const;
};

// Selects every chart's tiles for `view` (deterministic: a function of its arguments only).
// ngi::Error for an invalid view or charts without trees.
TileSelection selectTiles(const std::vector<AdaptiveChart>& charts, const SurfaceMates& mates,
                          const AdaptiveView& view);

// One selection to make: an adaptive surface (its charts and mates, which must outlive the
// call) and a view.
struct SelectionRequest {
    const std::vector<AdaptiveChart>* charts = nullptr;
    const SurfaceMates* mates = nullptr;
    AdaptiveView view;
};
// selectTiles for every request, spread over `threads` threads (0: the machine's cores; never
// more than the requests), in request order: the same selections as one call per request, for
// any thread count. A host with many instances and passes selects them all at once. An error
// of any request (a null surface is one) is the error of the first such request, thrown after
// every thread has finished.
std::vector<TileSelection> selectTilesInParallel(const std::vector<SelectionRequest>& requests, uint32_t threads = 0);

// The key of full-resolution sample (x, y) of chart `chart`: seam mates share it.
uint64_t vertexKey(const SurfaceMates& mates, uint32_t chart, uint32_t resolution, uint32_t x, uint32_t y);

// The triangles drawn for one chart's selected tiles (culled tiles too when `withCulled`):
// normalized space, vertices not shared between tiles, counter-clockwise in uv.
LodMesh buildAdaptiveMesh(const std::vector<AdaptiveChart>& charts, const SurfaceMates& mates,
                          const TileSelection& selection, uint32_t chart, bool withCulled = true);

// Distance from p to triangle (a, b, c) (Ericson 2005, "Real-Time Collision Detection",
// 5.1.5); the smallest corner distance for a degenerate triangle.
float pointTriangleDistance(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c);

}  // namespace ngi
