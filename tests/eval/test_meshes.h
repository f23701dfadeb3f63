// Small procedural meshes for the eval tests (docs/DESIGN.md "Data": unit tests build their
// meshes in code): spheres with vertices on the sphere, flat squares, height-field patches.
#pragma once

#include "ngi/asset.h"
#include "ngi/mesh/triangle_mesh.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <random>
#include <tuple>

namespace ngi::test {

// A sphere from the subdivided octahedron: each octant face split into n^2 triangles, the
// vertices pushed to the sphere. Welded, closed, counter-clockwise seen from outside. Its
// bounding box is exactly [-radius, radius]^3 (the six axis vertices are exact).
inline TriangleMesh octaSphere(int n, double radius = 1.0)
{
    TriangleMesh mesh;
    std::map<std::tuple<int, int, int>, uint32_t> index;
    auto vertex = [&](int x, int y, int z) {
        auto [it, added] = index.try_emplace({x, y, z}, uint32_t(mesh.positions.size()));
        if (added) mesh.positions.push_back(radius * glm::normalize(glm::dvec3(x, y, z)));
        return it->second;
    };
    for (int sx : {1, -1})
        for (int sy : {1, -1})
            for (int sz : {1, -1}) {
                auto at = [&](int i, int j) { return vertex(sx * i, sy * j, sz * (n - i - j)); };
                const bool flip = sx * sy * sz < 0;
                auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
                    mesh.triangles.push_back(flip ? glm::uvec3(a, c, b) : glm::uvec3(a, b, c));
                };
                for (int i = 0; i < n; ++i)
                    for (int j = 0; i + j < n; ++j) {
                        add(at(i, j), at(i + 1, j), at(i, j + 1));
                        if (i + j < n - 1) add(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    }
            }
    return mesh;
}

// A latitude-longitude sphere: `rings` latitude bands (even: it has an equator) and
// `segments` longitudes (a multiple of 4: the equator holds the four axis points), so its
// bounding box is exactly [-radius, radius]^3. Welded, closed, counter-clockwise outside.
inline TriangleMesh uvSphere(int rings, int segments, double radius = 1.0)
{
    TriangleMesh mesh;
    const double pi = std::numbers::pi;
    mesh.positions.push_back({0.0, 0.0, radius});
    for (int r = 1; r < rings; ++r) {
        const double theta = pi * r / rings;
        const double z = (2 * r == rings) ? 0.0 : std::cos(theta);
        const double s = std::sin(theta);
        for (int k = 0; k < segments; ++k) {
            const double phi = 2.0 * pi * k / segments;
            double c = std::cos(phi), d = std::sin(phi);
            if (k % (segments / 4) == 0) {  // exact axis points
                const int q = k / (segments / 4);
                c = (q == 0) ? 1.0 : (q == 2) ? -1.0 : 0.0;
                d = (q == 1) ? 1.0 : (q == 3) ? -1.0 : 0.0;
            }
            mesh.positions.push_back(radius * glm::dvec3(s * c, s * d, z));
        }
    }
    const uint32_t south = uint32_t(mesh.positions.size());
    mesh.positions.push_back({0.0, 0.0, -radius});
    auto ring = [&](int r, int k) { return uint32_t(1 + (r - 1) * segments + (k % segments)); };
    for (int k = 0; k < segments; ++k) {
        mesh.triangles.push_back({0u, ring(1, k), ring(1, k + 1)});
        mesh.triangles.push_back({south, ring(rings - 1, k + 1), ring(rings - 1, k)});
    }
    for (int r = 1; r + 1 < rings; ++r)
        for (int k = 0; k < segments; ++k) {
            mesh.triangles.push_back({ring(r, k), ring(r + 1, k), ring(r + 1, k + 1)});
            mesh.triangles.push_back({ring(r, k), ring(r + 1, k + 1), ring(r, k + 1)});
        }
    return mesh;
}

// The mesh scaled about the origin.
inline TriangleMesh scaled(TriangleMesh mesh, double factor)
{
    for (glm::dvec3& p : mesh.positions) p *= factor;
    return mesh;
}

// Every vertex moved along its direction from the origin to radius f(unit direction).
inline TriangleMesh radiallyDisplaced(TriangleMesh mesh, const std::function<double(glm::dvec3)>& radius)
{
    for (glm::dvec3& p : mesh.positions) {
        const glm::dvec3 u = glm::normalize(p);
        p = radius(u) * u;
    }
    return mesh;
}

// The smallest distance from the origin to the plane of a triangle: a closed mesh with all
// vertices on the sphere of radius R lies between the spheres of radius R*h and R, where h
// is this value for the mesh scaled to R = 1.
inline double minPlaneDistance(const TriangleMesh& mesh)
{
    double h = INFINITY;
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::dvec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
        const glm::dvec3 n = glm::normalize(glm::cross(b - a, c - a));
        h = std::min(h, std::abs(glm::dot(n, a)));
    }
    return h;
}

