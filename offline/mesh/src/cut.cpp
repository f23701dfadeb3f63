// ngi offline: cutting a surface into a disk (see cut.h).
//
// Cut graph by tree-cotree (Eppstein, "Dynamic generators of topologically embedded graphs",
// SODA 2003) with the greedy shortest-loop choice of Erickson & Whittlesey ("Greedy optimal
// homotopy and homology generators", SODA 2005):
//   1. T: shortest-path tree from a root in which every boundary loop is contracted to one
//      node, so each loop enters T as one path (the loop minus one edge) and loops are
//      joined to the root by shortest paths;
//   2. C: maximum spanning tree of the dual graph over the interior edges not in T, weighted
//      by the length of the loop an edge closes with T (dist(u) + dist(v) + |uv|);
//   3. the 2g edges in neither T nor C close the g handles' shortest loops; the cut graph is
//      T + those edges + all boundary edges, pruned of dangling branches (repeatedly removing
//      edges at degree-1 vertices). Cutting along it leaves one disk.
// Then each requested extremity is joined to the graph by a shortest path (Gu, Gortler,
// Hoppe 2002, section 3.2: cut augmentation through the points of worst stretch).
// Before cutting, uncut edges whose endpoints both lie on the cut graph are split at their
// midpoints, so that no disk triangle can be squashed flat onto one side of the square.
// Genus 0 without boundary prunes to nothing: the cut is then the shortest path between two
// far vertices (a double sweep of Dijkstra; cf. Gu, Gortler, Hoppe, "Geometry Images" 2002,
// whose initial cut of a sphere is also a path).
#include "ngi/mesh/cut.h"

#include "ngi/error.h"
#include "ngi/mesh/mesh_topology.h"
#include "union_find.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <queue>

