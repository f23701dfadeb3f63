// Adaptive LoD over geometry-image tiles (ngi/adaptive_lod.h): CDLOD's quadtree (Strugar
// 2009) with per-tile error bounds, restricted-quadtree balance and the 4-8 mesh's
// alternating diagonals (Lindstrom et al. 1996; Pajarola 1998), geomorphs after Hoppe 1996.
#include "ngi/adaptive_lod.h"

#include "ngi/tile_bound_code.h"

#include "ngi/error.h"
#include "ngi/fitted_levels.h"
#include "ngi/mip_pyramid.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <exception>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <thread>

namespace ngi {
namespace {

constexpr uint32_t P = kTileQuads;
static_assert(P % 4 == 0, "tile borders must be even lines of the next coarser level");

glm::vec3 safeNormalize(glm::vec3 n) { return glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0, 0, 1); }

uint64_t sampleKey(uint32_t chart, uint32_t x, uint32_t y) { return (uint64_t(chart) << 42) | (uint64_t(y) << 21) | x; }

// Perimeter index of border sample (x, y) of resolution r (the inverse of perimeterSample).
uint32_t perimeterIndex(uint32_t r, uint32_t x, uint32_t y)
{
    if (y == 0) return x;
    if (x == r) return r + y;
    if (y == r) return 3 * r - x;
    return 4 * r - y;
}

}  // namespace

float pointTriangleDistance(glm::vec3 p, glm::vec3 a, glm::vec3 b, glm::vec3 c)
{
    const glm::vec3 ab = b - a, ac = c - a, ap = p - a;
    const float d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) return glm::length(p - a);
    const glm::vec3 bp = p - b;
    const float d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) return glm::length(p - b);
    const float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return glm::length(p - (a + ab * (d1 / (d1 - d3))));
    const glm::vec3 cp = p - c;
    const float d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) return glm::length(p - c);
    const float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return glm::length(p - (a + ac * (d2 / (d2 - d6))));
    const float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
        return glm::length(p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    const float sum = va + vb + vc;
    if (!(sum > 0.0f)) return std::min({glm::length(p - a), glm::length(p - b), glm::length(p - c)});  // degenerate
    return glm::length(p - (a + ab * (vb / sum) + ac * (vc / sum)));
}

