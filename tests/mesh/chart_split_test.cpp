// Geodesic Voronoi partition into charts (chart_split.h): every face in one piece, pieces
// connected and of comparable area, split meshes manifold and together the whole surface.
#include "ngi/error.h"
#include "ngi/mesh/chart_split.h"
#include "ngi/mesh/mesh_topology.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/mesh/remesh.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace {

double area(const ngi::TriangleMesh& mesh)
{
    double a = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        a += 0.5 *
            glm::length(
                 glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
    return a;
}

// The faces of `mesh` labelled `piece`, sharing the input's vertices.
ngi::TriangleMesh facesOf(const ngi::TriangleMesh& mesh, const std::vector<uint32_t>& label, uint32_t piece)
{
    ngi::TriangleMesh out;
    out.positions = mesh.positions;
    for (size_t f = 0; f < mesh.triangles.size(); ++f)
        if (label[f] == piece) out.triangles.push_back(mesh.triangles[f]);
    return out;
}

TEST(ChartSplit, VoronoiPiecesCoverTheSphereAreConnectedAndComparable)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(4);  // 5120 triangles
    const ngi::ChartPartition partition = ngi::partitionByGeodesicVoronoi(sphere, {.pieces = 6});
    ASSERT_EQ(partition.pieces, 6u);
    ASSERT_EQ(partition.pieceOfFace.size(), sphere.triangles.size());
    for (uint32_t piece : partition.pieceOfFace) ASSERT_LT(piece, 6u);
    double total = 0.0;
    for (uint32_t p = 0; p < 6; ++p) {
        const ngi::TriangleMesh faces = facesOf(sphere, partition.pieceOfFace, p);
        ASSERT_FALSE(faces.triangles.empty()) << "piece " << p;
        EXPECT_EQ(ngi::findFaceComponents(faces, ngi::buildMeshEdges(faces)).count, 1u) << "piece " << p;
        total += partition.pieceArea[p];
    }
    EXPECT_NEAR(total, area(sphere), 1e-9 * area(sphere));
    // Six relaxed seeds on a sphere: the largest piece at most twice the smallest.
    const auto [smallest, largest] = std::minmax_element(partition.pieceArea.begin(), partition.pieceArea.end());
    EXPECT_LT(*largest / *smallest, 2.0) << *smallest << " .. " << *largest;
}

TEST(ChartSplit, PiecesAreManifoldCopiesThatMakeUpTheSurface)
{
    const ngi::TriangleMesh torus = ngi::makeTorus(48, 16);
    const ngi::ChartPartition partition = ngi::partitionByGeodesicVoronoi(torus, {.pieces = 4});
    const std::vector<ngi::TriangleMesh> pieces = ngi::splitIntoPieces(torus, partition.pieceOfFace);
    ASSERT_GE(pieces.size(), 4u);
    size_t triangles = 0;
    double total = 0.0, previous = 1e300;
    for (const ngi::TriangleMesh& piece : pieces) {
        const ngi::MeshTopology t = ngi::analyzeTopology(piece);
        EXPECT_EQ(t.components, 1u);
        EXPECT_EQ(t.nonManifoldEdges, 0u);
        EXPECT_GE(t.boundaryLoops, 1u) << "a piece of a closed surface is open where it was cut";
        EXPECT_EQ(t.vertices, piece.positions.size()) << "no unreferenced vertex";
        // findBoundaryLoops throws where a vertex has two outgoing boundary edges (a pinch).
        EXPECT_NO_THROW(ngi::findBoundaryLoops(piece, ngi::buildMeshEdges(piece)));
        triangles += piece.triangles.size();
        const double a = area(piece);
        EXPECT_LE(a, previous) << "largest first";
        previous = a;
        total += a;
    }
    EXPECT_EQ(triangles, torus.triangles.size());
    EXPECT_NEAR(total, area(torus), 1e-9 * area(torus));
}

