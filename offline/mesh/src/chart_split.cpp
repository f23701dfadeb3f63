// Geodesic Voronoi partition of a surface into charts: Peyré and Cohen 2006, "Geodesic
// remeshing using front propagation" (farthest-point seeding), with Lloyd-style relaxation
// (Lloyd 1982) of the seeds; see ngi/mesh/chart_split.h.
#include "ngi/mesh/chart_split.h"

#include "ngi/error.h"
#include "ngi/mesh/mesh_topology.h"
#include "union_find.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <queue>

namespace ngi {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The dual graph: per face its up to three neighbours across shared edges, with the
// distance between the two face centroids.
struct DualGraph {
    std::vector<std::array<uint32_t, 3>> neighbour;
    std::vector<std::array<double, 3>> length;
};

DualGraph buildDualGraph(const TriangleMesh& mesh, const MeshEdges& edges)
{
    const size_t faces = mesh.triangles.size();
    std::vector<glm::dvec3> centroid(faces);
    for (size_t f = 0; f < faces; ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        centroid[f] = (mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) / 3.0;
    }
    DualGraph graph;
    graph.neighbour.assign(faces, {kNoFace, kNoFace, kNoFace});
    graph.length.assign(faces, {0.0, 0.0, 0.0});
    for (size_t f = 0; f < faces; ++f)
        for (int k = 0; k < 3; ++k) {
            const glm::uvec2 pair = edges.faces[edges.faceEdges[f][k]];
            const uint32_t g = pair.x == f ? pair.y : pair.x;
            if (g == kNoFace || g == f) continue;
            graph.neighbour[f][k] = g;
            graph.length[f][k] = glm::length(centroid[g] - centroid[f]);
        }
    return graph;
}

// Multi-source Dijkstra over the dual graph from `sources` (distance 0 each), restricted to
// the faces where `allowed` is empty or allowed(face) is true. Fills distance and, per face,
// the index in `sources` of the source it is nearest to (ties: the first reached).
template <class Allowed>
void propagate(const DualGraph& graph, std::span<const uint32_t> sources, Allowed allowed, std::vector<double>& distance,
               std::vector<uint32_t>& nearest)
{
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (uint32_t s = 0; s < sources.size(); ++s) {
        distance[sources[s]] = 0.0;
        nearest[sources[s]] = s;
        queue.emplace(0.0, sources[s]);
    }
    while (!queue.empty()) {
        const auto [d, f] = queue.top();
        queue.pop();
        if (d > distance[f]) continue;
        for (int k = 0; k < 3; ++k) {
            const uint32_t g = graph.neighbour[f][k];
            if (g == kNoFace || !allowed(g)) continue;
            const double e = d + graph.length[f][k];
            if (e < distance[g]) {
                distance[g] = e;
                nearest[g] = nearest[f];
                queue.emplace(e, g);
            }
        }
    }
}

double triangleArea(const TriangleMesh& mesh, const glm::uvec3& t)
{
    return 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
}

} // namespace

ChartPartition partitionByGeodesicVoronoi(const TriangleMesh& mesh, const ChartPartitionOptions& options)
{
    const size_t faces = mesh.triangles.size();
    if (faces == 0) throw Error("chart partition: the mesh has no triangles");
    if (options.pieces == 0) throw Error("chart partition: 0 pieces asked for");
    const uint32_t pieces = uint32_t(std::min<size_t>(options.pieces, faces));
    const MeshEdges edges = buildMeshEdges(mesh);
    const DualGraph graph = buildDualGraph(mesh, edges);
    auto everywhere = [](uint32_t) { return true; };

    // Farthest-point seeds: the first is the face farthest from face 0 (an extremity), each
    // next one the face farthest from the seeds so far. A face the front never reaches (a
    // mesh that is not connected) counts as infinitely far, so every part gets a seed.
    std::vector<double> distance(faces, kInfinity);
    std::vector<uint32_t> nearest(faces, 0);
    std::vector<uint32_t> seeds;
    auto farthest = [&] {
        return uint32_t(std::max_element(distance.begin(), distance.end()) - distance.begin());
    };
    {
        const uint32_t start = 0;
        propagate(graph, std::span(&start, 1), everywhere, distance, nearest);
        seeds.push_back(farthest());
    }
    std::fill(distance.begin(), distance.end(), kInfinity);
    propagate(graph, seeds, everywhere, distance, nearest);
    while (seeds.size() < pieces) {
        const uint32_t next = farthest();
        seeds.push_back(next);
        // Only faces closer to the new seed change: a front from it alone updates them.
        const uint32_t index = uint32_t(seeds.size() - 1);
        distance[next] = 0.0;
        nearest[next] = index;
        using Item = std::pair<double, uint32_t>;
        std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
        queue.emplace(0.0, next);
        while (!queue.empty()) {
            const auto [d, f] = queue.top();
            queue.pop();
            if (d > distance[f]) continue;
            for (int k = 0; k < 3; ++k) {
                const uint32_t g = graph.neighbour[f][k];
                if (g == kNoFace) continue;
                const double e = d + graph.length[f][k];
                if (e < distance[g]) {
                    distance[g] = e;
                    nearest[g] = index;
                    queue.emplace(e, g);
                }
            }
        }
    }

    // Relaxation: each seed moves to the face of its region farthest from the region's border
    // (the centre of its largest inscribed geodesic disk), then the regions are recomputed.
    std::vector<double> inner(faces);
    std::vector<uint32_t> innerNearest(faces);
    for (uint32_t iteration = 0; iteration < options.relaxIterations; ++iteration) {
        std::vector<uint32_t> border;
        for (uint32_t f = 0; f < faces; ++f)
            for (int k = 0; k < 3; ++k) {
                const uint32_t g = graph.neighbour[f][k];
                if (g == kNoFace || nearest[g] != nearest[f]) {
                    border.push_back(f);
                    break;
                }
            }
        std::fill(inner.begin(), inner.end(), kInfinity);
        propagate(graph, border, everywhere, inner, innerNearest);
        // The front from the borders runs across regions too; keep per region its own maximum.
        std::vector<double> best(seeds.size(), -1.0);
        std::vector<uint32_t> moved = seeds;
        for (uint32_t f = 0; f < faces; ++f) {
            const uint32_t r = nearest[f];
            if (inner[f] != kInfinity && inner[f] > best[r]) best[r] = inner[f], moved[r] = f;
        }
        if (moved == seeds) break;
        seeds = moved;
        std::fill(distance.begin(), distance.end(), kInfinity);
        propagate(graph, seeds, everywhere, distance, nearest);
    }

    ChartPartition partition;
    partition.pieces = pieces;
    partition.pieceOfFace = std::move(nearest);
    partition.pieceArea.assign(pieces, 0.0);
    for (size_t f = 0; f < faces; ++f) partition.pieceArea[partition.pieceOfFace[f]] += triangleArea(mesh, mesh.triangles[f]);
    return partition;
}

