// ngi offline: edge table, boundary loops, components and Euler characteristic.
#include "ngi/mesh/mesh_topology.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>

namespace ngi {

MeshEdges buildMeshEdges(const TriangleMesh& mesh)
{
    const size_t vertexCount = mesh.positions.size();
    struct HalfEdge {
        uint64_t key;
        uint32_t face;
        uint32_t corner;
    };
    std::vector<HalfEdge> halfEdges;
    halfEdges.reserve(mesh.triangles.size() * 3);
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t)
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
            if (a >= vertexCount || b >= vertexCount)
                throw Error("triangle " + std::to_string(t) + " refers to vertex " + std::to_string(std::max(a, b)) +
                            " but the mesh has " + std::to_string(vertexCount) + " vertices");
            auto [lo, hi] = std::minmax(a, b);
            halfEdges.push_back({(uint64_t(lo) << 32) | hi, t, k});
        }
    std::sort(halfEdges.begin(), halfEdges.end(),
              [](const HalfEdge& l, const HalfEdge& r) { return std::tie(l.key, l.face) < std::tie(r.key, r.face); });
    MeshEdges edges;
    edges.faceEdges.resize(mesh.triangles.size());
    for (size_t i = 0; i < halfEdges.size();) {
        size_t j = i;
        while (j < halfEdges.size() && halfEdges[j].key == halfEdges[i].key) ++j;
        const uint32_t e = uint32_t(edges.vertices.size());
        edges.vertices.push_back({uint32_t(halfEdges[i].key >> 32), uint32_t(halfEdges[i].key & 0xffffffffu)});
        edges.faces.push_back({halfEdges[i].face, j - i > 1 ? halfEdges[i + 1].face : kNoFace});
        if (j - i > 2 && edges.nonManifoldEdges++ == 0) {
            edges.nonManifoldExample = e;
            edges.nonManifoldExampleFaces = j - i;
        }
        for (size_t h = i; h < j; ++h) edges.faceEdges[halfEdges[h].face][halfEdges[h].corner] = e;
        i = j;
    }
    return edges;
}

std::vector<std::vector<uint32_t>> findBoundaryLoops(const TriangleMesh& mesh, const MeshEdges& edges)
{
    // next[a] = b for every boundary half-edge a -> b, directed as in its triangle.
    std::vector<uint32_t> next(mesh.positions.size(), kNoFace);
    size_t boundaryEdges = 0;
    for (uint32_t e = 0; e < edges.vertices.size(); ++e) {
        if (!edges.isBoundary(e)) continue;
        const glm::uvec3& t = mesh.triangles[edges.faces[e].x];
        uint32_t a = 0, b = 0;
        for (int k = 0; k < 3; ++k)
            if (edges.faceEdges[edges.faces[e].x][k] == e) a = t[k], b = t[(k + 1) % 3];
        if (next[a] != kNoFace)
            throw Error("boundary vertex " + std::to_string(a) + " starts two boundary edges (non-manifold boundary)");
        next[a] = b;
        ++boundaryEdges;
    }
    std::vector<std::vector<uint32_t>> loops;
    std::vector<uint8_t> visited(mesh.positions.size(), 0);
    for (uint32_t start = 0; start < next.size(); ++start) {
        if (next[start] == kNoFace || visited[start]) continue;
        std::vector<uint32_t> loop;
        for (uint32_t v = start; !visited[v]; v = next[v]) {
            if (next[v] == kNoFace) throw Error("boundary is not closed at vertex " + std::to_string(v));
            visited[v] = 1;
            loop.push_back(v);
        }
        loops.push_back(std::move(loop));
    }
    size_t total = 0;
    for (const auto& loop : loops) total += loop.size();
    if (total != boundaryEdges) throw Error("boundary edges do not form simple loops");
    return loops;
}

FaceComponents findFaceComponents(const TriangleMesh& mesh, const MeshEdges& edges)
{
    FaceComponents result;
    result.componentOfFace.assign(mesh.triangles.size(), kNoFace);
    std::vector<uint32_t> stack;
    for (uint32_t seed = 0; seed < mesh.triangles.size(); ++seed) {
        if (result.componentOfFace[seed] != kNoFace) continue;
        const uint32_t id = result.count++;
        result.componentOfFace[seed] = id;
        stack.push_back(seed);
        while (!stack.empty()) {
            uint32_t t = stack.back();
            stack.pop_back();
            for (int k = 0; k < 3; ++k) {
                const glm::uvec2& f = edges.faces[edges.faceEdges[t][k]];
                for (uint32_t n : {f.x, f.y})
                    if (n != kNoFace && result.componentOfFace[n] == kNoFace) {
                        result.componentOfFace[n] = id;
                        stack.push_back(n);
                    }
            }
        }
    }
    return result;
}

MeshTopology analyzeTopology(const TriangleMesh& mesh)
{
    MeshEdges edges = buildMeshEdges(mesh);
    MeshTopology topology;
    std::vector<uint8_t> referenced(mesh.positions.size(), 0);
    for (const glm::uvec3& t : mesh.triangles) referenced[t.x] = referenced[t.y] = referenced[t.z] = 1;
    topology.vertices = size_t(std::count(referenced.begin(), referenced.end(), uint8_t(1)));
    topology.edges = edges.vertices.size();
    topology.faces = mesh.triangles.size();
    topology.nonManifoldEdges = edges.nonManifoldEdges;
    topology.boundaryLoops = findBoundaryLoops(mesh, edges).size();
    topology.components = findFaceComponents(mesh, edges).count;
    topology.eulerCharacteristic = long(topology.vertices) - long(topology.edges) + long(topology.faces);
    topology.genus = (2 - long(topology.boundaryLoops) - topology.eulerCharacteristic) / 2;
    return topology;
}

std::vector<double> vertexAngleSums(const TriangleMesh& mesh)
{
    std::vector<double> sum(mesh.positions.size(), 0.0);
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 a = mesh.positions[t[k]], b = mesh.positions[t[(k + 1) % 3]],
                             c = mesh.positions[t[(k + 2) % 3]];
            const double lb = glm::length(b - a), lc = glm::length(c - a);
            if (lb > 0.0 && lc > 0.0) sum[t[k]] += std::acos(std::clamp(glm::dot(b - a, c - a) / (lb * lc), -1.0, 1.0));
        }
    return sum;
}

}  // namespace ngi
