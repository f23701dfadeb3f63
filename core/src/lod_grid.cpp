// The drawn LoD surface on the CPU; shaders/surface.vert and shaders/morph_targets.comp are
// its GPU mirror. Geomorphing after Hoppe 1996 ("Progressive Meshes", section 4.2) applied
// to nested geometry-image grids (Gu, Gortler, Hoppe 2002).
#include "ngi/lod_grid.h"

#include "ngi/error.h"
#include "ngi/mip_pyramid.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace ngi {
namespace {

glm::vec3 safeNormalize(glm::vec3 n) { return glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0, 0, 1); }

struct Vertex {
    glm::vec3 position, normal;
};

Vertex morphedVertex(const SurfacePyramid& p, uint32_t level, float morph, uint32_t x, uint32_t y)
{
    Vertex v{p.positions[level].at(x, y), p.normals[level].at(x, y)};
    if (morph > 0.0f) {
        const auto [mp, mn] = morphTarget(p.positions[level], p.normals[level], x, y);
        v.position = glm::mix(v.position, mp, morph);
        v.normal = safeNormalize(glm::mix(v.normal, mn, morph));
    }
    return v;
}

// Triangulates an N x N vertex grid; `splitAC(i, j)` says whether quad (i, j) is split
// along its diagonal a-c.
template <class SplitAC> void triangulateGrid(LodMesh& mesh, uint32_t n, SplitAC splitAC)
{
    mesh.triangles.reserve(size_t(gridTriangleCount(n)));
    for (uint32_t j = 0; j + 1 < n; ++j)
        for (uint32_t i = 0; i + 1 < n; ++i) {
            const uint32_t a = j * n + i, b = a + 1, c = a + n + 1, d = a + n;
            if (splitAC(i, j)) {
                mesh.triangles.push_back({a, b, c});
                mesh.triangles.push_back({a, c, d});
            } else {
                mesh.triangles.push_back({a, b, d});
                mesh.triangles.push_back({b, c, d});
            }
        }
}

}  // namespace

SurfacePyramid buildSurfacePyramid(const GeometryImage& positions, const GeometryImage& normals)
{
    if (positions.size != normals.size) throw Error("surface pyramid: position and normal images differ in size");
    SurfacePyramid p;
    p.positions = buildMipPyramid(positions);
    p.normals = buildMipPyramid(normals);
    return p;
}

LodSelection selectLod(uint32_t levelCount, uint32_t fullSize, float lod)
{
    const float maxLod = float(levelCount - 1);
    const float f = std::isfinite(lod) ? std::clamp(lod, 0.0f, maxLod) : 0.0f;
    LodSelection s;
    s.level = std::min(uint32_t(std::floor(f)), levelCount - 1);
    s.morph = s.level + 1 < levelCount ? f - float(s.level) : 0.0f;
    s.gridSize = mipLevelSize(fullSize, s.level);
    return s;
}

uint32_t levelForGridSize(uint32_t fullSize, uint32_t gridSize)
{
    if (gridSize < 2 || gridSize > fullSize)
        throw Error("grid size " + std::to_string(gridSize) + " is outside [2, " + std::to_string(fullSize) + "]");
    uint32_t level = 0;
    while (mipLevelSize(fullSize, level + 1) >= gridSize &&
           mipLevelSize(fullSize, level + 1) < mipLevelSize(fullSize, level))
        ++level;
    return level;
}

uint64_t gridTriangleCount(uint32_t gridSize)
{
    const uint64_t q = gridSize > 1 ? gridSize - 1 : 0;
    return 2 * q * q;
}

std::pair<glm::vec3, glm::vec3> morphTarget(const GeometryImage& positions, const GeometryImage& normals, uint32_t x,
                                            uint32_t y)
{
    const bool oddX = x & 1, oddY = y & 1;
    if (!oddX && !oddY) return {positions.at(x, y), normals.at(x, y)};
    if (oddX != oddY) {
        const uint32_t dx = oddX, dy = oddY;
        const glm::vec3 p = (positions.at(x - dx, y - dy) + positions.at(x + dx, y + dy)) * 0.5f;
        const glm::vec3 n = normals.at(x - dx, y - dy) + normals.at(x + dx, y + dy);
        return {p, safeNormalize(n)};
    }
    const glm::vec3 a = positions.at(x - 1, y - 1), b = positions.at(x + 1, y - 1);
    const glm::vec3 c = positions.at(x + 1, y + 1), d = positions.at(x - 1, y + 1);
    const glm::vec3 ac = c - a, bd = d - b;
    if (glm::dot(ac, ac) <= glm::dot(bd, bd))
        return {(a + c) * 0.5f, safeNormalize(normals.at(x - 1, y - 1) + normals.at(x + 1, y + 1))};
    return {(b + d) * 0.5f, safeNormalize(normals.at(x + 1, y - 1) + normals.at(x - 1, y + 1))};
}

