// The adaptive LoD surface (ngi/adaptive_lod.h) over fitted coarse levels (fitted_levels.h),
// as the engine draws it: its bound, its watertightness across tiles and seams, its continuity
// under camera motion, determinism and bad views; what fitting the levels gains and keeps.
#include "ngi/adaptive_lod.h"

#include "ngi/analytic_surfaces.h"
#include "ngi/error.h"
#include "ngi/fitted_levels.h"
#include "ngi/lod_grid.h"
#include "ngi/mip_pyramid.h"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <random>
#include <tuple>

namespace ngi {
namespace {

// One analytic chart with its pyramid, tree and mates, built once per surface.
struct AdaptiveFixture {
    AnalyticSurface surface;
    SurfacePyramid pyramid;
    TileTree tree;
    std::vector<AdaptiveChart> charts;
    SurfaceMates mates;

    // `fitted`: the coarse levels fitted to the full surface, as the engine draws them
    // (fitted_levels.h); false: the nested subsamples.
    explicit AdaptiveFixture(AnalyticSurface s, bool fitted = true) : surface(std::move(s))
    {
        pyramid = buildSurfacePyramid(surface.positions, surface.normals);
        if (fitted) fitCoarseLevels(pyramid);
        const uint32_t coarsest = coarsestDrawnLevel(surface.seams, pyramid.levelCount());
        tree = buildTileTree(pyramid, coarsest, coarsest);
        charts.push_back({&pyramid, &tree, surface.seams});
        mates = buildSurfaceMates(charts, {});
    }
    TileSelection select(const AdaptiveView& view) const { return selectTiles(charts, mates, view); }
    LodMesh mesh(const TileSelection& s) const { return buildAdaptiveMesh(charts, mates, s, 0); }
};

const AdaptiveFixture& torus()
{
    static const AdaptiveFixture f(rippledTorusGeometryImage(129, 0.08f));
    return f;
}
const AdaptiveFixture& sphere()
{
    static const AdaptiveFixture f(sphereGeometryImage(129));
    return f;
}

// The drawn surface at every full-resolution sample, found through the triangles' grid uv
// (NaN where no triangle covers the sample: a hole in the parameter domain).
std::vector<glm::vec3> surfaceAtSamples(const LodMesh& mesh, uint32_t resolution)
{
    const uint32_t n = resolution + 1;
    std::vector<glm::vec3> at(size_t(n) * n, glm::vec3(std::numeric_limits<float>::quiet_NaN()));
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::vec2 a = mesh.uvs[t.x] * float(resolution), b = mesh.uvs[t.y] * float(resolution);
        const glm::vec2 c = mesh.uvs[t.z] * float(resolution);
        const float area = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if (area == 0.0f) continue;
        const int x0 = int(std::floor(std::min({a.x, b.x, c.x}))), x1 = int(std::ceil(std::max({a.x, b.x, c.x})));
        const int y0 = int(std::floor(std::min({a.y, b.y, c.y}))), y1 = int(std::ceil(std::max({a.y, b.y, c.y})));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const glm::vec2 p{float(x), float(y)};
                const float wa = ((b.x - p.x) * (c.y - p.y) - (c.x - p.x) * (b.y - p.y)) / area;
                const float wb = ((c.x - p.x) * (a.y - p.y) - (a.x - p.x) * (c.y - p.y)) / area;
                const float wc = 1.0f - wa - wb;
                if (wa < -1e-6f || wb < -1e-6f || wc < -1e-6f) continue;
                at[size_t(y) * n + x] = wa * mesh.positions[t.x] + wb * mesh.positions[t.y] + wc * mesh.positions[t.z];
            }
    }
    return at;
}