std::vector<TriangleMesh> splitIntoPieces(const TriangleMesh& mesh, std::span<const uint32_t> pieceOfFace)
{
    const size_t faces = mesh.triangles.size();
    if (pieceOfFace.size() != faces) throw Error("chart partition: the piece table does not match the mesh's triangles");
    const MeshEdges edges = buildMeshEdges(mesh);

    // Corners (3 per face) glued across every edge whose two faces lie in one piece; each
    // class of glued corners becomes one vertex. So a vertex shared by two pieces, or by two
    // fans of one piece, becomes one vertex per fan, and pieces are cut apart at their borders.
    detail::UnionFind corners(3 * faces);
    for (size_t e = 0; e < edges.vertices.size(); ++e) {
        const glm::uvec2 pair = edges.faces[e];
        if (pair.y == kNoFace || pieceOfFace[pair.x] != pieceOfFace[pair.y]) continue;
        const glm::uvec2 v = edges.vertices[e];
        for (uint32_t end : {v.x, v.y}) {
            uint32_t a = kNoFace, b = kNoFace;
            for (int k = 0; k < 3; ++k) {
                if (mesh.triangles[pair.x][k] == end) a = 3 * pair.x + k;
                if (mesh.triangles[pair.y][k] == end) b = 3 * pair.y + k;
            }
            corners.unite(a, b);
        }
    }

    // Pieces that fall apart (through edges) become separate meshes: faces glued across
    // in-piece edges.
    detail::UnionFind faceSets(faces);
    for (size_t e = 0; e < edges.vertices.size(); ++e) {
        const glm::uvec2 pair = edges.faces[e];
        if (pair.y != kNoFace && pieceOfFace[pair.x] == pieceOfFace[pair.y]) faceSets.unite(pair.x, pair.y);
    }
    std::vector<uint32_t> meshOfSet(faces, kNoFace);
    std::vector<uint32_t> vertexOfCorner(3 * faces, kNoFace);
    std::vector<TriangleMesh> result;
    for (uint32_t f = 0; f < faces; ++f) {
        uint32_t& m = meshOfSet[faceSets.find(f)];
        if (m == kNoFace) {
            m = uint32_t(result.size());
            result.emplace_back();
        }
        TriangleMesh& piece = result[m];
        glm::uvec3 t;
        for (int k = 0; k < 3; ++k) {
            uint32_t& v = vertexOfCorner[corners.find(3 * f + k)];
            if (v == kNoFace) {
                v = uint32_t(piece.positions.size());
                piece.positions.push_back(mesh.positions[mesh.triangles[f][k]]);
            }
            t[k] = v;
        }
        piece.triangles.push_back(t);
    }
    std::vector<double> area(result.size(), 0.0);
    for (size_t m = 0; m < result.size(); ++m)
        for (const glm::uvec3& t : result[m].triangles) area[m] += triangleArea(result[m], t);
    std::vector<size_t> order(result.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return area[a] > area[b]; });
    std::vector<TriangleMesh> sorted;
    sorted.reserve(result.size());
    for (size_t m : order) sorted.push_back(std::move(result[m]));
    return sorted;
}

} // namespace ngi