glm::vec3 quadDiagonal(const glm::vec3 level[4], const glm::vec3 target[4])
{
    // Same operations in the same order as shaders/quad_diagonals.comp.
    const glm::vec3 ac0 = level[2] - level[0], bd0 = level[3] - level[1];
    const glm::vec3 dac = (target[2] - target[0]) - ac0, dbd = (target[3] - target[1]) - bd0;
    return {glm::dot(ac0, ac0) - glm::dot(bd0, bd0), 2.0f * (glm::dot(ac0, dac) - glm::dot(bd0, dbd)),
            glm::dot(dac, dac) - glm::dot(dbd, dbd)};
}

LodMesh buildLodMesh(const SurfacePyramid& pyramid, float lod)
{
    const LodSelection s = selectLod(pyramid.levelCount(), pyramid.fullSize(), lod);
    const uint32_t n = s.gridSize;
    LodMesh mesh;
    mesh.positions.resize(size_t(n) * n);
    mesh.normals.resize(size_t(n) * n);
    std::vector<glm::vec3> targets(size_t(n) * n);
    const GeometryImage& level = pyramid.positions[s.level];
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const Vertex v = morphedVertex(pyramid, s.level, s.morph, x, y);
            mesh.positions[size_t(y) * n + x] = v.position;
            mesh.normals[size_t(y) * n + x] = v.normal;
            targets[size_t(y) * n + x] = s.level + 1 < pyramid.levelCount()
                ? morphTarget(level, pyramid.normals[s.level], x, y).first
                : level.at(x, y);
        }
    triangulateGrid(mesh, n, [&](uint32_t i, uint32_t j) {
        const glm::vec3 p0[4] = {level.at(i, j), level.at(i + 1, j), level.at(i + 1, j + 1), level.at(i, j + 1)};
        const size_t a = size_t(j) * n + i;
        const glm::vec3 p1[4] = {targets[a], targets[a + 1], targets[a + n + 1], targets[a + n]};
        return splitsAlongAC(quadDiagonal(p0, p1), s.morph);
    });
    return mesh;
}

LodMesh buildGridMesh(const SurfacePyramid& pyramid, uint32_t gridSize)
{
    const uint32_t level = levelForGridSize(pyramid.fullSize(), gridSize);
    const GeometryImage& pos = pyramid.positions[level];
    const GeometryImage& nrm = pyramid.normals[level];
    const uint32_t last = pos.size - 1, den = gridSize - 1;
    LodMesh mesh;
    mesh.positions.resize(size_t(gridSize) * gridSize);
    mesh.normals.resize(size_t(gridSize) * gridSize);
    for (uint32_t j = 0; j < gridSize; ++j)
        for (uint32_t i = 0; i < gridSize; ++i) {
            // Exact rational texel position (i, j) * last / den, as in surface.vert.
            const uint32_t nx = i * last, ny = j * last;
            const uint32_t x0 = nx / den, y0 = ny / den;
            const float fx = float(nx - x0 * den) / float(den), fy = float(ny - y0 * den) / float(den);
            const uint32_t x1 = std::min(x0 + 1, last), y1 = std::min(y0 + 1, last);
            auto bilinear = [&](const GeometryImage& g) {
                return glm::mix(glm::mix(g.at(x0, y0), g.at(x1, y0), fx), glm::mix(g.at(x0, y1), g.at(x1, y1), fx), fy);
            };
            mesh.positions[size_t(j) * gridSize + i] = bilinear(pos);
            mesh.normals[size_t(j) * gridSize + i] = safeNormalize(bilinear(nrm));
        }
    const uint32_t n = gridSize;
    triangulateGrid(mesh, n, [&](uint32_t i, uint32_t j) {
        const size_t a = size_t(j) * n + i;
        const glm::vec3 ac = mesh.positions[a + n + 1] - mesh.positions[a],
                        bd = mesh.positions[a + n] - mesh.positions[a + 1];
        return glm::dot(ac, ac) - glm::dot(bd, bd) <= 0.0f;
    });
    return mesh;
}

}  // namespace ngi
