// ngi tests: small procedural disk meshes for the parameterization tests (built in code, no
// files): a square plane patch with a jittered interior, and "ring disks" (a centre vertex and
// rings of 6r vertices) lifted to a flat disk, a spherical cap, a bumpy height field and a
// height field with a sharp spike.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>

namespace ngi::test {

// n x n cells on [0, size]^2, interior vertices jittered by up to `jitter` cells, diagonals
// alternating. The boundary loop starts at (0, 0) and runs counter-clockwise.
inline DiskMesh planePatch(int n, double jitter = 0.3, double size = 1.0, uint32_t seed = 7)
{
    DiskMesh disk;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> offset(-jitter, jitter);
    auto index = [n](int x, int y) { return uint32_t(y * (n + 1) + x); };
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) {
            const bool interior = x > 0 && x < n && y > 0 && y < n;
            const double dx = interior ? offset(rng) : 0.0, dy = interior ? offset(rng) : 0.0;
            disk.mesh.positions.push_back({(x + dx) * size / n, (y + dy) * size / n, 0.0});
        }
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t a = index(x, y), b = index(x + 1, y), c = index(x + 1, y + 1), d = index(x, y + 1);
            if ((x + y) % 2 == 0) {
                disk.mesh.triangles.push_back({a, b, c});
                disk.mesh.triangles.push_back({a, c, d});
            } else {
                disk.mesh.triangles.push_back({a, b, d});
                disk.mesh.triangles.push_back({b, c, d});
            }
        }
    for (int x = 0; x < n; ++x) disk.boundaryLoop.push_back(index(x, 0));
    for (int y = 0; y < n; ++y) disk.boundaryLoop.push_back(index(n, y));
    for (int x = n; x > 0; --x) disk.boundaryLoop.push_back(index(x, n));
    for (int y = n; y > 0; --y) disk.boundaryLoop.push_back(index(0, y));
    for (uint32_t v = 0; v < disk.mesh.positions.size(); ++v) disk.originalVertex.push_back(v);
    return disk;
}

// A disk of `rings` rings (ring r has 6r vertices at radius r / rings, angles jittered by up
// to `jitter` of a step inside), lifted to 3D by `lift(x, y)` with (x, y) in the unit disk.
inline DiskMesh ringDisk(int rings, const std::function<glm::dvec3(double, double)>& lift, double jitter = 0.25,
                         uint32_t seed = 11)
{
    DiskMesh disk;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> offset(-jitter, jitter);
    std::vector<uint32_t> ringStart{0};
    std::vector<std::vector<double>> ringAngle{{0.0}};
    disk.mesh.positions.push_back(lift(0.0, 0.0));
    for (int r = 1; r <= rings; ++r) {
        ringStart.push_back(uint32_t(disk.mesh.positions.size()));
        const int count = 6 * r;
        const double step = 2.0 * std::numbers::pi / count;
        std::vector<double> angles;
        for (int k = 0; k < count; ++k) {
            const bool interior = r < rings;
            const double phi = step * (k + (interior ? offset(rng) : 0.0)) + 0.1 * r;
            const double rho = (r + (interior ? 0.5 * offset(rng) : 0.0)) / rings;
            angles.push_back(step * k + 0.1 * r);
            disk.mesh.positions.push_back(lift(rho * std::cos(phi), rho * std::sin(phi)));
        }
        ringAngle.push_back(angles);
    }
    // Centre fan.
    for (uint32_t k = 0; k < 6; ++k) disk.mesh.triangles.push_back({0, ringStart[1] + k, ringStart[1] + (k + 1) % 6});
    // Strips between ring r-1 and ring r: advance the side whose next vertex has the smaller angle.
    for (int r = 2; r <= rings; ++r) {
        const int inner = 6 * (r - 1), outer = 6 * r;
        int i = 0, o = 0;
        auto angleOf = [&](int ring, int k, int count) {
            return ringAngle[size_t(ring)][size_t(k % count)] + 2.0 * std::numbers::pi * (k / count);
        };
        const double base = std::min(angleOf(r - 1, 0, inner), angleOf(r, 0, outer));
        (void)base;
        while (i < inner || o < outer) {
            const uint32_t vi = ringStart[size_t(r - 1)] + uint32_t(i % inner),
                           vo = ringStart[size_t(r)] + uint32_t(o % outer);
            const bool advanceOuter =
                i >= inner || (o < outer && angleOf(r, o + 1, outer) < angleOf(r - 1, i + 1, inner));
            if (advanceOuter) {
                disk.mesh.triangles.push_back({vi, vo, ringStart[size_t(r)] + uint32_t((o + 1) % outer)});
                ++o;
            } else {
                disk.mesh.triangles.push_back({vi, vo, ringStart[size_t(r - 1)] + uint32_t((i + 1) % inner)});
                ++i;
            }
        }
    }
    for (int k = 0; k < 6 * rings; ++k) disk.boundaryLoop.push_back(ringStart[size_t(rings)] + uint32_t(k));
    for (uint32_t v = 0; v < disk.mesh.positions.size(); ++v) disk.originalVertex.push_back(v);
    return disk;
}

inline DiskMesh flatDisk(int rings)
{
    return ringDisk(rings, [](double x, double y) { return glm::dvec3(x, y, 0.0); });
}

// Spherical cap of the unit sphere with polar half-angle `halfAngle` (pi/2: hemisphere).
inline DiskMesh sphericalCap(int rings, double halfAngle)
{
    return ringDisk(rings, [halfAngle](double x, double y) {
        const double rho = std::sqrt(x * x + y * y), theta = rho * halfAngle, phi = std::atan2(y, x);
        return glm::dvec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
    });
}

inline DiskMesh bumpyHeightField(int rings)
{
    return ringDisk(rings, [](double x, double y) {
        return glm::dvec3(x, y, 0.15 * std::sin(4.0 * x) * std::cos(3.0 * y) + 0.1 * std::sin(7.0 * x * y));
    });
}

// A flat disk with a Gaussian spike of height 0.6 and width 0.12 at (0.2, 0.1).
inline DiskMesh spikeDisk(int rings)
{
    return ringDisk(rings, [](double x, double y) {
        const double d2 = (x - 0.2) * (x - 0.2) + (y - 0.1) * (y - 0.1);
        return glm::dvec3(x, y, 0.6 * std::exp(-d2 / (0.12 * 0.12)));
    });
}

}  // namespace ngi::test
