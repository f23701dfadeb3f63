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

// Multi-source Dijkstra over the dual graph from `sources` (distance 0 each), on top of the
// distances already there (so adding one source updates only the faces nearer to it). Per face
// reached: its distance and firstIndex + the index in `sources` of its nearest source.
void propagate(const DualGraph& graph, std::span<const uint32_t> sources, std::vector<double>& distance,
               std::vector<uint32_t>& nearest, uint32_t firstIndex = 0)
{
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (uint32_t s = 0; s < sources.size(); ++s) {
        distance[sources[s]] = 0.0;
        nearest[sources[s]] = firstIndex + s;
        queue.emplace(0.0, sources[s]);
    }
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
                nearest[g] = nearest[f];
                queue.emplace(e, g);
            }
        }
    }
}

double triangleArea(const TriangleMesh& mesh, const glm::uvec3& t)
{
    return 0.5 *
        glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
}

// The vertex graph (compressed rows): neighbours of v are neighbour[offset[v] .. offset[v+1]),
// with the edge lengths.
struct VertexGraph {
    std::vector<uint32_t> offset, neighbour;
    std::vector<double> length;
};

VertexGraph buildVertexGraph(const TriangleMesh& mesh, const MeshEdges& edges)
{
    VertexGraph graph;
    graph.offset.assign(mesh.positions.size() + 1, 0);
    for (const glm::uvec2& e : edges.vertices) ++graph.offset[e.x + 1], ++graph.offset[e.y + 1];
    std::partial_sum(graph.offset.begin(), graph.offset.end(), graph.offset.begin());
    graph.neighbour.resize(graph.offset.back());
    graph.length.resize(graph.offset.back());
    std::vector<uint32_t> fill(graph.offset.begin(), graph.offset.end() - 1);
    for (const glm::uvec2& e : edges.vertices) {
        const double l = glm::length(mesh.positions[e.x] - mesh.positions[e.y]);
        graph.neighbour[fill[e.x]] = e.y, graph.length[fill[e.x]++] = l;
        graph.neighbour[fill[e.y]] = e.x, graph.length[fill[e.y]++] = l;
    }
    return graph;
}

// Geodesic distance along edges from the nearest of `sources`.
std::vector<double> vertexDistances(const VertexGraph& graph, std::span<const uint32_t> sources)
{
    std::vector<double> distance(graph.offset.size() - 1, kInfinity);
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (uint32_t s : sources) distance[s] = 0.0, queue.emplace(0.0, s);
    while (!queue.empty()) {
        const auto [d, v] = queue.top();
        queue.pop();
        if (d > distance[v]) continue;
        for (uint32_t i = graph.offset[v]; i < graph.offset[v + 1]; ++i) {
            const uint32_t w = graph.neighbour[i];
            const double e = d + graph.length[i];
            if (e < distance[w]) distance[w] = e, queue.emplace(e, w);
        }
    }
    return distance;
}

}  // namespace

ChartPartition partitionByGeodesicVoronoi(const TriangleMesh& mesh, const ChartPartitionOptions& options)
{
    const size_t faces = mesh.triangles.size();
    if (faces == 0) throw Error("chart partition: the mesh has no triangles");
    if (options.pieces == 0) throw Error("chart partition: 0 pieces asked for");
    const uint32_t pieces = uint32_t(std::min<size_t>(options.pieces, faces));
    const MeshEdges edges = buildMeshEdges(mesh);
    const DualGraph graph = buildDualGraph(mesh, edges);

    // Farthest-point seeds: the first is the face farthest from face 0 (an extremity), each
    // next one the face farthest from the seeds so far. A face the front never reaches (a
    // mesh that is not connected) counts as infinitely far, so every part gets a seed.
    std::vector<double> distance(faces, kInfinity);
    std::vector<uint32_t> nearest(faces, 0);
    std::vector<uint32_t> seeds;
    auto farthest = [&] { return uint32_t(std::max_element(distance.begin(), distance.end()) - distance.begin()); };
    {
        const uint32_t start = 0;
        propagate(graph, std::span(&start, 1), distance, nearest);
        seeds.push_back(farthest());
    }
    std::fill(distance.begin(), distance.end(), kInfinity);
    propagate(graph, seeds, distance, nearest);
    while (seeds.size() < pieces) {
        const uint32_t next = farthest();
        seeds.push_back(next);
        // Only faces closer to the new seed change: a front from it alone updates them.
        propagate(graph, std::span(&next, 1), distance, nearest, uint32_t(seeds.size() - 1));
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
        propagate(graph, border, inner, innerNearest);
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
        propagate(graph, seeds, distance, nearest);
    }

    ChartPartition partition;
    partition.pieces = pieces;
    partition.pieceOfFace = std::move(nearest);
    partition.pieceArea.assign(pieces, 0.0);
    for (size_t f = 0; f < faces; ++f)
        partition.pieceArea[partition.pieceOfFace[f]] += triangleArea(mesh, mesh.triangles[f]);
    return partition;
}