// For every full-resolution sample, its distance to the drawn triangles over its uv cell (those
// whose uv box, widened by one cell, holds the sample): an upper bound of its distance to the
// drawn surface. NaN where no triangle is near (a hole in the parameter domain).
std::vector<float> distanceToDrawn(const LodMesh& mesh, const GeometryImage& full)
{
    const uint32_t n = full.size, resolution = n - 1;
    std::vector<float> best(size_t(n) * n, std::numeric_limits<float>::quiet_NaN());
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::vec2 a = mesh.uvs[t.x] * float(resolution), b = mesh.uvs[t.y] * float(resolution);
        const glm::vec2 c = mesh.uvs[t.z] * float(resolution);
        const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))) - 1);
        const int x1 = std::min(int(resolution), int(std::ceil(std::max({a.x, b.x, c.x}))) + 1);
        const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}))) - 1);
        const int y1 = std::min(int(resolution), int(std::ceil(std::max({a.y, b.y, c.y}))) + 1);
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                float& d = best[size_t(y) * n + x];
                const float e =
                    pointTriangleDistance(full.at(x, y), mesh.positions[t.x], mesh.positions[t.y], mesh.positions[t.z]);
                if (!(d <= e)) d = e;
            }
    }
    return best;
}

// The largest distance from a drawn triangle's centroid to the full surface's triangles (the
// alternating split of its full-resolution quads) within two cells of the centroid's uv: an
// upper bound of the drawn -> full direction of the bound, sampled at the centroids.
float centroidDistanceToFull(const LodMesh& mesh, const GeometryImage& full)
{
    const int r = int(full.size) - 1;
    float worst = 0.0f;
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::vec3 c = (mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) / 3.0f;
        const glm::vec2 uv = (mesh.uvs[t.x] + mesh.uvs[t.y] + mesh.uvs[t.z]) / 3.0f * float(r);
        float best = std::numeric_limits<float>::max();
        for (int qy = std::max(0, int(uv.y) - 2); qy <= std::min(r - 1, int(uv.y) + 2); ++qy)
            for (int qx = std::max(0, int(uv.x) - 2); qx <= std::min(r - 1, int(uv.x) + 2); ++qx) {
                const glm::vec3 a = full.at(qx, qy), b = full.at(qx + 1, qy), cc = full.at(qx + 1, qy + 1),
                                d = full.at(qx, qy + 1);
                if (((qx + qy) & 1) == 0)
                    best = std::min({best, pointTriangleDistance(c, a, b, cc), pointTriangleDistance(c, a, cc, d)});
                else
                    best = std::min({best, pointTriangleDistance(c, a, b, d), pointTriangleDistance(c, b, cc, d)});
            }
        worst = std::max(worst, best);
    }
    return worst;
}

// Edges used by other than two triangles after welding bitwise-equal positions.
size_t openEdges(const LodMesh& mesh)
{
    std::map<std::tuple<float, float, float>, uint32_t> weld;
    std::vector<uint32_t> id(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        const glm::vec3& p = mesh.positions[v];
        id[v] = weld.try_emplace({p.x, p.y, p.z}, uint32_t(weld.size())).first->second;
    }
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    for (const glm::uvec3& t : mesh.triangles) {
        const uint32_t v[3] = {id[t.x], id[t.y], id[t.z]};
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = v[e], b = v[(e + 1) % 3];
            if (a != b) ++edges[{std::min(a, b), std::max(a, b)}];
        }
    }
    size_t open = 0;
    for (const auto& [edge, count] : edges) open += count != 2;
    return open;
}

AdaptiveView objectSpace(float maxError)
{
    AdaptiveView view;
    view.maxError = maxError;
    return view;
}

AdaptiveView cameraAt(glm::vec3 eye, float maxErrorPixels, bool cull = false)
{
    AdaptiveView view;
    view.camera = true;
    view.eye = eye;
    view.viewportHeight = 720.0f;
    view.maxErrorPixels = maxErrorPixels;
    view.cull = cull;
    glm::mat4 projection = glm::perspectiveRH_ZO(glm::radians(45.0f), 1280.0f / 720.0f, 0.01f, 100.0f);
    projection[1][1] *= -1.0f;
    view.clipFromNormalized = projection * glm::lookAtRH(eye, glm::vec3(0.5f), glm::vec3(0, 1, 0));
    return view;
}