// The same surface with vertices renumbered, triangles reordered and each triangle's
// corners rotated (orientation kept), from a fixed seed.
inline TriangleMesh shuffled(const TriangleMesh& mesh, uint64_t seed)
{
    std::mt19937_64 rng(seed);
    std::vector<uint32_t> newIndex(mesh.positions.size());
    for (uint32_t i = 0; i < newIndex.size(); ++i) newIndex[i] = i;
    std::shuffle(newIndex.begin(), newIndex.end(), rng);
    TriangleMesh out;
    out.positions.resize(mesh.positions.size());
    for (size_t i = 0; i < newIndex.size(); ++i) out.positions[newIndex[i]] = mesh.positions[i];
    out.triangles = mesh.triangles;
    std::shuffle(out.triangles.begin(), out.triangles.end(), rng);
    for (glm::uvec3& t : out.triangles) {
        t = {newIndex[t.x], newIndex[t.y], newIndex[t.z]};
        for (uint64_t r = rng() % 3; r > 0; --r) t = {t.y, t.z, t.x};
    }
    return out;
}

// A height-field patch z = height(x, y) over [0,1]^2 on an n x n grid of squares, each
// square split along the diagonal (0,0)-(1,1) when `mainDiagonal`, else along (1,0)-(0,1).
inline TriangleMesh heightField(int n, bool mainDiagonal, const std::function<double(double, double)>& height)
{
    TriangleMesh mesh;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = double(i) / n, y = double(j) / n;
            mesh.positions.push_back({x, y, height(x, y)});
        }
    auto v = [n](int i, int j) { return uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            if (mainDiagonal) {
                mesh.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
                mesh.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
            } else {
                mesh.triangles.push_back({v(i, j), v(i + 1, j), v(i, j + 1)});
                mesh.triangles.push_back({v(i + 1, j), v(i + 1, j + 1), v(i, j + 1)});
            }
        }
    return mesh;
}

// An asset: a rippled patch, full resolution 64 (65^2 samples), stored at level 2 (17^2).
inline Asset rippleAsset()
{
    Asset a;
    a.sourceName = "analytic:ripple";
    a.offset = {-1.0f, 2.0f, 0.5f};
    a.scale = {4.0f, 4.0f, 4.0f};
    a.parameterization = "analytic";
    AssetChart& chart = a.charts.emplace_back();
    chart.fullResolution = 64;
    chart.storedLevel = 2;
    GeometryImage pos(chart.storedSize()), nrm(chart.storedSize());
    for (uint32_t y = 0; y < pos.size; ++y)
        for (uint32_t x = 0; x < pos.size; ++x) {
            const float u = float(x) / float(pos.size - 1), v = float(y) / float(pos.size - 1);
            pos.at(x, y) = {u, v, 0.5f + 0.2f * std::sin(7.0f * u) * std::cos(5.0f * v)};
            nrm.at(x, y) = {0.0f, 0.0f, 1.0f};
        }
    storeGeometryImage(chart, pos, nrm);
    return a;
}

}  // namespace ngi::test
