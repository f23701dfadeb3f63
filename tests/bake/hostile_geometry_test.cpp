// Inputs the bake must take whatever their coordinates, stray parts or folds: a surface far from
// the origin (survey and CAD data) bakes as closely as at the origin, a part of (near) zero area
// beside a real surface is dropped with a warning instead of breaking the bake, and a surface
// folded back flat onto itself bakes instead of crashing the remesher.
#include "ngi/bake/bake.h"
#include "ngi/error.h"
#include "ngi/mesh/procedural_meshes.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace {

constexpr double kRadius = 2.0;

ngi::BakeOptions smallBake()
{
    ngi::BakeOptions options;
    options.resolution = 64;
    options.storeResolution = 16;
    options.remeshVertexCount = 800;
    options.sourceName = "far.obj";
    return options;
}

struct SphereError {
    double rms = 0.0, max = 0.0;
};

// How far the baked full images (BakeResult::charts, put back into the input's coordinates in
// double precision with the asset's offset and scale) are from the analytic sphere.
SphereError distanceToSphere(const ngi::BakeResult& result, const glm::dvec3& centre)
{
    const glm::dvec3 offset(result.asset.offset), scale(result.asset.scale);
    SphereError error;
    size_t count = 0;
    for (const ngi::ChartBake& chart : result.charts)
        for (const glm::vec3& t : chart.fullPositions.texels) {
            const double d = std::abs(glm::length(offset + scale * glm::dvec3(t) - centre) - kRadius);
            error.rms += d * d;
            error.max = std::max(error.max, d);
            ++count;
        }
    error.rms = std::sqrt(error.rms / double(count));
    return error;
}