TEST(AdaptiveLod, TileBoundsAreMonotoneUpTheTree)
{
    const TileTree& tree = torus().tree;
    ASSERT_EQ(tree.rootLevel, 5u);  // 128 cells / 4 quads per tile
    for (uint32_t l = 1; l <= tree.rootLevel; ++l)
        for (uint32_t y = 0; y < tree.tilesPerSide(l); ++y)
            for (uint32_t x = 0; x < tree.tilesPerSide(l); ++x) {
                const TileBound& parent = tree.tile(l, x, y);
                EXPECT_GE(parent.errorUp, parent.error);
                for (uint32_t j = 0; j < 2; ++j)
                    for (uint32_t i = 0; i < 2; ++i) {
                        const TileBound& child = tree.tile(l - 1, 2 * x + i, 2 * y + j);
                        EXPECT_LE(child.errorUp, parent.error + 1e-7f);
                    }
            }
}

TEST(AdaptiveLod, EveryTileSphereHoldsItsSamples)
{
    const AdaptiveFixture& f = torus();
    for (uint32_t l = 0; l <= f.tree.rootLevel; ++l)
        for (uint32_t ty = 0; ty < f.tree.tilesPerSide(l); ++ty)
            for (uint32_t tx = 0; tx < f.tree.tilesPerSide(l); ++tx) {
                const TileBound& b = f.tree.tile(l, tx, ty);
                const uint32_t span = kTileQuads << l;
                for (uint32_t y = ty * span; y <= (ty + 1) * span; ++y)
                    for (uint32_t x = tx * span; x <= (tx + 1) * span; ++x)
                        ASSERT_LE(glm::length(f.surface.positions.at(x, y) - b.centre), b.radius * 1.0001f + 1e-6f)
                            << "level " << l << " tile " << tx << "," << ty;
            }
}

TEST(AdaptiveLod, ObjectSpaceBoundHoldsAtEveryFullResolutionSample)
{
    for (const AdaptiveFixture* f : {&torus(), &sphere()})
        for (float bound : {0.002f, 0.01f, 0.04f}) {
            const TileSelection s = f->select(objectSpace(bound));
            const LodMesh mesh = f->mesh(s);
            // The parameter domain is covered: every sample's uv lies in a drawn triangle.
            const std::vector<glm::vec3> drawn = surfaceAtSamples(mesh, f->tree.resolution);
            for (size_t i = 0; i < drawn.size(); ++i)
                ASSERT_FALSE(std::isnan(drawn[i].x)) << "sample " << i << " is not covered at bound " << bound;
            float worst = 0.0f;
            for (float d : distanceToDrawn(mesh, f->surface.positions)) worst = std::max(worst, d);
            EXPECT_LE(worst, bound * 1.0001f) << "bound " << bound;
            EXPECT_GT(worst, bound * 0.2f) << "bound " << bound;  // the selection uses what it may
            EXPECT_LE(centroidDistanceToFull(mesh, f->surface.positions), bound * 1.0001f) << "bound " << bound;
            EXPECT_EQ(mesh.triangles.size(), s.triangles);
        }
}

TEST(AdaptiveLod, LooserBoundsDrawFewerTrianglesThanTheUniformLevelOfTheSameError)
{
    const AdaptiveFixture& f = torus();
    uint64_t previous = std::numeric_limits<uint64_t>::max();
    for (float bound : {0.001f, 0.004f, 0.016f}) {
        const TileSelection s = f.select(objectSpace(bound));
        EXPECT_LT(s.triangles, previous);
        previous = s.triangles;
        // The uniform level meeting the same bound everywhere: the finest level any tile needs.
        uint32_t finest = 99;
        for (const SelectedTile& t : s.tiles) finest = std::min(finest, t.level);
        EXPECT_LE(s.triangles, gridTriangleCount(mipLevelSize(129, finest)));
    }
}

