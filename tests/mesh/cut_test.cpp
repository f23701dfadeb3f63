// Stage 4: the cut produces a disk for every topology, and the seam mates are consistent.
#include "ngi/error.h"
#include "ngi/mesh/cut.h"
#include "ngi/mesh/mesh_topology.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/mesh/remesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <algorithm>
#include <set>

namespace {

void expectDisk(const ngi::TriangleMesh& input, const char* name, long genus, size_t loops,
                const ngi::CutOptions& options = {})
{
    SCOPED_TRACE(name);
    ngi::CutResult cut = ngi::cutToDisk(input, options);
    const ngi::TriangleMesh& mesh = cut.uncut;  // input + midpoints of split bridge edges
    ASSERT_GE(mesh.positions.size(), input.positions.size());
    for (size_t v = 0; v < input.positions.size(); ++v) EXPECT_EQ(mesh.positions[v], input.positions[v]);
    EXPECT_EQ(mesh.triangles.size(), input.triangles.size() + 2 * cut.report.splitBridgeEdges);
    const ngi::DiskMesh& disk = cut.disk;
    EXPECT_EQ(cut.report.genus, genus);
    EXPECT_EQ(cut.report.boundaryLoops, loops);
    ngi::MeshTopology topology = ngi::analyzeTopology(disk.mesh);
    EXPECT_EQ(topology.eulerCharacteristic, 1);
    EXPECT_EQ(topology.boundaryLoops, 1u);
    EXPECT_EQ(topology.components, 1u);
    EXPECT_EQ(topology.nonManifoldEdges, 0u);
    // Triangles keep order and orientation: mapping back gives the input triangles.
    ASSERT_EQ(disk.mesh.triangles.size(), mesh.triangles.size());
    ASSERT_EQ(disk.originalVertex.size(), disk.mesh.positions.size());
    for (size_t f = 0; f < mesh.triangles.size(); ++f) {
        const glm::uvec3& t = disk.mesh.triangles[f];
        EXPECT_EQ(glm::uvec3(disk.originalVertex[t.x], disk.originalVertex[t.y], disk.originalVertex[t.z]),
                  mesh.triangles[f]);
    }
    for (size_t v = 0; v < disk.mesh.positions.size(); ++v)
        EXPECT_EQ(disk.mesh.positions[v], mesh.positions[disk.originalVertex[v]]);
    // Boundary loop: every vertex once, consecutive vertices joined by a boundary edge that
    // follows its triangle's orientation.
    std::set<uint32_t> unique(disk.boundaryLoop.begin(), disk.boundaryLoop.end());
    EXPECT_EQ(unique.size(), disk.boundaryLoop.size());
    // No triangle has all three vertices on the boundary (none can be squashed onto a side).
    for (const glm::uvec3& t : disk.mesh.triangles)
        EXPECT_FALSE(unique.count(t.x) && unique.count(t.y) && unique.count(t.z));
    EXPECT_EQ(cut.report.diskBoundaryVertices, disk.boundaryLoop.size());
    // Seam: every cut edge appears twice, in opposite directions; original boundary edges once.
    ngi::SeamEdges seam = ngi::findSeamEdges(disk);
    const size_t n = disk.boundaryLoop.size();
    EXPECT_EQ(seam.mates.size() * 2 + seam.unmatched.size(), n);
    EXPECT_EQ(seam.mates.size(), cut.report.cutEdges);
    for (auto [i, j] : seam.mates) {
        uint32_t a0 = disk.originalVertex[disk.boundaryLoop[i]],
                 a1 = disk.originalVertex[disk.boundaryLoop[(i + 1) % n]];
        uint32_t b0 = disk.originalVertex[disk.boundaryLoop[j]],
                 b1 = disk.originalVertex[disk.boundaryLoop[(j + 1) % n]];
        EXPECT_EQ(a0, b1);
        EXPECT_EQ(a1, b0);
    }
    size_t originalBoundaryEdges = 0;
    ngi::MeshEdges edges = ngi::buildMeshEdges(mesh);
    for (uint32_t e = 0; e < edges.vertices.size(); ++e) originalBoundaryEdges += edges.isBoundary(e);
    EXPECT_EQ(seam.unmatched.size(), originalBoundaryEdges);
    if (genus > 0 || loops != 1) {
        EXPECT_GT(cut.report.cutLength, 0.0);
    }
}

TEST(CutToDisk, SphereTorusGenusTwoCylinderPlane)
{
    expectDisk(ngi::makeSphere(2), "sphere", 0, 0);
    expectDisk(ngi::makeTorus(24, 12), "torus", 1, 0);
    expectDisk(ngi::makeGenusSurface(2, 2), "double torus", 2, 0);
    expectDisk(ngi::makeGenusSurface(3, 1), "genus 3", 3, 0);
    expectDisk(ngi::makeOpenCylinder(24, 6), "open cylinder", 0, 2);
    expectDisk(ngi::makePlanePatch(8), "plane", 0, 1);
}

TEST(CutToDisk, AClosedSurfaceWhoseCutIsOneEdgeIsOpenedAtItsMidpoint)
{
    // A flat quad with a triangle pair on each side (CAD files carry such zero-volume closed
    // parts): its far vertices are joined by one edge, and a one-edge slit separates no corner.
    ngi::TriangleMesh quad;
    quad.positions = {{0, 0, 0}, {3, 5, 6}, {3, 5, 0}, {0, 0, 6}};
    quad.triangles = {{0, 1, 2}, {1, 0, 3}, {3, 2, 1}, {2, 3, 0}};
    for (const ngi::CutGraph graph : {ngi::CutGraph::TreeCotree, ngi::CutGraph::FacePeeling}) {
        const ngi::CutResult cut = ngi::cutToDisk(quad, {.graph = graph});
        const ngi::MeshTopology t = ngi::analyzeTopology(cut.disk.mesh);
        EXPECT_EQ(t.eulerCharacteristic, 1);
        EXPECT_EQ(t.boundaryLoops, 1u);
        EXPECT_EQ(cut.uncut.positions.size(), 5u);  // the midpoint added
        EXPECT_EQ(cut.report.cutEdges, 2u);
    }
}

TEST(CutToDisk, FacePeelingGivesADiskForEveryTopology)
{
    const ngi::CutOptions peel{.graph = ngi::CutGraph::FacePeeling};
    expectDisk(ngi::makeTorus(24, 12), "torus", 1, 0, peel);
    expectDisk(ngi::makeGenusSurface(2, 2), "double torus", 2, 0, peel);
    expectDisk(ngi::makeGenusSurface(3, 1), "genus 3", 3, 0, peel);
    expectDisk(ngi::makeOpenCylinder(24, 6), "open cylinder", 0, 2, peel);
    EXPECT_EQ(ngi::cutToDisk(ngi::makeTorus(24, 12), peel).report.method, "face peeling");
}

TEST(CutToDisk, ExtremityPathsKeepADiskAndReachTheTip)
{
    // Paths from far vertices of a sphere, a torus and a plane patch to their cuts: each adds a
    // slit, the result is still a disk, and the tip becomes a boundary vertex.
    struct Case {
        const char* name;
        ngi::TriangleMesh mesh;
        long genus;
        size_t loops;
    };
    for (Case c : {Case{"sphere", ngi::makeSphere(3), 0, 0}, Case{"torus", ngi::makeTorus(24, 12), 1, 0},
                   Case{"plane", ngi::makePlanePatch(12), 0, 1}}) {
        ngi::CutOptions options;
        const uint32_t tipA = uint32_t(c.mesh.positions.size() / 3), tipB = uint32_t(2 * c.mesh.positions.size() / 3);
        options.extremities = {tipA, tipB};
        const size_t before = ngi::cutToDisk(c.mesh).report.cutEdges;
        expectDisk(c.mesh, c.name, c.genus, c.loops, options);
        const ngi::CutResult cut = ngi::cutToDisk(c.mesh, options);
        SCOPED_TRACE(c.name);
        EXPECT_GE(cut.report.extremityPaths, 1u);
        EXPECT_GT(cut.report.cutEdges, before);
        EXPECT_GT(cut.report.extremityLength, 0.0);
        for (uint32_t tip : {tipA, tipB}) {
            bool onBoundary = false;
            for (uint32_t v : cut.disk.boundaryLoop) onBoundary = onBoundary || cut.disk.originalVertex[v] == tip;
            EXPECT_TRUE(onBoundary) << "tip " << tip;
        }
    }
    ngi::CutOptions bad;
    bad.extremities = {1u << 30};
    EXPECT_THROW(ngi::cutToDisk(ngi::makeSphere(2), bad), ngi::Error);
}

TEST(CutToDisk, TheSurfacesOwnBoundaryIsMarkedOnlyOnRequestAndNeverAlongTheCut)
{
    // A plane patch cut through an extremity: its 48 border vertices are marked, the slit's
    // copies and its tip are not. A closed sphere has nothing to mark.
    const ngi::TriangleMesh plane = ngi::makePlanePatch(12);
    ngi::CutOptions options;
    options.extremities = {uint32_t(plane.positions.size() / 2)};
    EXPECT_TRUE(ngi::cutToDisk(plane, options).disk.surfaceBoundary.empty());
    options.cornersAtBoundaryTurns = true;
    const ngi::CutResult cut = ngi::cutToDisk(plane, options);
    ASSERT_EQ(cut.disk.surfaceBoundary.size(), cut.disk.mesh.positions.size());
    std::set<uint32_t> marked;
    for (size_t v = 0; v < cut.disk.mesh.positions.size(); ++v)
        if (cut.disk.surfaceBoundary[v]) {
            const glm::dvec3 p = cut.disk.mesh.positions[v];
            const bool onBorder = std::min({p.x, p.y, 1.0 - p.x, 1.0 - p.y}) < 1e-9;
            EXPECT_TRUE(onBorder) << "vertex " << v << " at " << p.x << ", " << p.y;
            marked.insert(cut.disk.originalVertex[v]);
        }
    EXPECT_EQ(marked.size(), 48u);
    EXPECT_EQ(marked.count(options.extremities[0]), 0u);
    ngi::CutOptions closed;
    closed.cornersAtBoundaryTurns = true;
    const ngi::CutResult sphere = ngi::cutToDisk(ngi::makeSphere(3), closed);
    EXPECT_EQ(std::count(sphere.disk.surfaceBoundary.begin(), sphere.disk.surfaceBoundary.end(), 1), 0);
}

TEST(CutToDisk, CornerHintsAreJunctionCopiesForHandles)
{
    for (const ngi::TriangleMesh& mesh : {ngi::makeTorus(24, 12), ngi::makeGenusSurface(2, 2)}) {
        ngi::CutResult cut = ngi::cutToDisk(mesh);
        const ngi::DiskMesh& disk = cut.disk;
        ASSERT_EQ(disk.cornerHints.size(), 4u);
        std::vector<size_t> positions;
        for (uint32_t v : disk.cornerHints) {
            size_t copies = 0;
            for (uint32_t w : disk.boundaryLoop) copies += disk.originalVertex[w] == disk.originalVertex[v];
            EXPECT_GE(copies, 3u);  // a junction of the cut graph
            positions.push_back(
                size_t(std::find(disk.boundaryLoop.begin(), disk.boundaryLoop.end(), v) - disk.boundaryLoop.begin()));
        }
        EXPECT_TRUE(std::is_sorted(positions.begin(), positions.end()));
        EXPECT_LT(positions.back(), disk.boundaryLoop.size());
    }
    EXPECT_TRUE(ngi::cutToDisk(ngi::makeSphere(2)).disk.cornerHints.empty());
    EXPECT_TRUE(ngi::cutToDisk(ngi::makePlanePatch(8)).disk.cornerHints.empty());
}

TEST(CutToDisk, HandlesAndBoundariesTogether)
{
    // A torus with two holes punched in it: genus 1, two boundary loops.
    ngi::TriangleMesh torus = ngi::makeTorus(24, 12);
    std::vector<glm::uvec3> kept;
    for (size_t f = 0; f < torus.triangles.size(); ++f)
        if (f != 10 && f != 11 && f != 200 && f != 201) kept.push_back(torus.triangles[f]);
    torus.triangles = kept;
    expectDisk(torus, "torus with two holes", 1, 2);
}

TEST(CutToDisk, CutOfRemeshedTorusIsShort)
{
    // The two handle loops of a torus of radii 1 and 0.35 are at least 2 pi 0.35 and 2 pi 0.65
    // long; the greedy tree-cotree cut should be close to the sum of the shortest ones.
    ngi::RemeshResult remeshed = ngi::remeshIsotropic(ngi::makeTorus(48, 24), {.targetVertexCount = 3000});
    ngi::CutResult cut = ngi::cutToDisk(remeshed.mesh);
    EXPECT_LT(cut.report.cutLength, 1.6 * (2 * std::numbers::pi * 0.35 + 2 * std::numbers::pi * 0.65));
}

}  // namespace