uint32_t deepestVertex(const TriangleMesh& mesh)
{
    const MeshEdges edges = buildMeshEdges(mesh);
    std::vector<uint32_t> boundary;
    for (size_t e = 0; e < edges.vertices.size(); ++e)
        if (edges.isBoundary(uint32_t(e)))
            boundary.push_back(edges.vertices[e].x), boundary.push_back(edges.vertices[e].y);
    if (boundary.empty()) return kNoFace;
    const std::vector<double> d = vertexDistances(buildVertexGraph(mesh, edges), boundary);
    uint32_t best = kNoFace;
    for (uint32_t v = 0; v < d.size(); ++v)
        if (d[v] > 0.0 && d[v] != kInfinity && (best == kNoFace || d[v] > d[best])) best = v;
    return best;
}

void refinePieceBorders(TriangleMesh& mesh, std::vector<uint32_t>& pieceOfFace, uint32_t rounds)
{
    if (pieceOfFace.size() != mesh.triangles.size())
        throw Error("chart partition: the piece table does not match the mesh's triangles");
    for (uint32_t round = 0; round < rounds; ++round) {
        const MeshEdges edges = buildMeshEdges(mesh);
        const uint32_t firstMidpoint = uint32_t(mesh.positions.size());
        std::vector<uint32_t> midpoint(edges.vertices.size(), kNoFace);
        for (size_t e = 0; e < edges.vertices.size(); ++e) {
            const glm::uvec2 f = edges.faces[e];
            if (f.y == kNoFace || pieceOfFace[f.x] == pieceOfFace[f.y]) continue;
            midpoint[e] = uint32_t(mesh.positions.size());
            mesh.positions.push_back(0.5 * (mesh.positions[edges.vertices[e].x] + mesh.positions[edges.vertices[e].y]));
        }
        // A triangle with split edges is fanned from a midpoint into two, three or four.
        std::vector<glm::uvec3> triangles;
        std::vector<uint32_t> pieces;
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const glm::uvec3 v = mesh.triangles[t];
            // The polygon of the triangle with its midpoints, counter-clockwise.
            std::vector<uint32_t> polygon;
            for (int k = 0; k < 3; ++k) {
                polygon.push_back(v[k]);
                const uint32_t m = midpoint[edges.faceEdges[t][k]];
                if (m != kNoFace) polygon.push_back(m);
            }
            if (polygon.size() == 3) {
                triangles.push_back(v);
                pieces.push_back(pieceOfFace[t]);
                continue;
            }
            // Fan from a midpoint (never collinear with two fan neighbours): rotate so the
            // polygon starts at one, then fan.
            size_t start = 0;
            while (polygon[start] < firstMidpoint) ++start;
            std::rotate(polygon.begin(), polygon.begin() + long(start), polygon.end());
            for (size_t k = 1; k + 1 < polygon.size(); ++k) {
                triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
                pieces.push_back(pieceOfFace[t]);
            }
        }
        mesh.triangles = std::move(triangles);
        pieceOfFace = std::move(pieces);
    }
}

std::vector<TriangleMesh> splitIntoPieces(const TriangleMesh& mesh, std::span<const uint32_t> pieceOfFace,
                                          std::vector<std::vector<uint32_t>>* sourceVertex)
{
    const size_t faces = mesh.triangles.size();
    if (pieceOfFace.size() != faces)
        throw Error("chart partition: the piece table does not match the mesh's triangles");
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
    std::vector<std::vector<uint32_t>> source;
    for (uint32_t f = 0; f < faces; ++f) {
        uint32_t& m = meshOfSet[faceSets.find(f)];
        if (m == kNoFace) {
            m = uint32_t(result.size());
            result.emplace_back();
            source.emplace_back();
        }
        TriangleMesh& piece = result[m];
        glm::uvec3 t;
        for (int k = 0; k < 3; ++k) {
            uint32_t& v = vertexOfCorner[corners.find(3 * f + k)];
            if (v == kNoFace) {
                v = uint32_t(piece.positions.size());
                piece.positions.push_back(mesh.positions[mesh.triangles[f][k]]);
                source[m].push_back(mesh.triangles[f][k]);
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
    if (sourceVertex) sourceVertex->clear();
    for (size_t m : order) {
        sorted.push_back(std::move(result[m]));
        if (sourceVertex) sourceVertex->push_back(std::move(source[m]));
    }
    return sorted;
}

}  // namespace ngi