TEST(AdaptiveLod, ClosedSurfacesStayWatertightForRandomCameras)
{
    std::mt19937 random(7);
    std::uniform_real_distribution<float> angle(0.0f, 6.2831853f), distance(0.7f, 6.0f), pixels(0.3f, 8.0f);
    for (const AdaptiveFixture* f : {&torus(), &sphere()}) {
        ASSERT_EQ(openEdges(buildLodMesh(f->pyramid, 0.0f)), 0u);
        for (int i = 0; i < 12; ++i) {
            const float a = angle(random), b = 0.5f * angle(random) - 1.5f, d = distance(random);
            const glm::vec3 eye =
                glm::vec3(0.5f) + d * glm::vec3(std::cos(a) * std::cos(b), std::sin(b), std::sin(a) * std::cos(b));
            const TileSelection s = f->select(cameraAt(eye, pixels(random)));
            EXPECT_EQ(openEdges(f->mesh(s)), 0u) << "camera " << i << ", " << s.tiles.size() << " tiles";
        }
        for (float bound : {0.0005f, 0.003f, 0.02f, 0.2f})
            EXPECT_EQ(openEdges(f->mesh(f->select(objectSpace(bound)))), 0u) << "bound " << bound;
    }
}

TEST(AdaptiveLod, NearTilesAreFinerThanFarTiles)
{
    const AdaptiveFixture& f = torus();
    const glm::vec3 eye(0.5f, 0.5f, -0.4f);
    const TileSelection s = f.select(cameraAt(eye, 1.0f));
    float nearLevel = 0, farLevel = 0, nearest = 1e9f, farthest = 0;
    for (const SelectedTile& t : s.tiles) {
        const float d = glm::length(f.tree.tile(t.level, t.x, t.y).centre - eye);
        if (d < nearest) nearest = d, nearLevel = float(t.level) + t.morph;
        if (d > farthest) farthest = d, farLevel = float(t.level) + t.morph;
    }
    EXPECT_LT(nearLevel, farLevel);
}

TEST(AdaptiveLod, SmallCameraMotionMovesTheSurfaceLittle)
{
    const AdaptiveFixture& f = torus();
    const uint32_t r = f.tree.resolution;
    glm::vec3 eye(0.5f, 1.2f, 2.5f);
    std::vector<glm::vec3> previous = surfaceAtSamples(f.mesh(f.select(cameraAt(eye, 2.0f))), r);
    float worst = 0.0f;
    for (int step = 0; step < 200; ++step) {
        eye.z -= 0.01f;  // towards the surface: tiles refine and morph
        const std::vector<glm::vec3> now = surfaceAtSamples(f.mesh(f.select(cameraAt(eye, 2.0f))), r);
        for (size_t i = 0; i < now.size(); ++i) worst = std::max(worst, glm::length(now[i] - previous[i]));
        previous = now;
    }
    // A step of 0.01 (1% of the size) moves no point of the surface by more than 0.2% of it.
    EXPECT_LT(worst, 0.002f);
}

TEST(AdaptiveLod, SelectionIsDeterministic)
{
    const AdaptiveFixture& f = torus();
    const AdaptiveView view = cameraAt(glm::vec3(1.3f, 0.9f, 1.7f), 1.5f, true);
    const TileSelection a = f.select(view), b = f.select(view);
    ASSERT_EQ(a.tiles.size(), b.tiles.size());
    for (size_t i = 0; i < a.tiles.size(); ++i) {
        const SelectedTile &s = a.tiles[i], &t = b.tiles[i];
        EXPECT_EQ(std::tie(s.chart, s.level, s.x, s.y, s.morph, s.culled),
                  std::tie(t.chart, t.level, t.x, t.y, t.morph, t.culled));
    }
    EXPECT_EQ(a.triangles, b.triangles);
}

