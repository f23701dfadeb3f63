// The bake pipeline on small procedural meshes: every topology bakes to a valid asset whose
// full-resolution geometry image reconstructs the input surface.
#include "ngi/asset.h"
#include "ngi/bake/bake.h"
#include "ngi/error.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/param/extremity_cut.h"
#if NGI_HAVE_EVAL
#include "ngi/eval/surface_distance.h"
#endif

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <tuple>

#include <nlohmann/json.hpp>

namespace {

ngi::BakeOptions smallBake()
{
    ngi::BakeOptions options;
    options.resolution = 64;
    options.storeResolution = 16;
    options.remeshVertexCount = 800;
    options.sourceName = "test";
    return options;
}

// Largest distance from the samples of `image` to the surface of `mesh` is checked by the
// metric when ngi_eval is there; this is a brute-force one-sided fallback (small meshes).
double pointTriangleDistance(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    // Ericson, Real-Time Collision Detection, 5.1.5 (closest point on a triangle).
    const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return glm::distance(p, a);
    const glm::dvec3 bp = p - b;
    const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return glm::distance(p, b);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return glm::distance(p, a + ab * (d1 / (d1 - d3)));
    const glm::dvec3 cp = p - c;
    const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return glm::distance(p, c);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return glm::distance(p, a + ac * (d2 / (d2 - d6)));
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return glm::distance(p, b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    const double denom = 1.0 / (va + vb + vc);
    return glm::distance(p, a + ab * (vb * denom) + ac * (vc * denom));
}

void expectBakes(const ngi::TriangleMesh& mesh, const char* name, double maxChamfer, double maxHausdorff,
                 bool matchSeams = true)
{
    SCOPED_TRACE(name);
    ngi::BakeOptions options = smallBake();
    options.matchSeams = matchSeams;
    ngi::BakeResult result = ngi::bakeMesh(mesh, options);
    const ngi::Asset& asset = result.asset;
    ASSERT_EQ(asset.charts.size(), 1u);
    ASSERT_EQ(result.report.charts.size(), 1u);
    const ngi::AssetChart& chart = asset.charts[0];
    const ngi::ChartReport& report = result.report.charts[0];
    EXPECT_EQ(chart.fullResolution, 64u);
    EXPECT_EQ(chart.storedLevel, 2u);
    EXPECT_EQ(chart.storedSize(), 17u);
    EXPECT_EQ(chart.positions.size(), 17u * 17u * 3u);
    EXPECT_EQ(asset.parameterization, "ot");
    EXPECT_EQ(report.parameterization.flippedTriangles, 0u);
    EXPECT_LT(report.parameterization.otResidual, 1e-3);
    // Uniform scale, longest side exactly [0,1].
    EXPECT_EQ(asset.scale.x, asset.scale.y);
    EXPECT_EQ(asset.scale.y, asset.scale.z);
    // The asset survives a serialize/parse round trip and carries the report and the seam.
    ngi::Asset back = ngi::parseAsset(ngi::serializeAsset(asset), name);
    nlohmann::json metadata = nlohmann::json::parse(back.metadataJson);
    EXPECT_TRUE(metadata["bake"].contains("parameterization"));
    // The seam is matched: mates of the full image are bitwise equal, the chart keeps the
    // seam, and the rasterized mates were already within rounding of each other.
    ASSERT_EQ(back.charts[0].seams.matched, matchSeams) << report.seam.problem;
    if (matchSeams) {
        EXPECT_EQ(back.charts[0].seams.segments.size(), report.seam.cutPaths);
        EXPECT_EQ(report.seam.cutPaths > 0, report.cut.cutEdges > 0);
        const std::vector<uint32_t> table = ngi::seamWeldTable(back.charts[0].seams, chart.fullResolution);
        EXPECT_EQ(ngi::measureSeamGap(result.charts[0].fullPositions, table).unequalMates, 0u);
        EXPECT_EQ(ngi::measureSeamGap(result.charts[0].fullNormals, table).unequalMates, 0u);
        glm::dvec3 lo(1e300), hi(-1e300);
        for (const glm::dvec3& p : mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
        EXPECT_LT(report.seamGapBeforeWeld, 1e-5 * glm::length(hi - lo));
        EXPECT_EQ(report.seam.flippedTriangles, 0u);
    }
    // The stored level is the nested subsample of the full image.
    ngi::GeometryImage stored = ngi::storedPositions(chart);
    for (uint32_t y = 0; y < stored.size; ++y)
        for (uint32_t x = 0; x < stored.size; ++x)
            EXPECT_NEAR(glm::distance(stored.at(x, y), result.charts[0].fullPositions.at(4 * x, 4 * y)), 0.0f, 1e-4f);

    // Reconstruction: the full-resolution image, back in object space, against the input.
    ngi::GeometryImage objectSpace = result.charts[0].fullPositions;
    for (glm::vec3& t : objectSpace.texels) t = asset.offset + asset.scale * t;
    ngi::TriangleMesh reconstructed = ngi::geometryImageMesh(objectSpace);
#if NGI_HAVE_EVAL
    ngi::SurfaceDistance d = ngi::surfaceDistance(mesh, reconstructed, {.sampleCount = 20000});
    EXPECT_LT(d.chamfer * ngi::kChamferReportScale, maxChamfer);
    EXPECT_LT(d.hausdorff * ngi::kHausdorffReportScale, maxHausdorff);
    std::printf("%s: CD %.4f x1e-4, HD %.4f x1e-2; seam: %zu paths, level %u, lengths %.1f%% (mismatch %.1f%%), "
                "area distortion max %.2f -> %.2f\n",
                name, d.chamfer * ngi::kChamferReportScale, d.hausdorff * ngi::kHausdorffReportScale,
                report.seam.cutPaths, report.seam.level, 100.0 * report.seam.lengthChange, 100.0 * report.seam.mismatch,
                report.parameterization.areaDistortionMax, report.seamAreaDistortionMax);
#else
    double side = double(asset.scale.x), worst = 0.0;
    for (size_t i = 0; i < reconstructed.positions.size(); i += 7) {
        double best = 1e300;
        for (const glm::uvec3& t : mesh.triangles)
            best = std::min(best,
                            pointTriangleDistance(reconstructed.positions[i], mesh.positions[t.x], mesh.positions[t.y],
                                                  mesh.positions[t.z]));
        worst = std::max(worst, best);
    }
    EXPECT_LT(worst / side * 100.0, maxHausdorff);
    (void)maxChamfer;
#endif
}

TEST(BakeMesh, EveryTopologyBakesAndReconstructs)
{
    expectBakes(ngi::makeSphere(3), "sphere", 5.0, 5.0);
    expectBakes(ngi::makeTorus(32, 16), "torus", 5.0, 5.0);
    // Matching the seam costs this coarse (64 cells) genus-2 surface most: its cut's two sides
    // differ by 29% of the border in the transport map (HD 2.6 unmatched, 9.1 matched).
    expectBakes(ngi::makeGenusSurface(2, 2), "double torus", 10.0, 10.0);
    expectBakes(ngi::makeGenusSurface(2, 2), "double torus unmatched", 10.0, 8.0, false);
    expectBakes(ngi::makeOpenCylinder(32, 8), "open cylinder", 5.0, 5.0);
    expectBakes(ngi::makePlanePatch(16, 1.0, 0.2), "plane", 5.0, 5.0);
}

// Three disjoint parts (a sphere, a torus, a small sphere): one chart each, nothing dropped,
// resolutions by area share within [kMinChartResolution, 64], and the charts together
// reconstruct the whole input.
TEST(BakeMesh, SeveralPartsBakeOneChartEachAndReconstruct)
{
    ngi::TriangleMesh mesh = ngi::makeSphere(3);
    auto append = [&](const ngi::TriangleMesh& part, glm::dvec3 offset) {
        const uint32_t base = uint32_t(mesh.positions.size());
        for (const glm::dvec3& p : part.positions) mesh.positions.push_back(p + offset);
        for (const glm::uvec3& t : part.triangles) mesh.triangles.push_back(t + glm::uvec3(base));
    };
    append(ngi::makeTorus(32, 16), {3.5, 0.0, 0.0});
    append(ngi::makeSphere(2, 0.3), {0.0, 2.5, 0.0});
    ngi::BakeOptions options = smallBake();
    options.remeshVertexCount = 2400;  // shared by area: ~800 for the largest part
    const ngi::BakeResult result = ngi::bakeMesh(mesh, options);
    ASSERT_EQ(result.asset.charts.size(), 3u);
    ASSERT_EQ(result.charts.size(), 3u);
    EXPECT_EQ(result.asset.charts[0].fullResolution, 64u);
    for (const ngi::AssetChart& chart : result.asset.charts) {
        EXPECT_GE(chart.fullResolution, ngi::kMinChartResolution);
        EXPECT_LE(chart.fullResolution, 64u);
        EXPECT_EQ(chart.storedLevel, 2u);  // one level for all: one network restores every chart
    }
    ngi::TriangleMesh reconstructed;
    for (const ngi::ChartBake& chart : result.charts) {
        ngi::GeometryImage objectSpace = chart.fullPositions;
        for (glm::vec3& t : objectSpace.texels) t = result.asset.offset + result.asset.scale * t;
        const ngi::TriangleMesh part = ngi::geometryImageMesh(objectSpace);
        const uint32_t base = uint32_t(reconstructed.positions.size());
        reconstructed.positions.insert(reconstructed.positions.end(), part.positions.begin(), part.positions.end());
        for (const glm::uvec3& t : part.triangles) reconstructed.triangles.push_back(t + glm::uvec3(base));
    }
#if NGI_HAVE_EVAL
    const ngi::SurfaceDistance d = ngi::surfaceDistance(mesh, reconstructed, {.sampleCount = 20000});
    std::printf("three parts: CD %.4f x1e-4, HD %.4f x1e-2\n", d.chamfer * ngi::kChamferReportScale,
                d.hausdorff * ngi::kHausdorffReportScale);
    // Measured 0.0094; dropping the smallest part alone would add about its area share (4%)
    // times its squared distance to the rest (~0.1), i.e. ~40 x1e-4.
    EXPECT_LT(d.chamfer * ngi::kChamferReportScale, 5.0);
    EXPECT_LT(d.hausdorff * ngi::kHausdorffReportScale, 5.0);
#endif
}

// A comb of unit voxels: a 1 x 1 spine of 2 * teeth - 1 cells along x, and `teeth` teeth of
// `length` cells along y from every other cell. Genus 0; the teeth are long protrusions that
// one chart's map squeezes to almost no samples.
ngi::TriangleMesh makeVoxelComb(int teeth, int length)
{
    std::vector<glm::ivec3> filled;
    for (int x = 0; x < 2 * teeth - 1; ++x) filled.push_back({x, 0, 0});
    for (int t = 0; t < teeth; ++t)
        for (int y = 1; y <= length; ++y) filled.push_back({2 * t, y, 0});
    auto isFilled = [&](glm::ivec3 c) { return std::find(filled.begin(), filled.end(), c) != filled.end(); };
    struct Face {
        glm::ivec3 normal;
        glm::ivec3 corners[4];
    };
    const Face faces[6] = {{{1, 0, 0}, {{1, 0, 0}, {1, 1, 0}, {1, 1, 1}, {1, 0, 1}}},
                           {{-1, 0, 0}, {{0, 0, 0}, {0, 0, 1}, {0, 1, 1}, {0, 1, 0}}},
                           {{0, 1, 0}, {{0, 1, 0}, {0, 1, 1}, {1, 1, 1}, {1, 1, 0}}},
                           {{0, -1, 0}, {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}},
                           {{0, 0, 1}, {{0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}}},
                           {{0, 0, -1}, {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}}}};
    ngi::TriangleMesh mesh;
    std::map<std::tuple<int, int, int>, uint32_t> index;
    auto vertex = [&](glm::ivec3 p) {
        const auto [it, inserted] = index.try_emplace({p.x, p.y, p.z}, uint32_t(mesh.positions.size()));
        if (inserted) mesh.positions.push_back(glm::dvec3(p));
        return it->second;
    };
    for (const glm::ivec3 cell : filled)
        for (const Face& f : faces) {
            if (isFilled(cell + f.normal)) continue;
            uint32_t v[4];
            for (int i = 0; i < 4; ++i) v[i] = vertex(cell + f.corners[i]);
            mesh.triangles.push_back({v[0], v[1], v[2]});
            mesh.triangles.push_back({v[0], v[2], v[3]});
        }
    return mesh;
}

TEST(BakeMesh, APartWhoseOneChartFailsItsChecksIsSplitInsteadOfRefused)
{
    // A sphere of radius 25 and, beside it, a comb of 8 teeth 30 long: the comb's share of the
    // surface (~15%) is too small for the thin-part split, and its one chart leaves 57% of its
    // surface below 1/100 of its fair share of samples (limit 20%), on the dense remesh and the
    // coarse one alike. Refused without the split; with it (the default), the comb is cut
    // into matched pieces that pass, with a warning naming the failed check.
    ngi::TriangleMesh mesh = ngi::makeSphere(4, 25.0);
    for (glm::dvec3& p : mesh.positions) p += glm::dvec3(-35.0, 15.0, 0.0);
    const ngi::TriangleMesh comb = makeVoxelComb(8, 30);
    const uint32_t base = uint32_t(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), comb.positions.begin(), comb.positions.end());
    for (const glm::uvec3& t : comb.triangles) mesh.triangles.push_back(t + glm::uvec3(base));

    ngi::BakeOptions options;
    options.resolution = 256;
    options.storeResolution = 64;
    options.sourceName = "comb";
    ngi::BakeOptions oneChart = options;
    oneChart.splitThinParts = 0;  // --no-split
    try {
        ngi::bakeMesh(mesh, oneChart);
        ADD_FAILURE() << "the comb's one chart was meant to fail its sampling check";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("fair share of samples"), std::string::npos) << e.what();
    }

