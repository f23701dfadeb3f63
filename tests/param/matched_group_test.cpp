// The matched border of a group of charts (matched_group.h): a sphere cut into Voronoi pieces,
// each mapped to its own square, then matched together: every shared curve's border samples
// are the same surface point in both charts at every level down to the group's level K.
#include "ngi/mesh/chart_split.h"
#include "ngi/mesh/cut.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/param/matched_group.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace {

double partitionArea(const ngi::TriangleMesh& mesh)
{
    double a = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        a += 0.5 *
            glm::length(
                 glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
    return a;
}

struct Piece {
    ngi::DiskMesh disk;
    ngi::SquareMap map;
    uint32_t resolution = 0;
    std::vector<uint32_t> groupVertex;
};

// The 3D point at perimeter parameter t (full-resolution samples) of a chart's border: on the
// boundary edge whose ends' perimeter parameters bracket t, linear along it (what the
// rasterizer samples on the border).
glm::dvec3 borderPoint(const Piece& p, const std::vector<glm::dvec2>& uv, double t)
{
    const double R = p.resolution;
    auto parameter = [&](const glm::dvec2& x) {
        const double eps = 1e-12;
        if (x.y <= eps && x.x < 1.0 - eps) return x.x * R;
        if (x.x >= 1.0 - eps && x.y < 1.0 - eps) return (1.0 + x.y) * R;
        if (x.y >= 1.0 - eps && x.x > eps) return (3.0 - x.x) * R;
        return x.y <= eps ? 0.0 : (4.0 - x.y) * R;
    };
    const std::vector<uint32_t>& loop = p.disk.boundaryLoop;
    const size_t n = loop.size();
    for (size_t j = 0; j < n; ++j) {
        const uint32_t a = loop[j], b = loop[(j + 1) % n];
        double ta = parameter(uv[a]), tb = parameter(uv[b]);
        if (tb < ta) tb += 4.0 * R;  // the edge that wraps past corner (0, 0)
        for (double tt : {t, t + 4.0 * R})
            if (tt >= ta - 1e-9 && tt <= tb + 1e-9) {
                const double w = tb > ta ? std::clamp((tt - ta) / (tb - ta), 0.0, 1.0) : 0.0;
                return (1.0 - w) * p.disk.mesh.positions[a] + w * p.disk.mesh.positions[b];
            }
    }
    ADD_FAILURE() << "no border edge holds perimeter parameter " << t;
    return {};
}

// Resolutions: 64 for the whole sphere's area, each piece its share as the bake gives it (a
// power of two in log2, at least 16).
std::vector<Piece> sphereInPieces(uint32_t pieces, ngi::ParameterizationMethod method)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(4);
    const ngi::ChartPartition partition = ngi::partitionByGeodesicVoronoi(sphere, {.pieces = pieces});
    std::vector<std::vector<uint32_t>> source;
    const std::vector<ngi::TriangleMesh> meshes = ngi::splitIntoPieces(sphere, partition.pieceOfFace, &source);
    std::vector<Piece> out(meshes.size());
    for (size_t i = 0; i < meshes.size(); ++i) {
        const ngi::CutResult cut = ngi::cutToDisk(meshes[i]);
        out[i].disk = cut.disk;
        out[i].map = ngi::parameterizeToSquare(out[i].disk, {.method = method});
        const double share = partitionArea(meshes[i]) / partitionArea(sphere);
        out[i].resolution = std::max(16u, 1u << uint32_t(std::lround(std::log2(64.0 * std::sqrt(share)))));
        out[i].groupVertex.assign(out[i].disk.mesh.positions.size(), ngi::kNoGroupVertex);
        for (size_t v = 0; v < out[i].disk.mesh.positions.size(); ++v) {
            const uint32_t original = out[i].disk.originalVertex[v];
            if (original < source[i].size()) out[i].groupVertex[v] = source[i][original];
        }
    }
    return out;
}

