// ngi tests: rasterizing a square map reproduces the surface it samples.
#include "disk_meshes.h"

#include "ngi/error.h"
#include "ngi/param/parameterize.h"
#include "ngi/param/rasterize.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ngi {
namespace {

TEST(Rasterize, flatPlanePatchIsReproducedExactly)
{
    const double size = 3.0;
    const DiskMesh disk = test::planePatch(10, 0.3, size);
    std::vector<glm::dvec2> uv;
    for (const glm::dvec3& p : disk.mesh.positions) uv.emplace_back(p.x / size, p.y / size);
    const uint32_t R = 64;
    const RasterizedGeometryImage image = rasterizeGeometryImage(disk, uv, R);
    ASSERT_EQ(image.positions.size, R + 1);
    ASSERT_EQ(image.normals.size, R + 1);
    EXPECT_EQ(image.extrapolatedSamples, 0u);
    const float eps = 4.0f * std::numeric_limits<float>::epsilon() * float(size);
    for (uint32_t y = 0; y <= R; ++y)
        for (uint32_t x = 0; x <= R; ++x) {
            const glm::vec3 p = image.positions.at(x, y);
            ASSERT_NEAR(p.x, float(size * x / R), eps) << x << "," << y;
            ASSERT_NEAR(p.y, float(size * y / R), eps) << x << "," << y;
            ASSERT_EQ(p.z, 0.0f);
            const glm::vec3 n = image.normals.at(x, y);
            ASSERT_NEAR(n.z, 1.0f, 1e-6f);
        }
}

TEST(Rasterize, sphereCapSamplesLieOnTheSphereWithinTheChordError)
{
    const DiskMesh disk = test::sphericalCap(12, 0.4 * std::numbers::pi);
    // Every point of a triangle is at least its plane's distance from the centre.
    double innerRadius = 1.0;
    for (const glm::uvec3& t : disk.mesh.triangles) {
        const glm::dvec3 a = disk.mesh.positions[t[0]], b = disk.mesh.positions[t[1]], c = disk.mesh.positions[t[2]];
        innerRadius = std::min(innerRadius, std::abs(glm::dot(glm::normalize(glm::cross(b - a, c - a)), a)));
    }
    ASSERT_GT(innerRadius, 0.98);  // the chord error of this mesh is under 2%
    const SquareMap map = parameterizeToSquare(disk);
    const uint32_t R = 128;
    const RasterizedGeometryImage image = rasterizeGeometryImage(disk, map.uv, R);
    EXPECT_EQ(image.extrapolatedSamples, 0u);
    for (const glm::vec3& p : image.positions.texels) {
        const float r = glm::length(p);
        ASSERT_LE(r, 1.0f + 1e-6f);
        ASSERT_GE(r, float(innerRadius) - 1e-6f);
    }
    for (size_t i = 0; i < image.normals.texels.size(); ++i) {
        // Vertex normals of a sphere cap point outwards, within the mesh's faceting.
        const glm::vec3 n = image.normals.texels[i], p = glm::normalize(image.positions.texels[i]);
        ASSERT_NEAR(glm::length(n), 1.0f, 1e-5f);
        ASSERT_GT(glm::dot(n, p), 0.99f);
    }
}

TEST(Rasterize, seamMatesShareTheirNormal)
{
    DiskMesh disk = test::bumpyHeightField(8);
    const SquareMap map = parameterizeToSquare(disk, ParameterizeOptions{ParameterizationMethod::Tutte});
    disk.originalVertex[map.corners[1]] = map.corners[0];  // pretend corners 0 and 1 are one vertex cut open
    const uint32_t R = 32;
    const RasterizedGeometryImage image = rasterizeGeometryImage(disk, map.uv, R);
    const glm::vec3 a = image.normals.at(0, 0), b = image.normals.at(R, 0);
    EXPECT_NEAR(a.x, b.x, 1e-6f);
    EXPECT_NEAR(a.y, b.y, 1e-6f);
    EXPECT_NEAR(a.z, b.z, 1e-6f);
}

TEST(Rasterize, rejectsMismatchedInput)
{
    const DiskMesh disk = test::planePatch(4);
    std::vector<glm::dvec2> uv(disk.mesh.positions.size() - 1, glm::dvec2(0.5));
    EXPECT_THROW(rasterizeGeometryImage(disk, uv, 16), Error);
    uv.emplace_back(std::numeric_limits<double>::quiet_NaN(), 0.0);
    EXPECT_THROW(rasterizeGeometryImage(disk, uv, 16), Error);
    uv.back() = glm::dvec2(0.5);
    EXPECT_THROW(rasterizeGeometryImage(disk, uv, 0), Error);
}

}  // namespace
}  // namespace ngi