    const ngi::BakeResult result = ngi::bakeMesh(mesh, options);
    ASSERT_GE(result.asset.charts.size(), 3u) << "the sphere's chart and at least two pieces of the comb";
    EXPECT_TRUE(ngi::anyComponentSplitForThinParts(result.report));
    size_t named = 0;
    for (const std::string& w : result.report.warnings)
        named += w.find("one chart failed its checks") != std::string::npos &&
            w.find("fair share of samples") != std::string::npos;
    EXPECT_EQ(named, 1u);
    ngi::TriangleMesh reconstructed;
    for (const ngi::ChartBake& chart : result.charts) {
        ngi::GeometryImage objectSpace = chart.fullPositions;
        for (glm::vec3& t : objectSpace.texels) t = result.asset.offset + result.asset.scale * t;
        const ngi::TriangleMesh part = ngi::geometryImageMesh(objectSpace);
        const uint32_t first = uint32_t(reconstructed.positions.size());
        reconstructed.positions.insert(reconstructed.positions.end(), part.positions.begin(), part.positions.end());
        for (const glm::uvec3& t : part.triangles) reconstructed.triangles.push_back(t + glm::uvec3(first));
    }
#if NGI_HAVE_EVAL
    // The comb is in the asset, teeth included: measured CD 0.057 x1e-4, HD 3.6 x1e-2 (the box's
    // longest side is 75 units, a tooth 30 long: a tooth left out would put HD near 40 x1e-2).
    const ngi::SurfaceDistance d = ngi::surfaceDistance(mesh, reconstructed, {.sampleCount = 20000});
    std::printf("sphere and comb: CD %.4f x1e-4, HD %.4f x1e-2\n", d.chamfer * ngi::kChamferReportScale,
                d.hausdorff * ngi::kHausdorffReportScale);
    EXPECT_LT(d.chamfer * ngi::kChamferReportScale, 0.5);
    EXPECT_LT(d.hausdorff * ngi::kHausdorffReportScale, 8.0);
#endif
}