namespace {

// The level-k surface (alternating diagonals) at the uv of full-resolution sample (x, y).
glm::vec3 levelSurfaceAt(const GeometryImage& level, uint32_t k, uint32_t x, uint32_t y)
{
    const uint32_t h = 1u << k, last = level.size - 2;
    const uint32_t qx = std::min(x >> k, last), qy = std::min(y >> k, last);
    const float fx = float(x - (qx << k)) / float(h), fy = float(y - (qy << k)) / float(h);
    const glm::vec3 a = level.at(qx, qy), b = level.at(qx + 1, qy);
    const glm::vec3 c = level.at(qx + 1, qy + 1), d = level.at(qx, qy + 1);
    if (((qx + qy) & 1) == 0) {  // a-c
        if (fx >= fy) return a + fx * (b - a) + fy * (c - b);
        return a + fx * (c - d) + fy * (d - a);
    }
    if (fx + fy <= 1.0f) return a + fx * (b - a) + fy * (d - a);  // b-d
    return c + (1.0f - fx) * (d - c) + (1.0f - fy) * (b - c);
}

// Distance from p to the two triangles (alternating diagonals) of quad (qx, qy) of `level`.
float quadDistance(const GeometryImage& level, uint32_t qx, uint32_t qy, glm::vec3 p)
{
    const glm::vec3 a = level.at(qx, qy), b = level.at(qx + 1, qy);
    const glm::vec3 c = level.at(qx + 1, qy + 1), d = level.at(qx, qy + 1);
    if (((qx + qy) & 1) == 0) return std::min(pointTriangleDistance(p, a, b, c), pointTriangleDistance(p, a, c, d));
    return std::min(pointTriangleDistance(p, a, b, d), pointTriangleDistance(p, b, c, d));
}

// An upper bound of the two-sided distance between the full surface and the level-k surface at
// full-resolution sample (x, y): the larger of the sample's distance to the level's triangles
// over its quad and the distance from the level's point at the same uv to the full-resolution
// triangles around the sample. Neither counts samples sliding along the surface (the metrics
// measure point to surface too); both are at most the distance between the two points at the
// same uv, which bounds them cheaply first. `known`: a distance already reached nearby, for
// which only max(known, result) matters: the search over the full-resolution triangles stops
// once it is below max(known, the other direction), which leaves that max exact.
float levelDistance(const GeometryImage& full, const GeometryImage& level, uint32_t k, uint32_t x, uint32_t y,
                    float known)
{
    const glm::vec3 p = full.at(x, y), q = levelSurfaceAt(level, k, x, y);
    const float alongUv = glm::length(p - q);
    if (alongUv <= known) return alongUv;
    const uint32_t last = level.size - 2;
    const float fullToLevel = quadDistance(level, std::min(x >> k, last), std::min(y >> k, last), p);
    const float enough = std::max(known, fullToLevel);
    float levelToFull = alongUv;
    const uint32_t r = full.size - 1;
    // The sample's own quad first (q lies over it most often), then the other three around it.
    const uint32_t x0 = std::min(x, r - 1), y0 = std::min(y, r - 1);
    const uint32_t qxs[2] = {x0, x0 == x ? (x > 0 ? x - 1 : x0) : x0},
                   qys[2] = {y0, y0 == y ? (y > 0 ? y - 1 : y0) : y0};
    for (uint32_t j = 0; j < 2 && levelToFull > enough; ++j)
        for (uint32_t i = 0; i < 2 && levelToFull > enough; ++i) {
            if ((i == 1 && qxs[1] == qxs[0]) || (j == 1 && qys[1] == qys[0])) continue;
            levelToFull = std::min(levelToFull, quadDistance(full, qxs[i], qys[j], q));
        }
    return std::max(fullToLevel, levelToFull);
}

// Max-reduces a square array of n x n values by 2 x 2 blocks.
std::vector<float> reduceMax(const std::vector<float>& fine, uint32_t n)
{
    const uint32_t m = n / 2;
    std::vector<float> coarse(size_t(m) * m);
    for (uint32_t y = 0; y < m; ++y)
        for (uint32_t x = 0; x < m; ++x)
            coarse[size_t(y) * m + x] =
                std::max({fine[size_t(2 * y) * n + 2 * x], fine[size_t(2 * y) * n + 2 * x + 1],
                          fine[size_t(2 * y + 1) * n + 2 * x], fine[size_t(2 * y + 1) * n + 2 * x + 1]});
    return coarse;
}

struct Box {
    glm::vec3 lo{std::numeric_limits<float>::max()}, hi{-std::numeric_limits<float>::max()};
    void add(glm::vec3 p)
    {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    void add(const Box& b)
    {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
};

struct Cone {
    glm::vec3 sum{0.0f};  // area-weighted normal sum
    float halfAngle = 0.0f;
    bool valid = true;
};

}  // namespace

float quantizeMorph(float morph)
{
    const float t = std::isfinite(morph) ? std::clamp(morph, 0.0f, 1.0f) : 0.0f;
    return float(std::lround(t * float(kMorphSteps))) / float(kMorphSteps);
}

TileTree buildTileTree(const SurfacePyramid& pyramid, uint32_t coarsestLevel, uint32_t perimeterLevel)
{
    const uint32_t r = pyramid.fullSize() - 1;
    if (pyramid.fullSize() < 2 || !std::has_single_bit(r) || r < P)
        throw Error("adaptive LoD: a chart's full resolution " + std::to_string(r) +
                    " is not a power of two >= " + std::to_string(P));
    TileTree tree;
    tree.resolution = r;
    tree.levelCount = pyramid.levelCount();
    tree.rootLevel = uint32_t(std::countr_zero(r / P));
    tree.coarsestLevel = std::min(coarsestLevel, tree.levelCount - 1);
    tree.perimeterLevel = std::min(perimeterLevel, tree.coarsestLevel);
    const uint32_t leaves = r / P;
    const GeometryImage& full = pyramid.positions[0];

    // Quad normals, oriented like the normal image (one sign for the whole chart).
    const uint32_t q = r;
    std::vector<glm::vec3> quadNormal(size_t(q) * q);
    double orientation = 0.0;
    for (uint32_t y = 0; y < q; ++y)
        for (uint32_t x = 0; x < q; ++x) {
            const glm::vec3 n =
                0.5f * glm::cross(full.at(x + 1, y + 1) - full.at(x, y), full.at(x, y + 1) - full.at(x + 1, y));
            quadNormal[size_t(y) * q + x] = n;
            orientation += glm::dot(n, pyramid.normals[0].at(x, y));
        }
    const float sign = orientation < 0.0 ? -1.0f : 1.0f;

    // Leaves: boxes, cones and the largest distance to every coarser level.
    const uint32_t topLevel = std::min(tree.rootLevel + 1, tree.levelCount - 1);
    std::vector<std::vector<float>> leafError(topLevel + 1, std::vector<float>(size_t(leaves) * leaves, 0.0f));
    std::vector<Box> boxes(size_t(leaves) * leaves);
    std::vector<Cone> cones(size_t(leaves) * leaves);
    auto measureRow = [&](uint32_t ty) {
        for (uint32_t tx = 0; tx < leaves; ++tx) {
            const size_t t = size_t(ty) * leaves + tx;
            for (uint32_t y = ty * P; y <= ty * P + P; ++y)
                for (uint32_t x = tx * P; x <= tx * P + P; ++x) {
                    const glm::vec3 p = full.at(x, y);
                    boxes[t].add(p);
                    for (uint32_t k = 1; k <= topLevel; ++k)
                        leafError[k][t] = std::max(leafError[k][t],
                                                   levelDistance(full, pyramid.positions[k], k, x, y, leafError[k][t]));
                }
            Cone& cone = cones[t];
            for (uint32_t y = ty * P; y < ty * P + P; ++y)
                for (uint32_t x = tx * P; x < tx * P + P; ++x) cone.sum += sign * quadNormal[size_t(y) * q + x];
            const float length = glm::length(cone.sum);
            cone.valid = length > 0.0f;
            if (cone.valid) {
                const glm::vec3 axis = cone.sum / length;
                float minCos = 1.0f;
                for (uint32_t y = ty * P; y < ty * P + P; ++y)
                    for (uint32_t x = tx * P; x < tx * P + P; ++x) {
                        const glm::vec3 n = sign * quadNormal[size_t(y) * q + x];
                        const float l = glm::length(n);
                        if (l > 0.0f) minCos = std::min(minCos, glm::dot(n / l, axis));
                    }
                cone.halfAngle = std::acos(std::clamp(minCos, -1.0f, 1.0f));
            }
        }
    };
    // Rows of leaves are independent: one thread per core takes rows in turn (the result does
    // not depend on the number of threads).
    {
        std::atomic<uint32_t> nextRow{0};
        auto work = [&] {
            for (uint32_t ty = nextRow++; ty < leaves; ty = nextRow++) measureRow(ty);
        };
        const uint32_t threads = std::min(leaves, std::max(1u, std::thread::hardware_concurrency()));
        std::vector<std::thread> pool;
        for (uint32_t i = 1; i < threads; ++i) pool.emplace_back(work);
        work();
        for (std::thread& t : pool) t.join();
    }

    // Up the tree: level l's tiles from level l - 1's.
    tree.tiles.resize(tree.rootLevel + 1);
    // errorPyramid[k][l]: max distance to level k over the tiles of level l.
    std::vector<std::vector<std::vector<float>>> errorPyramid(topLevel + 1);
    for (uint32_t k = 1; k <= topLevel; ++k) {
        errorPyramid[k].push_back(leafError[k]);
        for (uint32_t l = 1; l <= tree.rootLevel; ++l)
            errorPyramid[k].push_back(reduceMax(errorPyramid[k].back(), leaves >> (l - 1)));
    }
    for (uint32_t l = 0; l <= tree.rootLevel; ++l) {
        const uint32_t n = tree.tilesPerSide(l);
        std::vector<TileBound>& tiles = tree.tiles[l];
        tiles.resize(size_t(n) * n);
        if (l > 0) {
            const uint32_t m = 2 * n;
            std::vector<Box> parentBoxes(size_t(n) * n);
            std::vector<Cone> parentCones(size_t(n) * n);
            for (uint32_t y = 0; y < n; ++y)
                for (uint32_t x = 0; x < n; ++x) {
                    Box& box = parentBoxes[size_t(y) * n + x];
                    Cone& cone = parentCones[size_t(y) * n + x];
                    const size_t children[4] = {size_t(2 * y) * m + 2 * x, size_t(2 * y) * m + 2 * x + 1,
                                                size_t(2 * y + 1) * m + 2 * x, size_t(2 * y + 1) * m + 2 * x + 1};
                    for (size_t c : children) {
                        box.add(boxes[c]);
                        cone.sum += cones[c].sum;
                        cone.valid = cone.valid && cones[c].valid;
                    }
                    const float length = glm::length(cone.sum);
                    cone.valid = cone.valid && length > 0.0f;
                    if (cone.valid) {
                        const glm::vec3 axis = cone.sum / length;
                        for (size_t c : children) {
                            const float between =
                                std::acos(std::clamp(glm::dot(axis, glm::normalize(cones[c].sum)), -1.0f, 1.0f));
                            cone.halfAngle = std::max(cone.halfAngle, between + cones[c].halfAngle);
                        }
                    }
                }
            boxes = std::move(parentBoxes);
            cones = std::move(parentCones);
        }
        for (size_t t = 0; t < tiles.size(); ++t) {
            TileBound& b = tiles[t];
            b.error = l == 0 ? 0.0f : errorPyramid[l][l][t];
            b.errorUp = l + 1 <= topLevel ? errorPyramid[l + 1][l][t] : b.error;
            b.errorUp = std::max(b.errorUp, b.error);
            b.centre = 0.5f * (boxes[t].lo + boxes[t].hi);
            b.radius = 0.5f * glm::length(boxes[t].hi - boxes[t].lo);
            const Cone& cone = cones[t];
            if (cone.valid && cone.halfAngle < 0.5f * std::numbers::pi_v<float>) {
                b.coneAxis = glm::normalize(cone.sum);
                b.coneCos = std::cos(cone.halfAngle);
            } else {
                b.coneCos = -1.0f;
            }
            // What the GPU's selection keeps, so that both decide on the same numbers.
            b = decodeTileBound(encodeTileBound(b));
        }
    }
    return tree;
}

SurfaceMates buildSurfaceMates(const std::vector<AdaptiveChart>& charts,
                               const std::vector<CrossSeamSegment>& crossSeams)
{
    SurfaceMates mates;
    std::vector<std::vector<bool>> matedPerChart;
    std::vector<ChartSeams> seams;
    std::vector<uint32_t> resolutions;
    for (uint32_t c = 0; c < charts.size(); ++c) {
        if (!charts[c].tree) throw Error("adaptive LoD: chart " + std::to_string(c) + " has no tile tree");
        const uint32_t r = charts[c].tree->resolution;
        std::vector<uint64_t>& keys = mates.perimeterKey.emplace_back(size_t(4) * r);
        std::vector<uint32_t> table;
        if (charts[c].seams.matched) table = seamWeldTable(charts[c].seams, r);
        for (uint32_t t = 0; t < 4 * r; ++t) {
            const glm::uvec2 s = perimeterSample(r, table.empty() ? t : table[t]);
            keys[t] = sampleKey(c, s.x, s.y);
        }
        // Closed: every border sample is in a seam segment (or, below, a cross seam).
        std::vector<bool> mated(size_t(4) * r, false);
        if (charts[c].seams.matched)
            for (const SeamSegment& segment : charts[c].seams.segments)
                for (uint32_t i = 0; i <= segment.length; ++i) {
                    mated[(segment.a + i) % (4 * r)] = true;
                    mated[(segment.b + i) % (4 * r)] = true;
                }
        matedPerChart.push_back(std::move(mated));
        seams.push_back(charts[c].seams);
        resolutions.push_back(r);
    }
    for (const CrossSeamSegment& s : crossSeams)
        for (uint32_t i = 0; i <= s.length; ++i) {
            if (s.chartA < charts.size()) matedPerChart[s.chartA][(s.a + i) % matedPerChart[s.chartA].size()] = true;
            if (s.chartB < charts.size()) matedPerChart[s.chartB][(s.b + i) % matedPerChart[s.chartB].size()] = true;
        }
    for (const std::vector<bool>& mated : matedPerChart)
        mates.closed.push_back(std::all_of(mated.begin(), mated.end(), [](bool m) { return m; }));
    if (!crossSeams.empty()) {
        const GroupWeldPlan plan = groupWeldPlan(seams, resolutions, crossSeams, 0);
        for (uint32_t c = 0; c < charts.size(); ++c) {
            for (const glm::uvec2& e : plan.gather[c]) mates.perimeterKey[c][e.x] = (uint64_t(1) << 63) | e.y;
            for (const glm::uvec2& e : plan.scatter[c]) mates.perimeterKey[c][e.x] = (uint64_t(1) << 63) | e.y;
        }
    }
    return mates;
}

uint64_t vertexKey(const SurfaceMates& mates, uint32_t chart, uint32_t resolution, uint32_t x, uint32_t y)
{
    if (x == 0 || y == 0 || x == resolution || y == resolution)
        return mates.perimeterKey[chart][perimeterIndex(resolution, x, y)];
    return sampleKey(chart, x, y);
}

ViewFrustum viewFrustum(const glm::mat4& m)
{
    ViewFrustum f;
    f.gradW = glm::length(glm::vec3(m[0][3], m[1][3], m[2][3]));
    f.rowY = glm::length(glm::vec3(m[0][1], m[1][1], m[2][1]));
    const glm::vec4 row0(m[0][0], m[1][0], m[2][0], m[3][0]), row1(m[0][1], m[1][1], m[2][1], m[3][1]);
    const glm::vec4 row2(m[0][2], m[1][2], m[2][2], m[3][2]), row3(m[0][3], m[1][3], m[2][3], m[3][3]);
    for (const glm::vec4& p : {row3 + row0, row3 - row0, row3 + row1, row3 - row1, row2, row3 - row2}) {
        const float length = glm::length(glm::vec3(p));
        if (length > 0.0f && std::isfinite(length)) f.planes[f.planeCount++] = p / length;
    }
    f.orthographic = m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f;
    return f;
}

void validateAdaptiveView(const AdaptiveView& view)
{
    if (!view.camera) {
        if (!std::isfinite(view.maxError) || !(view.maxError > 0.0f))
            throw Error("the adaptive error bound " + std::to_string(view.maxError) + " is not a finite number > 0");
        return;
    }
    if (!std::isfinite(view.maxErrorPixels) || !(view.maxErrorPixels > 0.0f))
        throw Error("the adaptive pixel error " + std::to_string(view.maxErrorPixels) + " is not a finite number > 0");
    if (!std::isfinite(view.viewportHeight) || !(view.viewportHeight >= 1.0f))
        throw Error("the viewport height " + std::to_string(view.viewportHeight) + " is not a finite number >= 1");
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            if (!std::isfinite(view.clipFromNormalized[i][j])) throw Error("the camera's matrix is not finite");
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(view.eye[i])) throw Error("the camera's eye is not finite");
}

namespace {

class Selector {
public:
    Selector(const std::vector<AdaptiveChart>& charts, const AdaptiveView& view) : charts_(charts), view_(view)
    {
        if (view.camera) frustum_ = viewFrustum(view.clipFromNormalized);
    }

