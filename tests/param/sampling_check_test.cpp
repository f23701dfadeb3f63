// The bake's refusal of a badly undersampled chart (sampling_check.h) on a synthetic map: a
// strip of unit quads whose uv map squeezes some of them.
#include "ngi/error.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/param/detail_transfer.h"
#include "ngi/param/sampling_check.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace ngi {
namespace {

// A 1 x 10 strip of unit quads (two triangles each) in the plane z = 0, and a uv map that
// gives the first `squeezed` quads a width `squeeze` (relative to 1) and the rest width 1.
struct Strip {
    TriangleMesh mesh;
    std::vector<glm::dvec2> uv;
};
Strip strip(int squeezed, double squeeze)
{
    Strip s;
    double x = 0.0;
    for (int i = 0; i <= 10; ++i) {
        s.mesh.positions.push_back({double(i), 0.0, 0.0});
        s.mesh.positions.push_back({double(i), 1.0, 0.0});
        s.uv.push_back({x, 0.0});
        s.uv.push_back({x, 1.0});
        x += i < squeezed ? squeeze : 1.0;
    }
    for (uint32_t i = 0; i < 10; ++i) {
        const uint32_t a = 2 * i, b = 2 * i + 1, c = 2 * i + 2, d = 2 * i + 3;
        s.mesh.triangles.push_back({a, c, d});
        s.mesh.triangles.push_back({a, d, b});
    }
    return s;
}

TEST(SamplingCheck, CountsTheAreaBelowAHundredthOfItsShare)
{
    // 3 of 10 quads at 1e-3 of the width: their uv share is ~1.4e-4 of the fair 0.1.
    Strip s = strip(3, 1e-3);
    EXPECT_NEAR(mapUndersampledAreaFraction(s.mesh, s.uv), 0.3, 1e-12);
    // At 1/20 of the width they get 1/14 of their share: squeezed, but above 1/100.
    s = strip(3, 0.05);
    EXPECT_EQ(mapUndersampledAreaFraction(s.mesh, s.uv), 0.0);
    // A uniform map, and a map of zero area.
    s = strip(0, 1.0);
    EXPECT_EQ(mapUndersampledAreaFraction(s.mesh, s.uv), 0.0);
    for (glm::dvec2& x : s.uv) x = glm::dvec2(0.5);
    EXPECT_EQ(mapUndersampledAreaFraction(s.mesh, s.uv), 0.0);
}

TEST(SamplingCheck, FailsAboveTheThresholdWithAMessageNamingTheChart)
{
    ChartSamplingContext context{.file = "cheese.off", .chart = 1, .charts = 3, .genus = 133};
    const Strip ok = strip(2, 1e-3), bad = strip(3, 1e-3);
    EXPECT_NO_THROW(checkChartSampling(mapUndersampledAreaFraction(ok.mesh, ok.uv), context));  // 20%: at the limit
    try {
        checkChartSampling(mapUndersampledAreaFraction(bad.mesh, bad.uv), context);
        FAIL() << "30% undersampled was accepted";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("cheese.off"), std::string::npos) << message;
        EXPECT_NE(message.find("chart 2 of 3"), std::string::npos) << message;
        EXPECT_NE(message.find("genus 133"), std::string::npos) << message;
        EXPECT_NE(message.find("30.0%"), std::string::npos) << message;
        EXPECT_NE(message.find("limit 20%"), std::string::npos) << message;
    }
    context.maxUndersampledAreaFraction = 0.5;  // a caller may allow more
    EXPECT_NO_THROW(checkChartSampling(mapUndersampledAreaFraction(bad.mesh, bad.uv), context));
    EXPECT_NO_THROW(checkChartSampling(std::nan(""), context));  // no measure: nothing to refuse
}

TEST(ImageCheck, RefusesAnImageThatLeavesTheInputAndNamesTheChart)
{
    // The input: a unit sphere. The "image": the same sphere with every vertex above z = 0.8
    // (~10% of the area) pushed out by 20% of the size: far more than 2% of it is more than 5%
    // of the size away; the sphere itself is not.
    const TriangleMesh input = makeSphere(4);
    TriangleMesh spiky = input;
    for (glm::dvec3& p : spiky.positions)
        if (p.z > 0.8) p *= 1.0 + 0.2 * 2.0;  // size (longest side) 2: 20% of it
    const double distance = kFarFromImageDistance * 2.0;
    const double same = areaFartherThan(input, input, distance);
    const double far = std::max(areaFartherThan(input, spiky, distance), areaFartherThan(spiky, input, distance));
    EXPECT_EQ(same, 0.0);
    EXPECT_GT(far, 0.05);
    EXPECT_LT(far, 0.3);
    const ChartSamplingContext context{.file = "cheese.off", .chart = 0, .charts = 1, .genus = 133};
    EXPECT_NO_THROW(checkChartImage(same, context));
    EXPECT_NO_THROW(checkChartImage(kMaxFarFromImageArea, context));  // at the limit
    try {
        checkChartImage(far, context);
        FAIL() << "an image " << far << " of whose area is far off was accepted";
    } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("cheese.off: chart 1 of 1 (genus 133)"), std::string::npos) << message;
        EXPECT_NE(message.find("limit 2%"), std::string::npos) << message;
    }
}

TEST(ImageCheck, AreaFartherThanAgreesWithAnUnboundedClosestPointSearch)
{
    // areaFartherThan bounds each search by the distance asked (a stand-in closest point just
    // beyond it); the unbounded search of squaredDistancesToSurface must classify every
    // centroid the same, at distances from a hair to the whole size.
    const TriangleMesh input = makeSphere(3);
    TriangleMesh bumpy = makeSphere(4);
    for (glm::dvec3& p : bumpy.positions) p *= 1.0 + 0.15 * std::sin(5.0 * p.x) * std::cos(3.0 * p.z);
    std::vector<glm::dvec3> centroids;
    std::vector<double> area;
    for (const glm::uvec3& t : bumpy.triangles) {
        const glm::dvec3 a = bumpy.positions[t.x], b = bumpy.positions[t.y], c = bumpy.positions[t.z];
        centroids.push_back((a + b + c) / 3.0);
        area.push_back(0.5 * glm::length(glm::cross(b - a, c - a)));
    }
    const std::vector<double> d2 = squaredDistancesToSurface(input, centroids);
    int between = 0;
    for (double distance : {1e-4, 0.01, 0.03, 0.06, 0.1, 0.5, 3.0}) {
        double total = 0.0, far = 0.0;
        for (size_t t = 0; t < area.size(); ++t) total += area[t], far += d2[t] > distance * distance ? area[t] : 0.0;
        EXPECT_NEAR(areaFartherThan(bumpy, input, distance), far / total, 1e-12) << "distance " << distance;
        between += far > 0.0 && far < total;
    }
    EXPECT_GE(between, 3);  // the distances cut through the bumps, not only all or nothing
}

}  // namespace
}  // namespace ngi