TEST(ChartSplit, APieceThatTouchesItselfAtAVertexGetsOneVertexPerFan)
{
    // A 2 x 2 patch; piece 0 = the lower-left and upper-right cells, which meet at the centre
    // vertex only; piece 1 = the other two cells (also meeting there only).
    const ngi::TriangleMesh patch = ngi::makePlanePatch(2);
    ASSERT_EQ(patch.triangles.size(), 8u);
    std::vector<uint32_t> label(8);
    for (size_t f = 0; f < 8; ++f) {
        const glm::uvec3& t = patch.triangles[f];
        const glm::dvec3 c = (patch.positions[t.x] + patch.positions[t.y] + patch.positions[t.z]) / 3.0;
        label[f] = (c.x < 0.5) == (c.y < 0.5) ? 0u : 1u;
    }
    const std::vector<ngi::TriangleMesh> pieces = ngi::splitIntoPieces(patch, label);
    ASSERT_EQ(pieces.size(), 4u) << "each cell on its own: the pieces meet themselves at a vertex only";
    for (const ngi::TriangleMesh& piece : pieces) {
        EXPECT_EQ(piece.triangles.size(), 2u);
        EXPECT_EQ(piece.positions.size(), 4u);
    }
}

TEST(ChartSplit, EveryPartOfADisconnectedMeshGetsASeed)
{
    ngi::TriangleMesh twoSpheres = ngi::makeSphere(2);
    const ngi::TriangleMesh second = ngi::makeSphere(2);
    const uint32_t base = uint32_t(twoSpheres.positions.size());
    for (const glm::dvec3& p : second.positions) twoSpheres.positions.push_back(p + glm::dvec3(5.0, 0.0, 0.0));
    for (const glm::uvec3& t : second.triangles) twoSpheres.triangles.push_back(t + glm::uvec3(base));
    const ngi::ChartPartition partition = ngi::partitionByGeodesicVoronoi(twoSpheres, {.pieces = 2});
    const size_t half = second.triangles.size();
    const std::set<uint32_t> first(partition.pieceOfFace.begin(), partition.pieceOfFace.begin() + half);
    const std::set<uint32_t> other(partition.pieceOfFace.begin() + half, partition.pieceOfFace.end());
    EXPECT_EQ(first.size(), 1u);
    EXPECT_EQ(other.size(), 1u);
    EXPECT_NE(*first.begin(), *other.begin());
}

TEST(ChartSplit, RefusesNoPiecesAndNoTriangles)
{
    EXPECT_THROW(ngi::partitionByGeodesicVoronoi(ngi::makeSphere(1), {.pieces = 0}), ngi::Error);
    EXPECT_THROW(ngi::partitionByGeodesicVoronoi(ngi::TriangleMesh{}, {.pieces = 2}), ngi::Error);
    EXPECT_THROW(ngi::splitIntoPieces(ngi::makeSphere(1), std::vector<uint32_t>(3, 0)), ngi::Error);
}

TEST(ChartSplit, RefiningThePieceBordersQuadruplesTheSharedEdgesAndKeepsTheSurface)
{
    ngi::TriangleMesh sphere = ngi::makeSphere(3);
    ngi::ChartPartition partition = ngi::partitionByGeodesicVoronoi(sphere, {.pieces = 4});
    auto borderEdges = [](const ngi::TriangleMesh& mesh, const std::vector<uint32_t>& piece) {
        const ngi::MeshEdges edges = ngi::buildMeshEdges(mesh);
        size_t count = 0;
        for (const glm::uvec2& f : edges.faces) count += f.y != ngi::kNoFace && piece[f.x] != piece[f.y];
        return count;
    };
    const size_t before = borderEdges(sphere, partition.pieceOfFace);
    const double areaBefore = area(sphere);
    std::vector<uint32_t> pieces = partition.pieceOfFace;
    ngi::refinePieceBorders(sphere, pieces, 2);
    ASSERT_EQ(pieces.size(), sphere.triangles.size());
    EXPECT_EQ(borderEdges(sphere, pieces), 4 * before);
    EXPECT_NEAR(area(sphere), areaBefore, 1e-12 * areaBefore);
    const ngi::MeshTopology t = ngi::analyzeTopology(sphere);
    EXPECT_EQ(t.nonManifoldEdges, 0u);
    EXPECT_EQ(t.genus, 0);
    EXPECT_EQ(t.boundaryLoops, 0u);
    for (uint32_t p = 0; p < 4; ++p) {
        const ngi::TriangleMesh faces = facesOf(sphere, pieces, p);
        EXPECT_EQ(ngi::findFaceComponents(faces, ngi::buildMeshEdges(faces)).count, 1u) << "piece " << p;
    }
}

}  // namespace