    // How far the tile's sphere lies outside the frustum (normalized units; <= 0: it meets it).
    float outsideFrustum(const TileBound& b) const
    {
        float outside = -std::numeric_limits<float>::infinity();
        for (uint32_t k = 0; k < frustum_.planeCount; ++k) {
            const glm::vec4& plane = frustum_.planes[k];
            outside = std::max(outside, -(glm::dot(glm::vec3(plane), b.centre) + plane.w) - b.radius);
        }
        return outside;
    }

    // Pixels one normalized unit covers at the tile's nearest point. A tile outside the view
    // is measured as if it were at least as far from the eye as it is from the view (its
    // distance outside the frustum as depth): it is never seen, and only its borders reach
    // the visible tiles, so it need not be finer than a tile that far away would be. This
    // is a function of the view alone (culling does not change it) and continuous in it, so a
    // tile turning into view refines and morphs without a pop.
    float pixelsPerUnit(const TileBound& b) const
    {
        if (!view_.camera) return 1.0f;
        const float wCentre = (view_.clipFromNormalized * glm::vec4(b.centre, 1.0f)).w;
        const float wNear = std::max(wCentre - b.radius * frustum_.gradW, frustum_.gradW * outsideFrustum(b));
        if (!(wNear > 0.0f)) return std::numeric_limits<float>::infinity();
        return 0.5f * view_.viewportHeight * frustum_.rowY / wNear;
    }
    float budget() const { return view_.camera ? view_.maxErrorPixels : view_.maxError; }