TEST(BakeMesh, EveryParameterizationMethodBakes)
{
    for (const char* method : {"tutte", "harmonic", "ricci", "authalic", "ot"}) {
        ngi::BakeOptions options = smallBake();
        options.method = ngi::parseParameterizationMethod(method);
        ngi::BakeResult result = ngi::bakeMesh(ngi::makeTorus(32, 16), options);
        EXPECT_EQ(result.asset.parameterization, method);
        EXPECT_EQ(result.report.charts.at(0).parameterization.flippedTriangles, 0u) << method;
    }
}

// The remesh carries only the map: with the detail transfer every full-resolution sample lies
// on the INPUT surface (float rounding of the normalization aside), without it the samples
// interpolate the coarse remesh and sit up to its chord error inside the sphere.
TEST(BakeMesh, DetailTransferPutsEverySampleOnTheInputSurface)
{
    const ngi::TriangleMesh input = ngi::makeSphere(3);  // 1280 triangles
    auto farthestSample = [&](bool transfer) {
        ngi::BakeOptions options = smallBake();
        options.remeshVertexCount = 300;  // far coarser than the input
        options.transferDetail = transfer;
        const ngi::BakeResult result = ngi::bakeMesh(input, options);
        EXPECT_EQ(result.report.charts[0].detail.projected, transfer ? 65u * 65u : 0u);
        double worst = 0.0;
        for (const glm::vec3& t : result.charts[0].fullPositions.texels) {
            const glm::dvec3 p = glm::dvec3(result.asset.offset + result.asset.scale * t);
            double nearest = 1e300;
            for (const glm::uvec3& tri : input.triangles)
                nearest = std::min(
                    nearest,
                    pointTriangleDistance(p, input.positions[tri.x], input.positions[tri.y], input.positions[tri.z]));
            worst = std::max(worst, nearest);
        }
        return worst;
    };
    EXPECT_LT(farthestSample(true), 2e-6);   // float samples of a unit sphere
    EXPECT_GT(farthestSample(false), 5e-3);  // chord error of a 300-vertex remesh
}