namespace ngi {
namespace {

using detail::UnionFind;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Vertex -> incident edges, compressed rows.
struct VertexEdges {
    std::vector<uint32_t> start, edge;
    VertexEdges(size_t vertexCount, const MeshEdges& edges) : start(vertexCount + 1, 0)
    {
        for (const glm::uvec2& e : edges.vertices) ++start[e.x + 1], ++start[e.y + 1];
        std::partial_sum(start.begin(), start.end(), start.begin());
        edge.resize(start.back());
        std::vector<uint32_t> fill(start.begin(), start.end() - 1);
        for (uint32_t e = 0; e < edges.vertices.size(); ++e)
            edge[fill[edges.vertices[e].x]++] = e, edge[fill[edges.vertices[e].y]++] = e;
    }
};

uint32_t edgeBetween(const VertexEdges& adjacency, const MeshEdges& edges, uint32_t a, uint32_t b)
{
    for (uint32_t i = adjacency.start[a]; i < adjacency.start[a + 1]; ++i) {
        const glm::uvec2& e = edges.vertices[adjacency.edge[i]];
        if ((e.x == a && e.y == b) || (e.x == b && e.y == a)) return adjacency.edge[i];
    }
    return kNoFace;
}

// Dijkstra from `sources` (distance 0); returns distances and, per vertex, the tree edge to its
// parent (kNoFace for sources and unreached vertices). Each loop in `contracted` acts as one
// node: when its first vertex is settled, the whole loop is settled at the same distance
// with the loop's own edges as tree edges (so the tree holds the loop minus one edge).
void shortestPaths(const VertexEdges& adjacency, const MeshEdges& edges, const std::vector<double>& length,
                   const std::vector<uint32_t>& sources, std::vector<double>& distance,
                   std::vector<uint32_t>& parentEdge, const std::vector<std::vector<uint32_t>>& contracted = {})
{
    const size_t n = adjacency.start.size() - 1;
    distance.assign(n, kInfinity);
    parentEdge.assign(n, kNoFace);
    std::vector<uint32_t> loopOf(n, kNoFace), positionInLoop(n, 0);
    for (uint32_t l = 0; l < contracted.size(); ++l)
        for (uint32_t i = 0; i < contracted[l].size(); ++i)
            loopOf[contracted[l][i]] = l, positionInLoop[contracted[l][i]] = i;
    std::vector<uint8_t> loopSettled(contracted.size(), 0);
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (uint32_t s : sources) distance[s] = 0.0, queue.push({0.0, s});
    while (!queue.empty()) {
        auto [d, v] = queue.top();
        queue.pop();
        if (d > distance[v]) continue;
        if (loopOf[v] != kNoFace && !loopSettled[loopOf[v]]) {
            const std::vector<uint32_t>& loop = contracted[loopOf[v]];
            loopSettled[loopOf[v]] = 1;
            for (size_t i = 1; i < loop.size(); ++i) {
                const uint32_t previous = loop[(positionInLoop[v] + i - 1) % loop.size()];
                const uint32_t w = loop[(positionInLoop[v] + i) % loop.size()];
                distance[w] = d;
                parentEdge[w] = edgeBetween(adjacency, edges, previous, w);
                queue.push({d, w});
            }
        }
        for (uint32_t i = adjacency.start[v]; i < adjacency.start[v + 1]; ++i) {
            const uint32_t e = adjacency.edge[i];
            const uint32_t w = edges.vertices[e].x == v ? edges.vertices[e].y : edges.vertices[e].x;
            const double nd = d + length[e];
            if (nd < distance[w]) distance[w] = nd, parentEdge[w] = e, queue.push({nd, w});
        }
    }
}

uint32_t farthest(const std::vector<double>& distance)
{
    uint32_t best = 0;
    for (uint32_t v = 0; v < distance.size(); ++v)
        if (distance[v] != kInfinity && distance[v] > distance[best]) best = v;
    return best;
}

// Splits the interior edge a-b of faces f and g at its midpoint m (appended): each face
// becomes two, in the same orientation. Returns m.
uint32_t splitEdgeAtMidpoint(TriangleMesh& mesh, uint32_t a, uint32_t b, uint32_t f, uint32_t g)
{
    const uint32_t m = uint32_t(mesh.positions.size());
    mesh.positions.push_back((mesh.positions[a] + mesh.positions[b]) * 0.5);
    for (uint32_t face : {f, g}) {
        glm::uvec3 t = mesh.triangles[face];
        int k = 0;  // corner where the edge starts: t[k] -> t[k+1] is a-b in some order
        while (!((t[k] == a || t[k] == b) && (t[(k + 1) % 3] == a || t[(k + 1) % 3] == b))) ++k;
        const uint32_t from = t[k], to = t[(k + 1) % 3], opposite = t[(k + 2) % 3];
        mesh.triangles[face] = {from, m, opposite};
        mesh.triangles.push_back({m, to, opposite});
    }
    return m;
}

// Splits, repeatedly, every edge not in the cut whose endpoints are both on the cut. Cut edges
// are given by key (min << 32 | max); they are never split, so the keys stay valid.
size_t splitBridges(TriangleMesh& mesh, std::vector<uint64_t>& cutKeys)
{
    std::sort(cutKeys.begin(), cutKeys.end());
    size_t splits = 0;
    for (int pass = 0; pass < 8; ++pass) {
        const MeshEdges edges = buildMeshEdges(mesh);
        std::vector<uint8_t> onCut(mesh.positions.size(), 0);
        for (uint64_t key : cutKeys) onCut[key >> 32] = onCut[key & 0xffffffffu] = 1;
        std::vector<uint8_t> touched(mesh.triangles.size(), 0);
        size_t before = splits;
        for (uint32_t e = 0; e < edges.vertices.size(); ++e) {
            const uint32_t a = edges.vertices[e].x, b = edges.vertices[e].y;
            if (!onCut[a] || !onCut[b] || edges.isBoundary(e)) continue;
            if (std::binary_search(cutKeys.begin(), cutKeys.end(), (uint64_t(a) << 32) | b)) continue;
            const uint32_t f = edges.faces[e].x, g = edges.faces[e].y;
            if (touched[f] || touched[g]) continue;  // next pass
            touched[f] = touched[g] = 1;
            splitEdgeAtMidpoint(mesh, a, b, f, g);
            touched.resize(mesh.triangles.size(), 1);
            ++splits;
        }
        if (splits == before) break;
    }
    return splits;
}

// Joins each extremity to the cut graph `inCut` by the shortest path from it to any vertex
// on the graph (multi-source Dijkstra from the graph's vertices); the path's interior
// avoids the graph, so it adds a slit and the cut still yields a disk.
void joinExtremities(const VertexEdges& adjacency, const MeshEdges& edges, const std::vector<double>& length,
                     const std::vector<uint32_t>& extremities, std::vector<uint8_t>& inCut, CutReport& report)
{
    const size_t vertexCount = adjacency.start.size() - 1;
    for (uint32_t tip : extremities) {
        if (tip >= vertexCount) throw Error("cut: extremity vertex " + std::to_string(tip) + " is not a mesh vertex");
        std::vector<uint8_t> onCut(vertexCount, 0);
        for (uint32_t e = 0; e < inCut.size(); ++e)
            if (inCut[e]) onCut[edges.vertices[e].x] = onCut[edges.vertices[e].y] = 1;
        if (onCut[tip]) continue;
        std::vector<uint32_t> sources;
        for (uint32_t v = 0; v < vertexCount; ++v)
            if (onCut[v]) sources.push_back(v);
        if (sources.empty()) continue;
        std::vector<double> distance;
        std::vector<uint32_t> parent;
        shortestPaths(adjacency, edges, length, sources, distance, parent);
        if (distance[tip] == kInfinity) continue;
        for (uint32_t v = tip; parent[v] != kNoFace;) {
            const uint32_t e = parent[v];
            inCut[e] = 1;
            report.extremityLength += length[e];
            v = edges.vertices[e].x == v ? edges.vertices[e].y : edges.vertices[e].x;
        }
        ++report.extremityPaths;
    }
}

// Removes, repeatedly, cut edges at vertices of cut degree 1 (re-gluing dangling branches).
void pruneDanglingEdges(const VertexEdges& adjacency, const MeshEdges& edges, std::vector<uint8_t>& inCut)
{
    const size_t vertexCount = adjacency.start.size() - 1;
    std::vector<uint32_t> degree(vertexCount, 0);
    for (uint32_t e = 0; e < inCut.size(); ++e)
        if (inCut[e]) ++degree[edges.vertices[e].x], ++degree[edges.vertices[e].y];
    std::vector<uint32_t> stack;
    for (uint32_t v = 0; v < vertexCount; ++v)
        if (degree[v] == 1) stack.push_back(v);
    while (!stack.empty()) {
        const uint32_t v = stack.back();
        stack.pop_back();
        if (degree[v] != 1) continue;
        for (uint32_t i = adjacency.start[v]; i < adjacency.start[v + 1]; ++i) {
            const uint32_t e = adjacency.edge[i];
            if (!inCut[e]) continue;
            inCut[e] = 0;
            const uint32_t w = edges.vertices[e].x == v ? edges.vertices[e].y : edges.vertices[e].x;
            --degree[v];
            if (--degree[w] == 1) stack.push_back(w);
            break;
        }
    }
}

// Face peeling (Gu, Gortler, Hoppe 2002, section 3.1), see findCutGraph: the edges a
// Dijkstra growth of faces from a seed (over face centroids, across interior edges) never
// crosses; not yet pruned.
std::vector<uint8_t> facePeelingCut(const TriangleMesh& mesh, const MeshEdges& edges, bool hasBoundary)
{
    const size_t edgeCount = edges.vertices.size();
    const size_t faceCount = mesh.triangles.size();
    std::vector<glm::dvec3> centroid(faceCount);
    for (size_t f = 0; f < faceCount; ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        centroid[f] = (mesh.positions[t.x] + mesh.positions[t.y] + mesh.positions[t.z]) / 3.0;
    }
    uint32_t seed = 0;
    if (hasBoundary)
        for (uint32_t e = 0; e < edgeCount; ++e)
            if (edges.isBoundary(e)) {
                seed = edges.faces[e].x;
                break;
            }
    std::vector<double> faceDistance(faceCount, kInfinity);
    std::vector<uint8_t> crossed(edgeCount, 0);
    std::vector<uint32_t> parentEdge(faceCount, kNoFace);
    using Item = std::pair<double, uint32_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    faceDistance[seed] = 0.0;
    queue.push({0.0, seed});
    std::vector<uint8_t> settled(faceCount, 0);
    while (!queue.empty()) {
        const auto [d, f] = queue.top();
        queue.pop();
        if (settled[f]) continue;
        settled[f] = 1;
        if (parentEdge[f] != kNoFace) crossed[parentEdge[f]] = 1;
        for (int k = 0; k < 3; ++k) {
            const uint32_t e = edges.faceEdges[f][k];
            if (edges.isBoundary(e)) continue;
            const uint32_t g = edges.faces[e].x == f ? edges.faces[e].y : edges.faces[e].x;
            if (settled[g]) continue;
            const double nd = d + glm::distance(centroid[f], centroid[g]);
            if (nd < faceDistance[g]) faceDistance[g] = nd, parentEdge[g] = e, queue.push({nd, g});
        }
    }
    std::vector<uint8_t> inCut(edgeCount);
    for (uint32_t e = 0; e < edgeCount; ++e) inCut[e] = !crossed[e];
    return inCut;
}

// The cut graph of a connected manifold mesh (see the file comment) as a per-edge flag;
// sets report.method.
std::vector<uint8_t> findCutGraph(const TriangleMesh& mesh, const MeshEdges& edges,
                                  const std::vector<std::vector<uint32_t>>& loops, const MeshTopology& topology,
                                  CutGraph graph, const std::vector<uint32_t>& extremities, CutReport& report)
{
    const size_t vertexCount = mesh.positions.size(), edgeCount = edges.vertices.size();

    std::vector<double> length(edgeCount);
    for (uint32_t e = 0; e < edgeCount; ++e)
        length[e] = glm::distance(mesh.positions[edges.vertices[e].x], mesh.positions[edges.vertices[e].y]);
    const VertexEdges adjacency(vertexCount, edges);

    std::vector<uint8_t> inCut(edgeCount, 0);
    for (uint32_t e = 0; e < edgeCount; ++e) inCut[e] = edges.isBoundary(e);

    if (topology.genus == 0 && loops.size() == 1) {
        report.method = "already a disk";
    } else if (topology.genus == 0 && loops.empty()) {
        report.method = "shortest path between far vertices";
        std::vector<double> distance;
        std::vector<uint32_t> parent;
        shortestPaths(adjacency, edges, length, {0}, distance, parent);
        const uint32_t p = farthest(distance);
        shortestPaths(adjacency, edges, length, {p}, distance, parent);
        for (uint32_t v = farthest(distance); parent[v] != kNoFace;) {
            const uint32_t e = parent[v];
            inCut[e] = 1;
            v = edges.vertices[e].x == v ? edges.vertices[e].y : edges.vertices[e].x;
        }
    } else if (graph == CutGraph::TreeCotree) {
        report.method = "tree-cotree";
        // 1. T: boundary loops contracted; root on the first loop, else at vertex 0.
        std::vector<double> distance;
        std::vector<uint32_t> parent;
        shortestPaths(adjacency, edges, length, {loops.empty() ? 0u : loops[0][0]}, distance, parent, loops);
        std::vector<uint8_t> inTree(edgeCount, 0);
        for (uint32_t v = 0; v < vertexCount; ++v)
            if (parent[v] != kNoFace) inTree[parent[v]] = 1;
        // 2. C: maximum spanning dual tree over interior non-tree edges.
        std::vector<uint32_t> candidates;
        for (uint32_t e = 0; e < edgeCount; ++e)
            if (!inTree[e] && !edges.isBoundary(e)) candidates.push_back(e);
        auto loopLength = [&](uint32_t e) {
            return distance[edges.vertices[e].x] + distance[edges.vertices[e].y] + length[e];
        };
        std::sort(candidates.begin(), candidates.end(),
                  [&](uint32_t a, uint32_t b) { return loopLength(a) > loopLength(b); });
        UnionFind faces(mesh.triangles.size());
        std::vector<uint32_t> leftover;
        for (uint32_t e : candidates)
            if (!faces.unite(edges.faces[e].x, edges.faces[e].y)) leftover.push_back(e);
        if (leftover.size() != size_t(2 * topology.genus))
            throw Error("cut: tree-cotree left " + std::to_string(leftover.size()) + " edges for genus " +
                        std::to_string(topology.genus) + " (expected " + std::to_string(2 * topology.genus) + ")");
        // 3. Cut graph = T + leftover + boundary, pruned.
        for (uint32_t e = 0; e < edgeCount; ++e)
            if (inTree[e]) inCut[e] = 1;
        for (uint32_t e : leftover) inCut[e] = 1;
        pruneDanglingEdges(adjacency, edges, inCut);
    } else {
        report.method = "face peeling";
        // Grow a disk of faces from a seed in order of distance; the edges the growth never
        // crosses are the cut graph, pruned of dangling branches. The cut runs where growth
        // fronts collide, so two cut branches never run side by side enclosing a thin channel
        // of the disk, as the two halves of a tree-cotree loop (shortest paths from one root to
        // the loop edge's ends) do; the conformal start shrinks such a dead-end channel of
        // length L and width w by e^(-pi L / w).
        inCut = facePeelingCut(mesh, edges, !loops.empty());
        pruneDanglingEdges(adjacency, edges, inCut);
    }
    joinExtremities(adjacency, edges, length, extremities, inCut, report);
    return inCut;
}

}  // namespace

CutResult cutToDisk(const TriangleMesh& input, const CutOptions& options)
{
    CutResult result;
    CutReport& report = result.report;
    std::vector<uint64_t> cutKeys;       // cut edges as (min << 32 | max), valid before and after splitting
    std::vector<uint8_t> inputBoundary;  // per input vertex, with CutOptions::cornersAtBoundaryTurns
    {
        const MeshEdges edges = buildMeshEdges(input);
        if (options.cornersAtBoundaryTurns) {
            inputBoundary.assign(input.positions.size(), 0);
            for (uint32_t e = 0; e < edges.vertices.size(); ++e)
                if (edges.isBoundary(e)) inputBoundary[edges.vertices[e].x] = inputBoundary[edges.vertices[e].y] = 1;
        }
        if (edges.nonManifoldEdges > 0) throw Error("cut: the mesh has non-manifold edges (clean it first)");
        const std::vector<std::vector<uint32_t>> loops = findBoundaryLoops(input, edges);
        const MeshTopology topology = analyzeTopology(input);
        if (topology.components != 1)
            throw Error("cut: the mesh has " + std::to_string(topology.components) + " components (expected 1)");
        report.genus = topology.genus;
        report.boundaryLoops = loops.size();
        const std::vector<uint8_t> inCut =
            findCutGraph(input, edges, loops, topology, options.graph, options.extremities, report);
        for (uint32_t e = 0; e < edges.vertices.size(); ++e)
            if (inCut[e]) cutKeys.push_back((uint64_t(edges.vertices[e].x) << 32) | edges.vertices[e].y);
    }
    result.uncut = input;
    // A closed surface cut along one edge is not opened: both ends of the slit stay one vertex
    // each, so no corner is separated. Its midpoint becomes the slit's inner vertex instead.
    if (report.boundaryLoops == 0 && cutKeys.size() == 1) {
        const uint32_t a = uint32_t(cutKeys[0] >> 32), b = uint32_t(cutKeys[0] & 0xffffffffu);
        const MeshEdges edges = buildMeshEdges(result.uncut);
        for (uint32_t e = 0; e < edges.vertices.size(); ++e)
            if (edges.vertices[e].x == a && edges.vertices[e].y == b && !edges.isBoundary(e)) {
                const uint32_t m = splitEdgeAtMidpoint(result.uncut, a, b, edges.faces[e].x, edges.faces[e].y);
                cutKeys = {(uint64_t(std::min(a, m)) << 32) | std::max(a, m),
                           (uint64_t(std::min(b, m)) << 32) | std::max(b, m)};
                break;
            }
    }
    if (options.splitBoundaryBridges) report.splitBridgeEdges = splitBridges(result.uncut, cutKeys);
    std::sort(cutKeys.begin(), cutKeys.end());

    const TriangleMesh& mesh = result.uncut;
    const MeshEdges edges = buildMeshEdges(mesh);
    const MeshTopology topology = analyzeTopology(mesh);
    const size_t edgeCount = edges.vertices.size();
    std::vector<uint8_t> inCut(edgeCount, 0);
    for (uint32_t e = 0; e < edgeCount; ++e) {
        inCut[e] = std::binary_search(cutKeys.begin(), cutKeys.end(),
                                      (uint64_t(edges.vertices[e].x) << 32) | edges.vertices[e].y);
        if (inCut[e] && !edges.isBoundary(e))
            ++report.cutEdges,
                report.cutLength +=
                glm::distance(mesh.positions[edges.vertices[e].x], mesh.positions[edges.vertices[e].y]);
    }
    const size_t loopCount = report.boundaryLoops;

    // Cut: corners of a vertex stay one vertex when joined across an uncut interior edge.
    UnionFind corners(mesh.triangles.size() * 3);
    auto corner = [&](uint32_t f, uint32_t v) {
        const glm::uvec3& t = mesh.triangles[f];
        return f * 3 + (t.x == v ? 0u : t.y == v ? 1u : 2u);
    };
    for (uint32_t e = 0; e < edgeCount; ++e) {
        if (inCut[e]) continue;
        for (uint32_t v : {edges.vertices[e].x, edges.vertices[e].y})
            corners.unite(corner(edges.faces[e].x, v), corner(edges.faces[e].y, v));
    }
    DiskMesh& disk = result.disk;
    std::vector<uint32_t> newVertexOfRoot(mesh.triangles.size() * 3, kNoFace);
    disk.mesh.triangles.resize(mesh.triangles.size());
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
        for (uint32_t k = 0; k < 3; ++k) {
            const uint32_t root = corners.find(f * 3 + k);
            if (newVertexOfRoot[root] == kNoFace) {
                newVertexOfRoot[root] = uint32_t(disk.mesh.positions.size());
                disk.mesh.positions.push_back(mesh.positions[mesh.triangles[f][k]]);
                disk.originalVertex.push_back(mesh.triangles[f][k]);
            }
            disk.mesh.triangles[f][k] = newVertexOfRoot[root];
        }
    report.seamVertices = disk.mesh.positions.size() - topology.vertices;

    const MeshTopology diskTopology = analyzeTopology(disk.mesh);
    const MeshEdges diskEdges = buildMeshEdges(disk.mesh);
    std::vector<std::vector<uint32_t>> diskLoops = findBoundaryLoops(disk.mesh, diskEdges);
    if (diskTopology.eulerCharacteristic != 1 || diskLoops.size() != 1 || diskTopology.components != 1)
        throw Error("cut: the cut mesh is not a disk (Euler characteristic " +
                    std::to_string(diskTopology.eulerCharacteristic) + ", " + std::to_string(diskLoops.size()) +
                    " boundary loops, " + std::to_string(diskTopology.components) + " components; genus " +
                    std::to_string(topology.genus) + ", " + std::to_string(loopCount) +
                    " boundary loops before the cut)");
    disk.boundaryLoop = std::move(diskLoops[0]);
    report.diskBoundaryVertices = disk.boundaryLoop.size();

    // Corner hints: the copies of the cut graph's junctions (original vertices cut into 3 or
    // more copies, where the handle loops meet) are the corners of the polygon schema; the four
    // with the smallest angle sums make the square's corners.
    if (report.method == "tree-cotree" || report.method == "face peeling") {
        std::map<uint32_t, uint32_t> copyCount;
        for (uint32_t v : disk.boundaryLoop) ++copyCount[disk.originalVertex[v]];
        const std::vector<double> angleSum = vertexAngleSums(disk.mesh);
        std::vector<std::pair<double, uint32_t>> candidates;  // (angle sum, loop position)
        for (uint32_t i = 0; i < disk.boundaryLoop.size(); ++i)
            if (copyCount[disk.originalVertex[disk.boundaryLoop[i]]] >= 3)
                candidates.push_back({angleSum[disk.boundaryLoop[i]], i});
        if (candidates.size() >= 4) {
            std::partial_sort(candidates.begin(), candidates.begin() + 4, candidates.end());
            std::vector<uint32_t> positions;
            for (int c = 0; c < 4; ++c) positions.push_back(candidates[c].second);
            std::sort(positions.begin(), positions.end());
            for (uint32_t i : positions) disk.cornerHints.push_back(disk.boundaryLoop[i]);
        }
    }
    // The input's own boundary (edge midpoints split off bridges have indices past the input's
    // vertices and lie inside the surface).
    if (options.cornersAtBoundaryTurns) {
        disk.surfaceBoundary.assign(disk.mesh.positions.size(), 0);
        for (size_t v = 0; v < disk.mesh.positions.size(); ++v) {
            const uint32_t o = disk.originalVertex[v];
            disk.surfaceBoundary[v] = o < inputBoundary.size() ? inputBoundary[o] : 0;
        }
    }
    return result;
}

SeamEdges findSeamEdges(const DiskMesh& disk)
{
    SeamEdges seam;
    const size_t n = disk.boundaryLoop.size();
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> open;  // original edge -> first boundary edge
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t a = disk.originalVertex[disk.boundaryLoop[i]],
                       b = disk.originalVertex[disk.boundaryLoop[(i + 1) % n]];
        auto [it, inserted] = open.try_emplace(std::minmax(a, b), i);
        if (!inserted) {
            seam.mates.push_back({it->second, i});
            open.erase(it);
        }
    }
    for (const auto& [key, i] : open) seam.unmatched.push_back(i);
    std::sort(seam.unmatched.begin(), seam.unmatched.end());
    return seam;
}

}  // namespace ngi