    static bool touchesPerimeter(const TileTree& tree, uint32_t level, uint32_t x, uint32_t y)
    {
        const uint32_t n = tree.tilesPerSide(level);
        return x == 0 || y == 0 || x + 1 == n || y + 1 == n;
    }
    static uint32_t levelCap(const TileTree& tree, uint32_t level, uint32_t x, uint32_t y)
    {
        return touchesPerimeter(tree, level, x, y) ? tree.perimeterLevel : tree.coarsestLevel;
    }

    bool needsRefinement(const TileTree& tree, uint32_t level, uint32_t x, uint32_t y) const
    {
        if (level == 0) return false;
        if (level > levelCap(tree, level, x, y)) return true;
        const TileBound& b = tree.tile(level, x, y);
        if (b.error <= 0.0f) return false;
        return b.error * pixelsPerUnit(b) > budget();
    }

    float morph(const TileTree& tree, uint32_t level, uint32_t x, uint32_t y) const
    {
        if (!view_.camera) return 0.0f;
        // The parent's level must be one this tile could be replaced by.
        if (level + 1 > levelCap(tree, level, x, y) || level + 1 > tree.rootLevel) return 0.0f;
        const TileBound& b = tree.tile(level, x, y);
        const float ppu = pixelsPerUnit(b);
        if (!(ppu < std::numeric_limits<float>::infinity())) return 0.0f;
        const float allowed = budget() / ppu;
        if (b.errorUp <= allowed) return 1.0f;
        if (!(b.errorUp > b.error)) return 0.0f;
        if (b.error >= allowed) return 0.0f;
        const float t = b.error > 0.0f ? std::log(allowed / b.error) / std::log(b.errorUp / b.error)
                                       : (allowed - b.error) / (b.errorUp - b.error);
        return quantizeMorph(t);
    }