TEST(BakeMesh, SearchesTheCutOnACoarseRemeshAndMakesItOnTheRemesh)
{
    // A torus remeshed at 1600 vertices with the search limit at 300: the cut search runs on a
    // ~300-vertex remesh (both cut graphs), the chosen cut is made on the 1600-vertex remesh,
    // and the map is as good as with the search on the remesh itself.
    auto bake = [](size_t searchVertices, std::vector<std::string>* stages) {
        ngi::BakeOptions options = smallBake();
        options.remeshVertexCount = 1600;
        options.cutSearchVertices = searchVertices;
        if (stages)
            options.stageDone = [stages](const std::string& stage, double, const std::string&) {
                stages->push_back(stage);
            };
        return ngi::bakeMesh(ngi::makeTorus(32, 16), options).report;
    };
    std::vector<std::string> stages;
    const ngi::BakeReport coarse = bake(300, &stages);
    const ngi::BakeReport direct = bake(0, nullptr);
    ASSERT_EQ(coarse.charts.size(), 1u);
    const ngi::ChartReport& c = coarse.charts[0];
    EXPECT_GT(c.cutSearchVertices, 200u);
    EXPECT_LT(c.cutSearchVertices, 500u);
    EXPECT_EQ(direct.charts[0].cutSearchVertices, 0u);
    EXPECT_GE(c.cutRounds, 3u);  // two cut graphs on the coarse remesh + the cut on the remesh
    EXPECT_EQ(c.cut.genus, 1);
    EXPECT_TRUE(std::isfinite(c.cutConformalShrink));
    EXPECT_LE(c.cutConformalShrink, ngi::ExtremityCutOptions{}.maxConformalShrink);
    EXPECT_EQ(c.parameterization.flippedTriangles, 0u);
    EXPECT_LT(c.parameterization.areaDistortionMean, direct.charts[0].parameterization.areaDistortionMean * 1.5 + 0.02);
    ASSERT_GE(stages.size(), 3u);
    EXPECT_EQ(stages[1], "cut search");  // after clean, before the remesh
    EXPECT_EQ(stages[2], "remesh");
}