void expectSharedCurvesMatch(const std::vector<Piece>& pieces, const ngi::MatchedGroup& group)
{
    ASSERT_TRUE(group.matched) << group.problem;
    ASSERT_FALSE(group.crossSeams.empty());
    for (size_t c = 0; c < pieces.size(); ++c) {
        EXPECT_TRUE(group.charts[c].seams.matched);
        EXPECT_EQ(group.charts[c].report.flippedTriangles, 0u);
        // The corners are on the corners.
        const auto& uv = group.charts[c].uv;
        const glm::dvec2 corner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (int k = 0; k < 4; ++k) EXPECT_LT(glm::distance(uv[group.charts[c].corners[k]], corner[k]), 1e-9);
    }
    // Every chart's perimeter is covered by its curves at most once, and the curves' samples
    // are one surface point on both sides at every level 0..K.
    size_t checked = 0;
    for (const ngi::CrossSeamSegment& s : group.crossSeams) {
        ASSERT_LT(s.chartA, s.chartB);
        EXPECT_EQ(s.a % (1u << group.level), 0u);
        EXPECT_EQ(s.b % (1u << group.level), 0u);
        EXPECT_EQ(s.length % (1u << group.level), 0u);
        EXPECT_LE(s.a + s.length, 4 * pieces[s.chartA].resolution);
        EXPECT_LE(s.b + s.length, 4 * pieces[s.chartB].resolution);
        for (uint32_t level = 0; level <= group.level; ++level) {
            const uint32_t step = 1u << level;
            for (uint32_t i = 0; i <= s.length; i += step) {
                const glm::dvec3 pa = borderPoint(pieces[s.chartA], group.charts[s.chartA].uv, s.a + i);
                const glm::dvec3 pb = borderPoint(pieces[s.chartB], group.charts[s.chartB].uv, s.b + s.length - i);
                ASSERT_LT(glm::distance(pa, pb), 1e-9) << "curve " << s.chartA << ":" << s.a << " ~ " << s.chartB << ":"
                                                       << s.b << " at " << i << ", level " << level;
                ++checked;
            }
        }
    }
    EXPECT_GT(checked, 100u);
}

// Three pieces of resolutions 64, 32, 32 could not be matched at all (the 64 would need all of
// both others' borders and more); the bake's area shares give about equal pieces equal ones.
TEST(MatchBorders, VoronoiPiecesOfASphereShareTheirCurvesAtEveryLevel)
{
    const std::vector<Piece> pieces = sphereInPieces(3, ngi::ParameterizationMethod::Tutte);
    ASSERT_EQ(pieces.size(), 3u);
    std::vector<ngi::GroupChart> charts;
    for (const Piece& p : pieces) charts.push_back({&p.disk, &p.map, p.resolution, p.groupVertex});
    const ngi::MatchedGroup group = ngi::matchBorders(charts, 3);
    expectSharedCurvesMatch(pieces, group);
    EXPECT_GE(group.level, 1u);
    EXPECT_EQ(group.sharedCurves, group.crossSeams.size());
}

TEST(MatchBorders, SixOptimalTransportPiecesMatchToo)
{
    const std::vector<Piece> pieces = sphereInPieces(6, ngi::ParameterizationMethod::OptimalTransport);
    std::vector<ngi::GroupChart> charts;
    for (const Piece& p : pieces) charts.push_back({&p.disk, &p.map, p.resolution, p.groupVertex});
    const ngi::MatchedGroup group = ngi::matchBorders(charts, 3);
    expectSharedCurvesMatch(pieces, group);
}

TEST(MatchBorders, TwoDisksOfUnequalPerimeterSharingTheirWholeBorderAreRefused)
{
    // Two hemispheres: each is bounded by the one curve they share, so the curve would need
    // 4 x 64 samples in one chart and 4 x 32 in the other.
    std::vector<Piece> pieces = sphereInPieces(2, ngi::ParameterizationMethod::Tutte);
    ASSERT_EQ(pieces.size(), 2u);
    pieces[0].resolution = 64, pieces[1].resolution = 32;
    std::vector<ngi::GroupChart> charts;
    for (const Piece& p : pieces) charts.push_back({&p.disk, &p.map, p.resolution, p.groupVertex});
    const ngi::MatchedGroup group = ngi::matchBorders(charts, 3);
    EXPECT_FALSE(group.matched);
    EXPECT_NE(group.problem.find("no integer matching"), std::string::npos) << group.problem;
    for (size_t c = 0; c < 2; ++c) EXPECT_EQ(group.charts[c].uv, pieces[c].map.uv) << "maps returned unchanged";
    // With equal resolutions the same curve matches.
    charts[1].resolution = 64;
    std::vector<Piece> equal = pieces;
    equal[1].resolution = 64;
    expectSharedCurvesMatch(equal, ngi::matchBorders(charts, 3));
}

}  // namespace