    void visit(uint32_t chart, uint32_t level, uint32_t x, uint32_t y, std::vector<SelectedTile>& out) const
    {
        const TileTree& tree = *charts_[chart].tree;
        if (needsRefinement(tree, level, x, y)) {
            for (uint32_t j = 0; j < 2; ++j)
                for (uint32_t i = 0; i < 2; ++i) visit(chart, level - 1, 2 * x + i, 2 * y + j, out);
            return;
        }
        out.push_back(make(chart, level, x, y));
    }

    SelectedTile make(uint32_t chart, uint32_t level, uint32_t x, uint32_t y) const
    {
        SelectedTile t;
        t.chart = chart;
        t.level = level;
        t.x = x;
        t.y = y;
        t.morph = morph(*charts_[chart].tree, level, x, y);
        return t;
    }

    // Calls f(x, y, odd) for every border vertex of a tile: its full-resolution sample (x, y)
    // (its own level's samples; `odd`: not a sample of the next coarser level).
    template <class F> static void forEachBorderSample(const SelectedTile& t, F&& f)
    {
        const uint32_t x0 = t.x * P, y0 = t.y * P;
        auto visitSample = [&](uint32_t i, uint32_t j) {
            const uint32_t x = x0 + i, y = y0 + j;
            f(x << t.level, y << t.level, ((x | y) & 1) != 0);
        };
        for (uint32_t i = 0; i <= P; ++i) {
            visitSample(i, 0);
            visitSample(i, P);
        }
        for (uint32_t j = 1; j < P; ++j) {
            visitSample(0, j);
            visitSample(P, j);
        }
    }

    // Calls f(x, y) for the midpoint of every border edge of a tile of level > 0 (its
    // full-resolution sample): the sample of the next finer level that a finer neighbour
    // holds there and must drop.
    template <class F> static void forEachBorderMidpointSample(const SelectedTile& t, F&& f)
    {
        if (t.level == 0) return;
        const uint32_t x0 = 2 * t.x * P, y0 = 2 * t.y * P, side = 2 * P, shift = t.level - 1;
        auto visitSample = [&](uint32_t i, uint32_t j) { f((x0 + i) << shift, (y0 + j) << shift); };
        for (uint32_t i = 1; i < side; i += 2) {
            visitSample(i, 0);
            visitSample(i, side);
            visitSample(0, i);
            visitSample(side, i);
        }
    }

    bool cullFrustum(const TileBound& b) const { return outsideFrustum(b) > 0.0f; }