bool anyWarningContains(const ngi::BakeResult& result, const std::string& text)
{
    return std::any_of(result.report.warnings.begin(), result.report.warnings.end(),
                       [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

ngi::TriangleMesh sphereAt(const glm::dvec3& centre)
{
    ngi::TriangleMesh sphere = ngi::makeSphere(3, kRadius);
    for (glm::dvec3& p : sphere.positions) p += centre;
    return sphere;
}

TEST(BakeFarFromOrigin, OffsetSphereBakesAsCloselyAsAtTheOrigin)
{
    const ngi::BakeResult atOrigin = ngi::bakeMesh(sphereAt(glm::dvec3(0.0)), smallBake());
    const SphereError reference = distanceToSphere(atOrigin, glm::dvec3(0.0));
    EXPECT_FALSE(anyWarningContains(atOrigin, "32-bit floats"));
    // The polyhedron's own distance to the sphere (1280 triangles): the origin bake's error.
    EXPECT_LT(reference.max, 0.02 * kRadius);
    // At 1e8 a float step is 8: the asset's box widens to cover the rounded offset, and a
    // warning says that float consumers lose the surface there; the stored shape does not.
    for (const glm::dvec3 centre :
         {glm::dvec3(5e5, 5e6, 100.0), glm::dvec3(1e8, 0.0, 0.0), glm::dvec3(1e8, 1e8, 1e8)}) {
        SCOPED_TRACE(centre.x);
        const ngi::BakeResult far = ngi::bakeMesh(sphereAt(centre), smallBake());
        const SphereError error = distanceToSphere(far, centre);
        // Within 1% (plus 1e-6 of the radius) of the origin bake's error, RMS and max.
        EXPECT_LE(error.rms, 1.01 * reference.rms + 1e-6 * kRadius);
        EXPECT_LE(error.max, 1.01 * reference.max + 1e-6 * kRadius);
        EXPECT_TRUE(anyWarningContains(far, "far.obj: the surface lies"));
        EXPECT_TRUE(anyWarningContains(far, "32-bit floats"));
    }
}

TEST(BakeFarFromOrigin, TheNormalizationCoversTheImageExactly)
{
    // Positions relative to a far centre: the float offset and scale must contain every sample
    // in the input's coordinates (offset <= centre + p <= offset + scale, exactly in double).
    ngi::GeometryImage image;
    image.size = 2;
    image.texels = {{-2.0f, -1.0f, -0.5f}, {2.0f, 1.0f, 0.5f}, {0.3f, -0.7f, 0.1f}, {1.9f, 0.9f, -0.4f}};
    for (const glm::dvec3 centre : {glm::dvec3(0.0), glm::dvec3(5e5, 5e6, 100.0), glm::dvec3(1e8, -1e8, 3.3e7)}) {
        glm::vec3 offset, scale;
        ngi::normalizationFor(image, centre, offset, scale);
        for (const glm::vec3& p : image.texels)
            for (int i = 0; i < 3; ++i) {
                const double world = centre[i] + double(p[i]);
                EXPECT_LE(double(offset[i]), world) << centre.x;
                EXPECT_LE(world, double(offset[i]) + double(scale[i])) << centre.x;
            }
        // The box widens by at most a float step of the distance from the origin.
        const double step = std::max(1.0, std::abs(centre.x) + std::abs(centre.y) + std::abs(centre.z)) * 0x1p-23;
        EXPECT_LE(double(scale.x), 4.0 + 2.0 * step) << centre.x;
    }
}

TEST(BakeNearZeroArea, ASliverBesideASphereIsDroppedWithAWarning)
{
    ngi::TriangleMesh mesh = sphereAt(glm::dvec3(0.0));
    const uint32_t base = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {{3.0, 0.0, 0.0}, {1003.0, 0.0, 0.0}, {503.0, 1e-7, 0.0}});
    mesh.triangles.push_back({base, base + 1, base + 2});
    const ngi::BakeResult result = ngi::bakeMesh(mesh, smallBake());
    EXPECT_EQ(result.charts.size(), 1u);
    EXPECT_EQ(result.report.clean.droppedZeroAreaComponents, 1u);
    EXPECT_TRUE(anyWarningContains(result, "far.obj: dropped 1 of 2 components for (near) zero area"));
    EXPECT_LT(distanceToSphere(result, glm::dvec3(0.0)).max, 0.02 * kRadius);
}

TEST(BakeFlatFold, AFanFoldedOntoItselfBakesWithTheLastResortMap)
{
    // Seven vertices in a plane, seven triangles around the origin, two folded back onto their
    // neighbours: ngi-bake crashed on it (SIGSEGV in CGAL's tangential relaxation), then refused
    // it (its remesh changes the topology). It has a surface, so it bakes: the last-resort map
    // takes the part as it is, and every sample stays in its plane and inside its outline.
    ngi::TriangleMesh fan;
    fan.positions = {{0, 0, 0}, {2, -2, 0}, {2, 0, 0}, {1, 1, 0}, {0, 2, 0}, {-2, 2, 0}, {-1, 0, 0}};
    fan.triangles = {{4, 3, 1}, {0, 2, 3}, {0, 3, 4}, {0, 4, 5}, {0, 5, 6}, {0, 6, 1}, {3, 6, 1}};
    // ngi-bake's defaults (the remesh is dense enough to split the folds; about 40 s).
    ngi::BakeOptions options;
    options.sourceName = "fan.obj";
    const ngi::BakeResult result = ngi::bakeMesh(fan, options);
    ASSERT_FALSE(result.charts.empty());
    EXPECT_TRUE(anyWarningContains(result, "fan.obj: baked with the last-resort map"));
    const glm::dvec3 offset(result.asset.offset), scale(result.asset.scale);
    double offPlane = 0.0, outside = 0.0;
    for (const ngi::ChartBake& chart : result.charts)
        for (const glm::vec3& t : chart.fullPositions.texels) {
            const glm::dvec3 p = offset + scale * glm::dvec3(t);
            offPlane = std::max(offPlane, std::abs(p.z));
            outside = std::max({outside, std::abs(p.x) - 2.0, std::abs(p.y) - 2.0});
        }
    EXPECT_LT(offPlane, 1e-4);  // the input's size is 4: 16-bit steps are 6e-5
    EXPECT_LT(outside, 1e-4);
}

}  // namespace