TEST(AdaptiveLod, SelectionsInParallelAreTheSelectionsOneByOne)
{
    std::mt19937 random(11);
    std::uniform_real_distribution<float> angle(0.0f, 6.2831853f), distance(0.3f, 6.0f), pixels(0.3f, 8.0f);
    std::vector<SelectionRequest> requests;
    for (int i = 0; i < 24; ++i) {
        const AdaptiveFixture& f = i % 2 ? torus() : sphere();
        const float a = angle(random), d = distance(random);
        const glm::vec3 eye = glm::vec3(0.5f) + d * glm::vec3(std::cos(a), 0.3f, std::sin(a));
        requests.push_back({&f.charts, &f.mates, cameraAt(eye, pixels(random), i % 3 == 0)});
    }
    for (const uint32_t threads : {0u, 1u, 3u, 64u}) {
        const std::vector<TileSelection> all = selectTilesInParallel(requests, threads);
        ASSERT_EQ(all.size(), requests.size());
        for (size_t k = 0; k < requests.size(); ++k) {
            const TileSelection one = selectTiles(*requests[k].charts, *requests[k].mates, requests[k].view);
            ASSERT_EQ(all[k].tiles.size(), one.tiles.size()) << "request " << k << ", " << threads << " threads";
            for (size_t i = 0; i < one.tiles.size(); ++i) {
                const SelectedTile &s = all[k].tiles[i], &t = one.tiles[i];
                EXPECT_EQ(std::tie(s.chart, s.level, s.x, s.y, s.morph, s.culled),
                          std::tie(t.chart, t.level, t.x, t.y, t.morph, t.culled));
            }
            EXPECT_EQ(all[k].triangles, one.triangles);
        }
    }
    // The first bad request's error, after the others ran.
    requests[5].view.maxErrorPixels = std::nanf("");
    requests[9].mates = nullptr;
    try {
        selectTilesInParallel(requests, 4);
        ADD_FAILURE() << "a NaN budget was selected";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("pixel error"), std::string::npos) << e.what();
    }
    requests[5].view.maxErrorPixels = 1.0f;
    EXPECT_THROW(selectTilesInParallel(requests, 4), Error);
    EXPECT_TRUE(selectTilesInParallel({}, 4).empty());
}

TEST(AdaptiveLod, TilesOutsideTheViewAreNoFinerThanTheirDistanceFromItNeeds)
{
    // From inside the torus' hole, looking along +x: most of the surface is beside or behind
    // the eye. Measured from the eye alone, the tiles just behind it would be refined to level 0.
    const AdaptiveFixture& f = torus();
    AdaptiveView view = cameraAt(glm::vec3(0.5f), 4.0f, true);
    glm::mat4 projection = glm::perspectiveRH_ZO(glm::radians(45.0f), 1280.0f / 720.0f, 0.01f, 100.0f);
    projection[1][1] *= -1.0f;
    view.clipFromNormalized =
        projection * glm::lookAtRH(glm::vec3(0.5f), glm::vec3(1.5f, 0.5f, 0.5f), glm::vec3(0, 1, 0));
    const TileSelection s = f.select(view);
    ASSERT_GT(s.culledFrustum, 0u);
    // Tiles wholly behind the eye by more than 0.25 (an infinite projected error by the eye
    // alone: level 0) are measured as 0.25 or more away: coarser than level 0 at 4 pixels,
    // but for the few the balance splits next to finer ones (at most a tenth).
    const glm::mat4& m = view.clipFromNormalized;
    const glm::vec4 rowW(m[0][3], m[1][3], m[2][3], m[3][3]);
    const float gradW = glm::length(glm::vec3(rowW));
    uint32_t behind = 0, finest = 0;
    for (const SelectedTile& t : s.tiles) {
        const TileBound& b = f.tree.tile(t.level, t.x, t.y);
        if (glm::dot(rowW, glm::vec4(b.centre, 1.0f)) + b.radius * gradW < -0.25f * gradW) {
            ++behind;
            EXPECT_TRUE(t.culled);
            finest += t.level == 0;
        }
    }
    EXPECT_GT(behind, 10u);
    EXPECT_LE(finest * 10, behind) << finest << " of " << behind << " tiles behind the eye at level 0";
    // The selection stays watertight and independent of culling.
    EXPECT_EQ(openEdges(f.mesh(s)), 0u);
    view.cull = false;
    const TileSelection all = f.select(view);
    ASSERT_EQ(all.tiles.size(), s.tiles.size());
    for (size_t i = 0; i < s.tiles.size(); ++i)
        EXPECT_EQ(std::tie(all.tiles[i].level, all.tiles[i].morph), std::tie(s.tiles[i].level, s.tiles[i].morph));
}

