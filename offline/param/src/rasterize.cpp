// ngi offline: rasterization of a square map into a geometry image (Gu, Gu, Hoppe 2002,
// "Geometry images"; paper section 4, "Implementation Details": positions and normals are
// sampled on the regular grid of the unit square). Sample (x, y) sits at uv = (x, y) / R, so
// border samples lie ON the boundary loop. Each uv triangle scans the samples of its
// bounding box (edge functions with a small tolerance so shared edges and the border are
// covered); rows are split between threads.
#include "ngi/param/rasterize.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <thread>

namespace ngi {

RasterizedGeometryImage rasterizeGeometryImage(const DiskMesh& disk, std::span<const glm::dvec2> uv,
                                               uint32_t resolution)
{
    const auto& mesh = disk.mesh;
    const size_t n = mesh.positions.size();
    if (uv.size() != n)
        throw Error("rasterize: " + std::to_string(uv.size()) + " uv coordinates for " + std::to_string(n) +
                    " vertices");
    if (resolution == 0) throw Error("rasterize: resolution must be positive");
    if (!disk.originalVertex.empty() && disk.originalVertex.size() != n)
        throw Error("rasterize: originalVertex size does not match the vertex count");
    for (const glm::dvec2& x : uv)
        if (!std::isfinite(x.x) || !std::isfinite(x.y)) throw Error("rasterize: uv has a NaN/Inf coordinate");

    // Area-weighted vertex normals of the uncut mesh (seam mates share their original vertex).
    auto original = [&](size_t v) -> size_t { return disk.originalVertex.empty() ? v : disk.originalVertex[v]; };
    size_t originalCount = 0;
    for (size_t v = 0; v < n; ++v) originalCount = std::max(originalCount, original(v) + 1);
    std::vector<glm::dvec3> accumulated(originalCount, glm::dvec3(0.0));
    for (const glm::uvec3& tri : mesh.triangles) {
        const glm::dvec3 faceNormal = glm::cross(mesh.positions[tri[1]] - mesh.positions[tri[0]],
                                                 mesh.positions[tri[2]] - mesh.positions[tri[0]]);
        for (int k = 0; k < 3; ++k) accumulated[original(tri[k])] += faceNormal;
    }
    std::vector<glm::dvec3> normal(n);
    for (size_t v = 0; v < n; ++v) {
        const glm::dvec3 a = accumulated[original(v)];
        const double len = glm::length(a);
        normal[v] = len > 0.0 ? a / len : glm::dvec3(0, 0, 1);
    }

    const uint32_t size = resolution + 1;
    RasterizedGeometryImage image{GeometryImage(size), GeometryImage(size)};
    std::vector<uint8_t> filled(size_t(size) * size, 0);
    const double R = double(resolution);

    auto write = [&](size_t index, const glm::uvec3& tri, double b0, double b1, double b2) {
        const glm::dvec3 position =
            b0 * mesh.positions[tri[0]] + b1 * mesh.positions[tri[1]] + b2 * mesh.positions[tri[2]];
        glm::dvec3 nrm = b0 * normal[tri[0]] + b1 * normal[tri[1]] + b2 * normal[tri[2]];
        const double len = glm::length(nrm);
        nrm = len > 0.0 ? nrm / len : normal[tri[0]];
        image.positions.texels[index] = glm::vec3(position);
        image.normals.texels[index] = glm::vec3(nrm);
        filled[index] = 1;
    };

    auto scanRows = [&](uint32_t rowBegin, uint32_t rowEnd) {
        for (const glm::uvec3& tri : mesh.triangles) {
            const glm::dvec2 a = uv[tri[0]] * R, b = uv[tri[1]] * R, c = uv[tri[2]] * R;
            const double twiceArea = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
            if (!(std::abs(twiceArea) > 0.0)) continue;
            const double tolerance = 1e-9 * std::max(1.0, std::abs(twiceArea));
            const double minY = std::min({a.y, b.y, c.y}), maxY = std::max({a.y, b.y, c.y});
            const double minX = std::min({a.x, b.x, c.x}), maxX = std::max({a.x, b.x, c.x});
            const int64_t y0 = std::max<int64_t>(rowBegin, int64_t(std::ceil(minY - 1e-9)));
            const int64_t y1 = std::min<int64_t>(int64_t(rowEnd) - 1, int64_t(std::floor(maxY + 1e-9)));
            const int64_t x0 = std::max<int64_t>(0, int64_t(std::ceil(minX - 1e-9)));
            const int64_t x1 = std::min<int64_t>(int64_t(size) - 1, int64_t(std::floor(maxX + 1e-9)));
            for (int64_t y = y0; y <= y1; ++y) {
                for (int64_t x = x0; x <= x1; ++x) {
                    const glm::dvec2 q{double(x), double(y)};
                    // Edge functions, signed like the triangle (flipped triangles still rasterize).
                    double w0 = (b.x - q.x) * (c.y - q.y) - (b.y - q.y) * (c.x - q.x);
                    double w1 = (c.x - q.x) * (a.y - q.y) - (c.y - q.y) * (a.x - q.x);
                    double w2 = (a.x - q.x) * (b.y - q.y) - (a.y - q.y) * (b.x - q.x);
                    if (twiceArea < 0.0) {
                        w0 = -w0;
                        w1 = -w1;
                        w2 = -w2;
                    }
                    if (w0 < -tolerance || w1 < -tolerance || w2 < -tolerance) continue;
                    const double sum = w0 + w1 + w2;
                    write(size_t(y) * size + size_t(x), tri, w0 / sum, w1 / sum, w2 / sum);
                }
            }
        }
    };
    const unsigned threads = std::max(1u, std::min(2u, std::thread::hardware_concurrency()));
    std::vector<std::thread> workers;
    for (unsigned t = 1; t < threads; ++t)
        workers.emplace_back(scanRows, uint32_t(uint64_t(size) * t / threads),
                             uint32_t(uint64_t(size) * (t + 1) / threads));
    scanRows(0, uint32_t(uint64_t(size) / threads));
    for (std::thread& w : workers) w.join();

    // Samples in no triangle: the closest point of the uv boundary loop, interpolated along its edge.
    const auto& loop = disk.boundaryLoop;
    for (size_t index = 0; index < filled.size(); ++index) {
        if (filled[index]) continue;
        ++image.extrapolatedSamples;
        const glm::dvec2 q{double(index % size) / R, double(index / size) / R};
        double best = std::numeric_limits<double>::max();
        uint32_t bestA = 0, bestB = 0;
        double bestT = 0.0;
        for (size_t k = 0; k < loop.size(); ++k) {
            const uint32_t ia = loop[k], ib = loop[(k + 1) % loop.size()];
            const glm::dvec2 e = uv[ib] - uv[ia];
            const double e2 = glm::dot(e, e);
            const double t = e2 > 0.0 ? std::clamp(glm::dot(q - uv[ia], e) / e2, 0.0, 1.0) : 0.0;
            const glm::dvec2 d = uv[ia] + t * e - q;
            if (glm::dot(d, d) < best) {
                best = glm::dot(d, d);
                bestA = ia;
                bestB = ib;
                bestT = t;
            }
        }
        if (loop.empty()) continue;
        const glm::dvec3 position = (1.0 - bestT) * mesh.positions[bestA] + bestT * mesh.positions[bestB];
        const glm::dvec3 nrm = glm::normalize((1.0 - bestT) * normal[bestA] + bestT * normal[bestB]);
        image.positions.texels[index] = glm::vec3(position);
        image.normals.texels[index] = glm::vec3(nrm);
    }
    return image;
}

}  // namespace ngi
