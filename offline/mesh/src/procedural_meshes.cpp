// ngi offline: procedural test meshes (see procedural_meshes.h for the list and invariants).
#include "ngi/mesh/procedural_meshes.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <tuple>

namespace ngi {
namespace {

// Flips every triangle if the closed surface encloses negative signed volume.
void orientOutward(TriangleMesh& mesh)
{
    double volume = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        volume += glm::dot(mesh.positions[t.x], glm::cross(mesh.positions[t.y], mesh.positions[t.z]));
    if (volume < 0.0)
        for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
}

// Adds the two triangles of quad (a, b, c, d), counter-clockwise.
void addQuad(TriangleMesh& mesh, uint32_t a, uint32_t b, uint32_t c, uint32_t d)
{
    mesh.triangles.push_back({a, b, c});
    mesh.triangles.push_back({a, c, d});
}

}  // namespace

TriangleMesh makeSphere(uint32_t subdivisions, double radius)
{
    if (subdivisions > 8) throw Error("makeSphere: at most 8 subdivisions (1.3M triangles)");
    const double p = (1.0 + std::sqrt(5.0)) / 2.0;
    TriangleMesh mesh;
    mesh.positions = {{-1, p, 0},  {1, p, 0},  {-1, -p, 0}, {1, -p, 0}, {0, -1, p},  {0, 1, p},
                      {0, -1, -p}, {0, 1, -p}, {p, 0, -1},  {p, 0, 1},  {-p, 0, -1}, {-p, 0, 1}};
    mesh.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                      {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (uint32_t level = 0; level < subdivisions; ++level) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoints;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            auto key = std::minmax(a, b);
            auto [it, inserted] = midpoints.try_emplace({key.first, key.second}, uint32_t(mesh.positions.size()));
            if (inserted) mesh.positions.push_back((mesh.positions[a] + mesh.positions[b]) * 0.5);
            return it->second;
        };
        std::vector<glm::uvec3> finer;
        finer.reserve(mesh.triangles.size() * 4);
        for (const glm::uvec3& t : mesh.triangles) {
            uint32_t ab = midpoint(t.x, t.y), bc = midpoint(t.y, t.z), ca = midpoint(t.z, t.x);
            finer.push_back({t.x, ab, ca});
            finer.push_back({t.y, bc, ab});
            finer.push_back({t.z, ca, bc});
            finer.push_back({ab, bc, ca});
        }
        mesh.triangles = std::move(finer);
    }
    for (glm::dvec3& v : mesh.positions) v = glm::normalize(v) * radius;
    orientOutward(mesh);
    return mesh;
}