TEST(AdaptiveLod, CullingMarksOnlyTilesOutsideTheViewOrFacingAway)
{
    const AdaptiveFixture& f = sphere();
    const glm::vec3 eye(0.5f, 0.5f, 3.0f);
    const TileSelection all = f.select(cameraAt(eye, 1.0f, false));
    const TileSelection culled = f.select(cameraAt(eye, 1.0f, true));
    ASSERT_EQ(all.tiles.size(), culled.tiles.size());  // culling never changes the selection
    EXPECT_GT(culled.culledBackface, 0u);
    EXPECT_LT(culled.triangles, all.triangles);
    for (const SelectedTile& t : culled.tiles) {
        if (!t.culled) continue;
        // A culled tile of the sphere faces away: its centre is on the far hemisphere.
        EXPECT_LT(f.tree.tile(t.level, t.x, t.y).centre.z, 0.5f + 0.1f);
    }
}

TEST(AdaptiveLod, AnOpenSurfaceSeenFromBehindIsNotCulledByItsNormals)
{
    // A curved open sheet (no seam: its border is a boundary): ngi draws both sides.
    AnalyticSurface sheet;
    sheet.positions = GeometryImage(65);
    sheet.normals = GeometryImage(65);
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const float u = float(x) / 64.0f, v = float(y) / 64.0f;
            sheet.positions.at(x, y) = glm::vec3(u, v, 0.2f * (u - 0.5f) * (u - 0.5f));
            sheet.normals.at(x, y) = glm::normalize(glm::vec3(-0.4f * (u - 0.5f), 0.0f, 1.0f));
        }
    const AdaptiveFixture open(sheet);
    ASSERT_FALSE(open.mates.closed[0]);
    ASSERT_TRUE(sphere().mates.closed[0]);
    const TileSelection behind = open.select(cameraAt(glm::vec3(0.5f, 0.5f, -1.5f), 1.0f, true));
    EXPECT_EQ(behind.culledBackface, 0u);
    const TileSelection all = open.select(cameraAt(glm::vec3(0.5f, 0.5f, -1.5f), 1.0f, false));
    EXPECT_EQ(behind.triangles, all.triangles);
}

TEST(AdaptiveLod, TheBalanceAcrossACrossSeamSplitsTheCoarserChartBelowItsOwnFinestTiles)
{
    // Two charts of one surface meet along A's right side and B's left side: A ripples next
    // to the seam, B is flat (its own tiles all want the coarsest level). The balance across
    // the seam must split B's tiles there below the finest level B chose alone.
    constexpr uint32_t r = 128;
    AnalyticSurface a, b;
    for (AnalyticSurface* s : {&a, &b}) s->positions = s->normals = GeometryImage(r + 1);
    for (uint32_t y = 0; y <= r; ++y)
        for (uint32_t x = 0; x <= r; ++x) {
            const float u = float(x) / float(r), v = float(y) / float(r);
            const float ripple = x == r ? 0.0f : 0.01f * std::sin(60.0f * u) * std::sin(60.0f * v) * u * u;
            a.positions.at(x, y) = glm::vec3(u, v, ripple);
            b.positions.at(x, y) = glm::vec3(1.0f + u, v, 0.0f);
            a.normals.at(x, y) = b.normals.at(x, y) = glm::vec3(0.0f, 0.0f, 1.0f);
        }
    SurfacePyramid pa = buildSurfacePyramid(a.positions, a.normals), pb = buildSurfacePyramid(b.positions, b.normals);
    const uint32_t coarsest = pa.levelCount() - 1;
    const TileTree ta = buildTileTree(pa, coarsest, coarsest), tb = buildTileTree(pb, coarsest, coarsest);
    ChartSeams seams;  // no seam of their own; the cross seam ends on the square's corners
    seams.matched = true;
    seams.coarsestWatertightLevel = coarsest;
    const std::vector<AdaptiveChart> charts = {{&pa, &ta, seams}, {&pb, &tb, seams}};
    // A:r + i (its right side, upwards) is B:3r + r - i (its left side, upwards).
    const SurfaceMates mates = buildSurfaceMates(charts, {{0, r, 1, 3 * r, r}});
    AdaptiveView view;
    view.maxError = 2e-4f;
    const TileSelection s = selectTiles(charts, mates, view);
    uint32_t finestA = 99, finestB = 99, coarsestB = 0;
    for (const SelectedTile& t : s.tiles) {
        (t.chart == 0 ? finestA : finestB) = std::min(t.chart == 0 ? finestA : finestB, t.level);
        if (t.chart == 1) coarsestB = std::max(coarsestB, t.level);
    }
    ASSERT_LE(finestA + 2, coarsestB) << "A is much finer than B's flat interior";
    EXPECT_EQ(finestB, finestA + 1) << "B's tiles on the seam are one level coarser than A's";
    ASSERT_GT(s.forcedSplits, 0u);
    // Every tile border vertex has a state, B's seam tiles stitch to A's: the two charts
    // together are one closed strip along the seam (no open edge but the outer border).
    LodMesh both = buildAdaptiveMesh(charts, mates, s, 0);
    const LodMesh meshB = buildAdaptiveMesh(charts, mates, s, 1);
    const uint32_t base = uint32_t(both.positions.size());
    both.positions.insert(both.positions.end(), meshB.positions.begin(), meshB.positions.end());
    for (const glm::uvec3& t : meshB.triangles) both.triangles.push_back(t + glm::uvec3(base));
    size_t onSeam = 0;
    std::map<std::pair<std::tuple<float, float, float>, std::tuple<float, float, float>>, int> edges;
    for (const glm::uvec3& t : both.triangles)
        for (int e = 0; e < 3; ++e) {
            glm::vec3 p = both.positions[t[e]], q = both.positions[t[(e + 1) % 3]];
            if (std::tie(p.x, p.y, p.z) > std::tie(q.x, q.y, q.z)) std::swap(p, q);
            ++edges[{{p.x, p.y, p.z}, {q.x, q.y, q.z}}];
        }
    for (const auto& [edge, count] : edges) {
        const auto& [p, q] = edge;
        const bool seam = std::get<0>(p) == 1.0f && std::get<0>(q) == 1.0f;
        if (seam) {
            ++onSeam;
            EXPECT_EQ(count, 2) << "an open edge on the seam";
        }
    }
    EXPECT_GT(onSeam, 0u);
}