TEST(BakeMesh, ReportsStagesInOrder)
{
    std::vector<std::string> stages;
    ngi::BakeOptions options = smallBake();
    options.stageDone = [&](const std::string& stage, double seconds, const std::string&) {
        stages.push_back(stage);
        EXPECT_GE(seconds, 0.0);
    };
    ngi::bakeMesh(ngi::makeSphere(2), options);
    EXPECT_EQ(
        stages,
        (std::vector<std::string>{"clean", "remesh", "cut", "parameterize", "match seams", "rasterize", "store"}));
}

TEST(BakeMesh, RejectsBadResolutions)
{
    ngi::BakeOptions options = smallBake();
    options.resolution = 100;
    EXPECT_THROW(ngi::bakeMesh(ngi::makeSphere(1), options), ngi::Error);
    options = smallBake();
    options.storeResolution = 128;
    EXPECT_THROW(ngi::bakeMesh(ngi::makeSphere(1), options), ngi::Error);
}

}  // namespace

namespace {

TEST(UndersampledArea, CountsTheSurfaceTheMapSqueezes)
{
    // Two triangles of equal 3D area (a unit square split along its diagonal). Identity uv:
    // nothing is squeezed. Moving the shared corner so that one triangle keeps 1/200 of the uv
    // area: exactly its half of the surface is undersampled at 1/100.
    ngi::TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    std::vector<glm::dvec2> uv = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    EXPECT_EQ(ngi::undersampledAreaFraction(mesh, uv, 100.0), 0.0);
    uv = {{0, 0}, {1, 0}, {1, 1}, {0, 0.005}};  // second triangle: area 0.0025 of 0.5025
    EXPECT_NEAR(ngi::undersampledAreaFraction(mesh, uv, 100.0), 0.5, 1e-12);
    EXPECT_EQ(ngi::undersampledAreaFraction(mesh, uv, 1.0 / 0.0025 * 0.5), 0.0);  // threshold below its share
}

}  // namespace