TriangleMesh makeTorus(uint32_t majorSegments, uint32_t minorSegments, double majorRadius, double minorRadius)
{
    if (majorSegments < 3 || minorSegments < 3 || !(minorRadius > 0.0) || !(majorRadius > minorRadius))
        throw Error("makeTorus: needs >= 3 segments each way and majorRadius > minorRadius > 0");
    TriangleMesh mesh;
    const double twoPi = 2.0 * std::numbers::pi;
    for (uint32_t i = 0; i < majorSegments; ++i)
        for (uint32_t j = 0; j < minorSegments; ++j) {
            double u = twoPi * i / majorSegments, v = twoPi * j / minorSegments;
            double ring = majorRadius + minorRadius * std::cos(v);
            mesh.positions.push_back({ring * std::cos(u), ring * std::sin(u), minorRadius * std::sin(v)});
        }
    auto index = [&](uint32_t i, uint32_t j) { return (i % majorSegments) * minorSegments + (j % minorSegments); };
    for (uint32_t i = 0; i < majorSegments; ++i)
        for (uint32_t j = 0; j < minorSegments; ++j)
            addQuad(mesh, index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
    orientOutward(mesh);
    return mesh;
}

TriangleMesh makeGenusSurface(uint32_t genus, uint32_t faceSubdivisions)
{
    if (genus < 1 || genus > 64 || faceSubdivisions < 1 || faceSubdivisions > 64)
        throw Error("makeGenusSurface: genus must be in 1..64 and faceSubdivisions in 1..64");
    const int sizeX = int(2 * genus + 1), sizeY = 3;
    auto occupied = [&](int x, int y, int z) {
        if (x < 0 || y < 0 || z != 0 || x >= sizeX || y >= sizeY) return false;
        return !(y == 1 && x % 2 == 1);  // the holes
    };
    const int n = int(faceSubdivisions);
    TriangleMesh mesh;
    std::map<std::array<int, 3>, uint32_t> lattice;  // welds shared face vertices exactly
    auto vertex = [&](std::array<int, 3> p) {
        auto [it, inserted] = lattice.try_emplace(p, uint32_t(mesh.positions.size()));
        if (inserted) mesh.positions.push_back(glm::dvec3(p[0], p[1], p[2]) / double(n));
        return it->second;
    };
    for (int x = 0; x < sizeX; ++x)
        for (int y = 0; y < sizeY; ++y) {
            if (!occupied(x, y, 0)) continue;
            const std::array<int, 3> cell{x, y, 0};
            for (int axis = 0; axis < 3; ++axis)
                for (int side = 0; side < 2; ++side) {
                    std::array<int, 3> neighbour = cell;
                    neighbour[axis] += side ? 1 : -1;
                    if (occupied(neighbour[0], neighbour[1], neighbour[2])) continue;
                    // Face in the plane axis = cell[axis] + side; (a, b) span it with a x b = +axis.
                    int a = (axis + 1) % 3, b = (axis + 2) % 3;
                    if (!side) std::swap(a, b);  // outward normal -axis
                    std::array<int, 3> origin{cell[0] * n, cell[1] * n, cell[2] * n};
                    origin[axis] += side * n;
                    auto at = [&](int i, int j) {
                        std::array<int, 3> p = origin;
                        p[a] += i;
                        p[b] += j;
                        return vertex(p);
                    };
                    for (int i = 0; i < n; ++i)
                        for (int j = 0; j < n; ++j)
                            addQuad(mesh, at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                }
        }
    return mesh;
}

TriangleMesh makeOpenCylinder(uint32_t segments, uint32_t rings, double radius, double height)
{
    if (segments < 3 || rings < 1 || !(radius > 0.0) || !(height > 0.0))
        throw Error("makeOpenCylinder: needs >= 3 segments, >= 1 ring, positive radius and height");
    TriangleMesh mesh;
    for (uint32_t j = 0; j <= rings; ++j)
        for (uint32_t i = 0; i < segments; ++i) {
            double u = 2.0 * std::numbers::pi * i / segments;
            mesh.positions.push_back({radius * std::cos(u), radius * std::sin(u), height * j / rings});
        }
    auto index = [&](uint32_t i, uint32_t j) { return j * segments + (i % segments); };
    for (uint32_t j = 0; j < rings; ++j)
        for (uint32_t i = 0; i < segments; ++i)  // d/du x d/dz points outward
            addQuad(mesh, index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
    return mesh;
}

TriangleMesh makePlanePatch(uint32_t cells, double size, double bumpHeight)
{
    if (cells < 1 || !(size > 0.0)) throw Error("makePlanePatch: needs >= 1 cell and a positive size");
    TriangleMesh mesh;
    for (uint32_t j = 0; j <= cells; ++j)
        for (uint32_t i = 0; i <= cells; ++i) {
            double x = double(i) / cells, y = double(j) / cells;
            double z = bumpHeight * std::sin(std::numbers::pi * x) * std::sin(std::numbers::pi * y);
            mesh.positions.push_back({x * size, y * size, z * size});
        }
    auto index = [&](uint32_t i, uint32_t j) { return j * (cells + 1) + i; };
    for (uint32_t j = 0; j < cells; ++j)
        for (uint32_t i = 0; i < cells; ++i)
            addQuad(mesh, index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
    return mesh;
}

TriangleMesh makeTwoArmedBody(uint32_t subdivisions)
{
    TriangleMesh mesh = makeSphere(subdivisions);
    for (glm::dvec3& p : mesh.positions) {
        const double ax = std::abs(p.x), t = std::clamp((ax - 0.3) / 0.3, 0.0, 1.0);
        const double narrow = 1.0 - 0.7 * t * t * (3.0 - 2.0 * t);  // smoothstep into the arm
        p = {std::copysign(ax + 10.0 * std::max(0.0, ax - 0.5), p.x), narrow * p.y, narrow * p.z};
    }
    return mesh;
}

}  // namespace ngi