TEST(AdaptiveLod, BadViewsAreOneClearError)
{
    const AdaptiveFixture& f = torus();
    for (float bad : {0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
        EXPECT_THROW(f.select(objectSpace(bad)), Error);
        EXPECT_THROW(f.select(cameraAt(glm::vec3(2.0f), bad)), Error);
    }
    AdaptiveView view = cameraAt(glm::vec3(2.0f), 1.0f);
    view.viewportHeight = 0.0f;
    EXPECT_THROW(f.select(view), Error);
}

}  // namespace
}  // namespace ngi

namespace ngi {
namespace {

// The largest tile error of each level of a tree.
std::vector<float> worstErrorPerLevel(const TileTree& tree)
{
    std::vector<float> worst;
    for (const std::vector<TileBound>& level : tree.tiles) {
        float w = 0.0f;
        for (const TileBound& t : level) w = std::max(w, t.error);
        worst.push_back(w);
    }
    return worst;
}

TEST(FittedLevels, ApproximateCurvedSurfacesCloserAndMeetABoundWithFewerTriangles)
{
    for (const AnalyticSurface& s : {rippledTorusGeometryImage(129, 0.08f), sphereGeometryImage(129)}) {
        const AdaptiveFixture nested(s, false), fitted(s, true);
        const std::vector<float> a = worstErrorPerLevel(nested.tree), b = worstErrorPerLevel(fitted.tree);
        for (size_t l = 2; l < a.size(); ++l) {
            std::printf("level %zu: worst tile error nested %.5f fitted %.5f (%.2fx)\n", l, a[l], b[l], b[l] / a[l]);
            // The root level (5 x 5 samples, 16 of them on the fixed border) gains least.
            EXPECT_LT(b[l], (l + 1 < a.size() ? 0.75f : 0.95f) * a[l]) << "level " << l;
        }
        for (float bound : {0.002f, 0.005f, 0.01f}) {
            AdaptiveView view;
            view.maxError = bound;
            const uint64_t n = nested.select(view).triangles, f = fitted.select(view).triangles;
            std::printf("bound %.3f: %llu triangles nested, %llu fitted\n", bound, (unsigned long long)n,
                        (unsigned long long)f);
            EXPECT_LE(f, n) << "bound " << bound;
        }
    }
}

TEST(FittedLevels, KeepLevel0AndTheBorderAndReproducePlanes)
{
    const AnalyticSurface torus = rippledTorusGeometryImage(65, 0.08f);
    const SurfacePyramid nested = buildSurfacePyramid(torus.positions, torus.normals);
    SurfacePyramid fitted = nested;
    fitCoarseLevels(fitted);
    EXPECT_EQ(std::memcmp(fitted.positions[0].texels.data(), nested.positions[0].texels.data(),
                          nested.positions[0].texels.size() * sizeof(glm::vec3)),
              0);
    size_t moved = 0;
    for (uint32_t l = 1; l < nested.levelCount(); ++l) {
        const uint32_t n = nested.positions[l].size;
        EXPECT_EQ(
            std::memcmp(fitted.normals[l].texels.data(), nested.normals[l].texels.data(), n * n * sizeof(glm::vec3)),
            0);
        for (uint32_t y = 0; y < n; ++y)
            for (uint32_t x = 0; x < n; ++x) {
                const glm::vec3 a = nested.positions[l].at(x, y), b = fitted.positions[l].at(x, y);
                if (x == 0 || y == 0 || x + 1 == n || y + 1 == n)
                    EXPECT_EQ(std::memcmp(&a, &b, sizeof a), 0)
                        << "border sample " << x << "," << y << " of level " << l;
                else
                    moved += a != b;
            }
    }
    EXPECT_GT(moved, 0u);
    // A plane with an affine parameterization is its own best fit at every level.
    GeometryImage plane(65), up(65);
    for (uint32_t y = 0; y < 65; ++y)
        for (uint32_t x = 0; x < 65; ++x) {
            const float u = float(x) / 64.0f, v = float(y) / 64.0f;
            plane.at(x, y) = glm::vec3(0.1f + 0.8f * u, 0.2f + 0.5f * v, 0.3f * u + 0.2f * v);
            up.at(x, y) = glm::vec3(0, 0, 1);
        }
    const SurfacePyramid flat = buildSurfacePyramid(plane, up);
    SurfacePyramid flatFitted = flat;
    fitCoarseLevels(flatFitted);
    for (uint32_t l = 1; l < flat.levelCount(); ++l)
        for (size_t i = 0; i < flat.positions[l].texels.size(); ++i)
            EXPECT_LT(glm::distance(flat.positions[l].texels[i], flatFitted.positions[l].texels[i]), 1e-6f)
                << "level " << l;
}

TEST(FittedLevels, TheGeomorphTargetIsTheCoarserSurfaceAtTheSamplesUv)
{
    SurfacePyramid p = buildSurfacePyramid(sphereGeometryImage(33).positions, sphereGeometryImage(33).normals);
    fitCoarseLevels(p);
    const GeometryImage& fine = p.positions[1];
    const GeometryImage& coarse = p.positions[2];
    // Even samples go to their coarser sample, edge midpoints to the coarser edge's midpoint,
    // quad centres to the midpoint of the diagonal the alternating split draws.
    EXPECT_EQ(coarserSurfaceAt(coarse, p.normals[2], 4, 6).first, coarse.at(2, 3));
    EXPECT_LT(
        glm::distance(coarserSurfaceAt(coarse, p.normals[2], 5, 6).first, 0.5f * (coarse.at(2, 3) + coarse.at(3, 3))),
        1e-6f);
    // Quad (2, 3): 2 + 3 odd, split along b-d.
    EXPECT_LT(
        glm::distance(coarserSurfaceAt(coarse, p.normals[2], 5, 7).first, 0.5f * (coarse.at(3, 3) + coarse.at(2, 4))),
        1e-6f);
    // Quad (2, 2): even, split along a-c.
    EXPECT_LT(
        glm::distance(coarserSurfaceAt(coarse, p.normals[2], 5, 5).first, 0.5f * (coarse.at(2, 2) + coarse.at(3, 3))),
        1e-6f);
    // The last sample of a row lies on the coarser level's last column.
    EXPECT_EQ(coarserSurfaceAt(coarse, p.normals[2], fine.size - 1, 4).first, coarse.at(coarse.size - 1, 2));
}

}  // namespace
}  // namespace ngi