    bool cullBackface(const TileBound& b) const
    {
        if (b.coneCos <= 0.0f) return false;
        const glm::vec3 v = b.centre - view_.eye;
        const float distance = glm::length(v);
        if (!(distance > b.radius)) return false;
        const float between = std::acos(std::clamp(glm::dot(v / distance, b.coneAxis), -1.0f, 1.0f));
        const float cone = std::acos(std::clamp(b.coneCos, -1.0f, 1.0f));
        const float sphere = std::asin(std::clamp(b.radius / distance, 0.0f, 1.0f));
        return between + cone + sphere < 0.5f * std::numbers::pi_v<float>;
    }

    bool orthographic() const { return frustum_.orthographic; }

private:
    const std::vector<AdaptiveChart>& charts_;
    const AdaptiveView& view_;
    ViewFrustum frustum_;
};

}  // namespace

namespace {

bool onPerimeter(uint32_t resolution, uint32_t x, uint32_t y)
{
    return x == 0 || y == 0 || x == resolution || y == resolution;
}

// The later of two holders of a border vertex: the coarser level, the larger morph at one level.
void holdState(BorderState& s, const SelectedTile& t)
{
    if (t.level > s.level)
        s = {t.level, t.morph};
    else if (t.level == s.level)
        s.morph = std::max(s.morph, t.morph);
}

// Each chart's square as a grid of cells of its finest tile's size: the level of the tile
// over each cell, and (after the balance) the tile itself.
struct LevelGrid {
    uint32_t finestLevel = 0, side = 0;
    std::vector<uint8_t> level;
    uint32_t cells(uint32_t tileLevel) const { return 1u << (tileLevel - finestLevel); }
    // Cells of level `finer` (< finestLevel): each cell becomes its four quarters, and so on.
    void refine(uint32_t finer)
    {
        const uint32_t shift = finestLevel - finer, side2 = side << shift;
        std::vector<uint8_t> finerLevels(size_t(side2) * side2);
        for (uint32_t y = 0; y < side2; ++y)
            for (uint32_t x = 0; x < side2; ++x)
                finerLevels[size_t(y) * side2 + x] = level[size_t(y >> shift) * side + (x >> shift)];
        level = std::move(finerLevels);
        side = side2;
        finestLevel = finer;
    }
    void fill(const SelectedTile& t)
    {
        if (t.level < finestLevel) refine(t.level);
        const uint32_t n = cells(t.level), x0 = t.x * n, y0 = t.y * n;
        for (uint32_t y = y0; y < y0 + n; ++y) std::fill_n(level.begin() + size_t(y) * side + x0, n, uint8_t(t.level));
    }
    // The finest level of the tiles around tile t: the cells along its four sides and its corners.
    uint32_t finestAround(const SelectedTile& t) const
    {
        const uint32_t n = cells(t.level);
        const int x0 = int(t.x * n) - 1, y0 = int(t.y * n) - 1, x1 = int(t.x * n + n), y1 = int(t.y * n + n);
        uint32_t finest = t.level;
        auto at = [&](int x, int y) {
            if (x >= 0 && y >= 0 && x < int(side) && y < int(side))
                finest = std::min<uint32_t>(finest, level[size_t(y) * side + x]);
        };
        for (int x = x0; x <= x1; ++x) at(x, y0), at(x, y1);
        for (int y = y0 + 1; y < y1; ++y) at(x0, y), at(x1, y);
        return finest;
    }
};

}  // namespace

TileSelection selectTiles(const std::vector<AdaptiveChart>& charts, const SurfaceMates& mates, const AdaptiveView& view)
{
    validateAdaptiveView(view);
    if (mates.perimeterKey.size() != charts.size()) throw Error("adaptive LoD: the seam mates do not match the charts");
    const Selector selector(charts, view);
    TileSelection selection;
    for (uint32_t c = 0; c < charts.size(); ++c) {
        if (!charts[c].tree || !charts[c].pyramid)
            throw Error("adaptive LoD: chart " + std::to_string(c) + " has no tile tree");
        selector.visit(c, charts[c].tree->rootLevel, 0, 0, selection.tiles);
    }
    // Each chart's grid at its finest tile's level (finer where the balance splits a tile
    // below it, next to a finer chart across a seam).
    std::vector<LevelGrid> grids(charts.size());
    for (LevelGrid& g : grids) g.finestLevel = ~0u;
    for (const SelectedTile& t : selection.tiles)
        grids[t.chart].finestLevel = std::min(grids[t.chart].finestLevel, t.level);
    for (uint32_t c = 0; c < charts.size(); ++c) {
        LevelGrid& g = grids[c];
        g.side = charts[c].tree->tilesPerSide(g.finestLevel);
        g.level.assign(size_t(g.side) * g.side, 0);
    }
    for (const SelectedTile& t : selection.tiles) grids[t.chart].fill(t);
    auto touchesPerimeter = [&](const SelectedTile& t) {
        return Selector::touchesPerimeter(*charts[t.chart].tree, t.level, t.x, t.y);
    };

    // Balance: tiles sharing a vertex (or a seam mate of one) differ by at most one level.
    // Within a chart, the tiles around a tile are read off its grid. On the charts' borders,
    // where seam mates join tiles of other sides and charts, `finest` holds the finest level
    // holding each border vertex (by its key, which mates share). A split tile's children
    // hold every vertex of its border, so adding theirs keeps the map what it would be built anew.
    VertexKeyMap<uint32_t> finest;
    auto holdFinest = [&](const SelectedTile& t) {
        if (!touchesPerimeter(t)) return;
        const uint32_t r = charts[t.chart].tree->resolution;
        selector.forEachBorderSample(t, [&](uint32_t x, uint32_t y, bool) {
            if (!onPerimeter(r, x, y)) return;
            bool inserted;
            uint32_t& level = finest.tryEmplace(vertexKey(mates, t.chart, r, x, y), t.level, inserted);
            level = std::min(level, t.level);
        });
    };
    for (const SelectedTile& t : selection.tiles) holdFinest(t);
    std::vector<SelectedTile> children;
    for (bool changed = true; changed;) {
        changed = false;
        std::vector<SelectedTile> balanced;
        balanced.reserve(selection.tiles.size());
        for (const SelectedTile& t : selection.tiles) {
            bool split = t.level >= 2 && grids[t.chart].finestAround(t) + 1 < t.level;
            if (!split && t.level >= 2 && touchesPerimeter(t)) {
                const uint32_t r = charts[t.chart].tree->resolution;
                selector.forEachBorderSample(t, [&](uint32_t x, uint32_t y, bool) {
                    split =
                        split || (onPerimeter(r, x, y) && finest.at(vertexKey(mates, t.chart, r, x, y)) + 1 < t.level);
                });
            }
            if (!split) {
                balanced.push_back(t);
                continue;
            }
            ++selection.forcedSplits;
            changed = true;
            for (uint32_t j = 0; j < 2; ++j)
                for (uint32_t i = 0; i < 2; ++i) {
                    balanced.push_back(selector.make(t.chart, t.level - 1, 2 * t.x + i, 2 * t.y + j));
                    children.push_back(balanced.back());
                }
        }
        // After the pass, so every tile of it was checked against the same levels.
        for (const SelectedTile& t : children) {
            grids[t.chart].fill(t);
            holdFinest(t);
        }
        children.clear();
        selection.tiles = std::move(balanced);
    }

    // Which tile covers each cell, and one state per border vertex of the charts' borders: the
    // coarsest level holding it (or an edge through it) over it and its mates, the largest
    // morph there. Inside a chart the state is read off the cover (borderState).
    selection.cover.resize(charts.size());
    for (uint32_t c = 0; c < charts.size(); ++c) {
        ChartTileCover& cover = selection.cover[c];
        cover.resolution = charts[c].tree->resolution;
        cover.finestLevel = grids[c].finestLevel;
        cover.side = charts[c].tree->tilesPerSide(cover.finestLevel);
        cover.tiles.assign(size_t(cover.side) * cover.side, 0);
    }
    for (uint32_t k = 0; k < selection.tiles.size(); ++k) {
        const SelectedTile& t = selection.tiles[k];
        ChartTileCover& cover = selection.cover[t.chart];
        const uint32_t n = 1u << (t.level - cover.finestLevel), x0 = t.x * n, y0 = t.y * n;
        for (uint32_t y = y0; y < y0 + n; ++y) std::fill_n(cover.tiles.begin() + size_t(y) * cover.side + x0, n, k);
    }
    auto holdAt = [&](uint64_t key, const SelectedTile& t) {
        bool inserted;
        BorderState& s = selection.perimeterStates.tryEmplace(key, BorderState{t.level, t.morph}, inserted);
        if (!inserted) holdState(s, t);
    };
    for (const SelectedTile& t : selection.tiles) {
        if (!touchesPerimeter(t)) continue;
        const uint32_t r = charts[t.chart].tree->resolution;
        selector.forEachBorderSample(t, [&](uint32_t x, uint32_t y, bool) {
            if (onPerimeter(r, x, y)) holdAt(vertexKey(mates, t.chart, r, x, y), t);
        });
        selector.forEachBorderMidpointSample(t, [&](uint32_t x, uint32_t y) {
            if (onPerimeter(r, x, y)) holdAt(vertexKey(mates, t.chart, r, x, y), t);
        });
    }
    const bool backface = view.camera && view.cull && !selector.orthographic();
    for (SelectedTile& t : selection.tiles) {
        if (view.camera && view.cull) {
            const TileBound& b = charts[t.chart].tree->tile(t.level, t.x, t.y);
            if (selector.cullFrustum(b)) {
                t.culled = true;
                ++selection.culledFrustum;
            } else if (backface && mates.closed[t.chart] && selector.cullBackface(b)) {
                t.culled = true;
                ++selection.culledBackface;
            }
        }
        if (t.culled) continue;
        uint64_t dropped = 0;
        selector.forEachBorderSample(t, [&](uint32_t x, uint32_t y, bool odd) {
            dropped += odd && selection.borderState(mates, t.chart, x, y).level > t.level;
        });
        selection.triangles += 2 * P * P - dropped;
    }
    return selection;
}

BorderState TileSelection::borderState(const SurfaceMates& mates, uint32_t chart, uint32_t x, uint32_t y) const
{
    if (chart >= cover.size()) throw Error("adaptive LoD: no chart " + std::to_string(chart) + " in the selection");
    const ChartTileCover& c = cover[chart];
    if (x > c.resolution || y > c.resolution) throw Error("adaptive LoD: a tile border vertex is outside its chart");
    if (onPerimeter(c.resolution, x, y)) return perimeterStates.at(vertexKey(mates, chart, c.resolution, x, y));
    // Inside the square: the tiles over the cells that meet at the sample (two across a
    // cell side, four at a corner).
    const uint32_t size = P << c.finestLevel, cx = x / size, cy = y / size;
    const bool betweenX = x % size == 0, betweenY = y % size == 0;
    if (!betweenX && !betweenY) throw Error("adaptive LoD: a tile border vertex has no state");
    BorderState s{0, 0.0f};
    bool any = false;
    for (uint32_t j = betweenY ? cy - 1 : cy; j <= cy; ++j)
        for (uint32_t i = betweenX ? cx - 1 : cx; i <= cx; ++i) {
            const SelectedTile& t = tiles[c.tiles[size_t(j) * c.side + i]];
            if (!any)
                s = {t.level, t.morph}, any = true;
            else
                holdState(s, t);
        }
    return s;
}

std::vector<TileSelection> selectTilesInParallel(const std::vector<SelectionRequest>& requests, uint32_t threads)
{
    std::vector<TileSelection> selections(requests.size());
    std::vector<std::exception_ptr> errors(requests.size());
    std::atomic<size_t> next{0};
    auto work = [&] {
        for (size_t k; (k = next.fetch_add(1)) < requests.size();) {
            try {
                const SelectionRequest& r = requests[k];
                if (!r.charts || !r.mates)
                    throw Error("adaptive LoD: selection request " + std::to_string(k) + " has no surface");
                selections[k] = selectTiles(*r.charts, *r.mates, r.view);
            } catch (...) {
                errors[k] = std::current_exception();
            }
        }
    };
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    threads = uint32_t(std::min<size_t>(threads, requests.size()));
    std::vector<std::thread> pool;
    for (uint32_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();  // this thread takes a share too
    for (std::thread& t : pool) t.join();
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
    return selections;
}

LodMesh buildAdaptiveMesh(const std::vector<AdaptiveChart>& charts, const SurfaceMates& mates,
                          const TileSelection& selection, uint32_t chart, bool withCulled)
{
    if (chart >= charts.size() || !charts[chart].pyramid || !charts[chart].tree)
        throw Error("adaptive LoD: no chart " + std::to_string(chart));
    const SurfacePyramid& pyramid = *charts[chart].pyramid;
    const TileTree& tree = *charts[chart].tree;
    auto point = [&](uint32_t level, uint32_t x, uint32_t y, float morph) {
        std::pair<glm::vec3, glm::vec3> v{pyramid.positions[level].at(x, y), pyramid.normals[level].at(x, y)};
        if (morph > 0.0f && level + 1 < pyramid.levelCount()) {
            const auto [p, n] = coarserSurfaceAt(pyramid.positions[level + 1], pyramid.normals[level + 1], x, y);
            v.first = glm::mix(v.first, p, morph);
            v.second = safeNormalize(glm::mix(v.second, n, morph));
        }
        return v;
    };
    LodMesh mesh;
    constexpr uint32_t side = P + 1;
    for (const SelectedTile& t : selection.tiles) {
        if (t.chart != chart || (t.culled && !withCulled)) continue;
        const uint32_t base = uint32_t(mesh.positions.size());
        const uint32_t x0 = t.x * P, y0 = t.y * P;
        uint32_t remap[side * side];
        for (uint32_t j = 0; j <= P; ++j)
            for (uint32_t i = 0; i <= P; ++i) {
                const uint32_t x = x0 + i, y = y0 + j, v = j * side + i;
                remap[v] = v;
                BorderState state{t.level, t.morph};
                if (i == 0 || j == 0 || i == P || j == P)
                    state = selection.borderState(mates, chart, x << t.level, y << t.level);
                std::pair<glm::vec3, glm::vec3> p;
                if (state.level == t.level) {
                    p = point(t.level, x, y, state.morph);
                } else if (((x | y) & 1) == 0) {
                    p = point(state.level, x >> 1, y >> 1, state.morph);
                } else {
                    // An odd vertex on a border drawn one level coarser: its triangles take its
                    // even neighbour along the border (the earlier one), the degenerate one is dropped.
                    remap[v] = (j == 0 || j == P) ? v - 1 : v - side;
                    p = {mesh.positions[base + remap[v]], mesh.normals[base + remap[v]]};
                }
                mesh.positions.push_back(p.first);
                mesh.normals.push_back(p.second);
                mesh.uvs.push_back(glm::vec2(float(x << t.level), float(y << t.level)) / float(tree.resolution));
            }
        auto index = [&](uint32_t i, uint32_t j) { return base + remap[j * side + i]; };
        auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
            if (a != b && b != c && a != c) mesh.triangles.push_back({a, b, c});
        };
        for (uint32_t j = 0; j < P; ++j)
            for (uint32_t i = 0; i < P; ++i) {
                const uint32_t a = index(i, j), b = index(i + 1, j), c = index(i + 1, j + 1), d = index(i, j + 1);
                if (((x0 + i + y0 + j) & 1) == 0) {
                    emit(a, b, c);
                    emit(a, c, d);
                } else {
                    emit(a, b, d);
                    emit(b, c, d);
                }
            }
    }
    return mesh;
}

}  // namespace ngi
