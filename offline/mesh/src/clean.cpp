// ngi offline: ngi-bake stage 2, mesh cleaning (see clean.h for the contract).
// Plain connectivity work (sorting, union-find, breadth-first orientation); no CGAL.
#include "ngi/mesh/clean.h"

#include "ngi/error.h"
#include "ngi/mesh/mesh_topology.h"
#include "union_find.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <unordered_set>

namespace ngi {
namespace {

using detail::UnionFind;

std::string describe(const glm::dvec3& p) {
    std::ostringstream out;
    out << "(" << p.x << ", " << p.y << ", " << p.z << ")";
    return out.str();
}

double triangleArea(const TriangleMesh& mesh, const glm::uvec3& t) {
    return 0.5 * glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
}

bool hasDirectedEdge(const glm::uvec3& t, uint32_t a, uint32_t b) {
    for (int k = 0; k < 3; ++k)
        if (t[k] == a && t[(k + 1) % 3] == b) return true;
    return false;
}

// Merges vertices at identical positions; returns how many were merged.
size_t mergeDuplicateVertices(TriangleMesh& mesh) {
    std::vector<uint32_t> order(mesh.positions.size());
    std::iota(order.begin(), order.end(), 0u);
    auto less = [&](uint32_t a, uint32_t b) {
        const glm::dvec3 &p = mesh.positions[a], &q = mesh.positions[b];
        return std::tie(p.x, p.y, p.z, a) < std::tie(q.x, q.y, q.z, b);
    };
    std::sort(order.begin(), order.end(), less);
    std::vector<uint32_t> representative(mesh.positions.size());
    size_t merged = 0;
    for (size_t i = 0; i < order.size(); ++i) {
        if (i > 0 && mesh.positions[order[i]] == mesh.positions[order[i - 1]]) {
            representative[order[i]] = representative[order[i - 1]];
            ++merged;
        } else {
            representative[order[i]] = order[i];
        }
    }
    for (glm::uvec3& t : mesh.triangles) t = {representative[t.x], representative[t.y], representative[t.z]};
    return merged;
}

// Orients all triangles consistently per component (breadth-first from each seed).
size_t orientConsistently(TriangleMesh& mesh, const MeshEdges& edges, const std::string& name) {
    std::vector<uint8_t> visited(mesh.triangles.size(), 0);
    std::vector<uint32_t> queue;
    size_t flipped = 0;
    for (uint32_t seed = 0; seed < mesh.triangles.size(); ++seed) {
        if (visited[seed]) continue;
        visited[seed] = 1;
        queue.assign(1, seed);
        for (size_t head = 0; head < queue.size(); ++head) {
            const uint32_t f = queue[head];
            for (int k = 0; k < 3; ++k) {
                const uint32_t a = mesh.triangles[f][k], b = mesh.triangles[f][(k + 1) % 3];
                uint32_t edge = edges.faceEdges[f][0];  // corners move when f is flipped: look the edge up
                for (uint32_t candidate : {edges.faceEdges[f][0], edges.faceEdges[f][1], edges.faceEdges[f][2]})
                    if (std::minmax(edges.vertices[candidate].x, edges.vertices[candidate].y) == std::minmax(a, b)) edge = candidate;
                const glm::uvec2& pair = edges.faces[edge];
                const uint32_t g = pair.x == f ? pair.y : pair.x;
                if (g == kNoFace) continue;
                const bool sameDirection = hasDirectedEdge(mesh.triangles[g], a, b);
                if (!visited[g]) {
                    visited[g] = 1;
                    if (sameDirection) {
                        std::swap(mesh.triangles[g].y, mesh.triangles[g].z);
                        ++flipped;
                    }
                    queue.push_back(g);
                } else if (sameDirection) {
                    throw Error(name + ": the surface is not orientable (a Moebius-like strip) near vertex " +
                                std::to_string(a) + " at " + describe(mesh.positions[a]));
                }
            }
        }
    }
    return flipped;
}

// Removes zero-area triangles; see CleanOptions::zeroAreaRepairPasses.
void repairZeroAreaTriangles(TriangleMesh& mesh, double minimumArea, int passes, CleanReport& report) {
    for (int pass = 0; pass <= passes; ++pass) {
        const bool lastPass = pass == passes;
        MeshEdges edges = buildMeshEdges(mesh);
        std::vector<uint8_t> removed(mesh.triangles.size(), 0), touched(mesh.triangles.size(), 0);
        std::vector<glm::uvec3> added;
        std::unordered_set<uint64_t> existing;
        for (const glm::uvec2& e : edges.vertices) existing.insert((uint64_t(e.x) << 32) | e.y);
        size_t found = 0;
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
            const glm::uvec3 t = mesh.triangles[f];
            if (triangleArea(mesh, t) >= minimumArea) continue;
            ++found;
            if (touched[f]) continue;
            int longest = 0;
            for (int k = 1; k < 3; ++k)
                if (glm::distance(mesh.positions[t[k]], mesh.positions[t[(k + 1) % 3]]) >
                    glm::distance(mesh.positions[t[longest]], mesh.positions[t[(longest + 1) % 3]]))
                    longest = k;
            const uint32_t a = t[longest], b = t[(longest + 1) % 3], c = t[(longest + 2) % 3];
            const glm::uvec2& pair = edges.faces[edges.faceEdges[f][longest]];
            const uint32_t g = pair.x == f ? pair.y : pair.x;
            if (g != kNoFace && touched[g]) continue;  // next pass
            bool split = g != kNoFace && !lastPass;
            uint32_t d = 0;
            if (split) {
                const glm::uvec3& n = mesh.triangles[g];
                for (int k = 0; k < 3; ++k)
                    if (n[k] != a && n[k] != b) d = n[k];
                // Splitting must not create an edge c-d that already exists (non-manifold).
                if (existing.count((uint64_t(std::min(c, d)) << 32) | std::max(c, d))) split = false;
            }
            if (split) {
                added.push_back({b, c, d});  // g = (b, a, d) split at c, orientation kept
                added.push_back({c, a, d});
                removed[g] = touched[g] = 1;
                ++report.repairedZeroAreaTriangles;
            } else if (g == kNoFace) {
                ++report.repairedZeroAreaTriangles;  // a boundary cap: the boundary just bends
            } else {
                if (!lastPass) continue;
                ++report.droppedZeroAreaTriangles;
            }
            removed[f] = touched[f] = 1;
        }
        if (found == 0) return;
        std::vector<glm::uvec3> kept;
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
            if (!removed[f]) kept.push_back(mesh.triangles[f]);
        kept.insert(kept.end(), added.begin(), added.end());
        mesh.triangles = std::move(kept);
    }
}

} // namespace

CleanResult cleanMesh(const TriangleMesh& input, const CleanOptions& options) {
    const std::string& name = options.sourceName;
    CleanResult result;
    CleanReport& report = result.report;
    report.inputVertices = input.positions.size();
    report.inputTriangles = input.triangles.size();
    if (input.triangles.empty()) throw Error(name + ": the mesh is empty (no triangles)");
    for (size_t i = 0; i < input.positions.size(); ++i)
        if (!std::isfinite(input.positions[i].x) || !std::isfinite(input.positions[i].y) || !std::isfinite(input.positions[i].z))
            throw Error(name + ": vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
    for (const glm::uvec3& t : input.triangles)
        if (std::max({t.x, t.y, t.z}) >= input.positions.size())
            throw Error(name + ": a triangle refers to vertex " + std::to_string(std::max({t.x, t.y, t.z})) + " of " +
                        std::to_string(input.positions.size()));

    TriangleMesh mesh = input;
    report.mergedDuplicateVertices = mergeDuplicateVertices(mesh);

    // Degenerate (repeated vertex) and duplicate (same vertex set) triangles.
    {
        std::vector<std::pair<glm::uvec3, uint32_t>> keyed;
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
            glm::uvec3 t = mesh.triangles[f];
            if (t.x == t.y || t.y == t.z || t.z == t.x) {
                ++report.droppedDegenerateTriangles;
                continue;
            }
            glm::uvec3 key = t;
            std::sort(&key.x, &key.x + 3);
            keyed.push_back({key, f});
        }
        std::sort(keyed.begin(), keyed.end(), [](const auto& l, const auto& r) {
            return std::tie(l.first.x, l.first.y, l.first.z, l.second) < std::tie(r.first.x, r.first.y, r.first.z, r.second);
        });
        std::vector<uint32_t> keep;
        for (size_t i = 0; i < keyed.size(); ++i) {
            if (i > 0 && keyed[i].first == keyed[i - 1].first) {
                ++report.droppedDuplicateTriangles;
                continue;
            }
            keep.push_back(keyed[i].second);
        }
        std::sort(keep.begin(), keep.end());  // keep the file's triangle order
        std::vector<glm::uvec3> triangles;
        for (uint32_t f : keep) triangles.push_back(mesh.triangles[f]);
        mesh.triangles = std::move(triangles);
    }
    if (mesh.triangles.empty()) throw Error(name + ": every triangle is degenerate (nothing left after cleaning)");

    MeshEdges edges = buildMeshEdges(mesh);
    if (edges.nonManifoldEdges > 0) {
        const glm::uvec2 e = edges.vertices[edges.nonManifoldExample];
        throw Error(name + ": non-manifold edge: " + std::to_string(edges.nonManifoldExampleFaces) +
                    " triangles share the edge between " + describe(mesh.positions[e.x]) + " and " +
                    describe(mesh.positions[e.y]) + " (" + std::to_string(edges.nonManifoldEdges) +
                    " such edges; cannot be repaired automatically)");
    }
    report.flippedTriangles = orientConsistently(mesh, edges, name);

    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) lo = glm::min(lo, mesh.positions[t[k]]), hi = glm::max(hi, mesh.positions[t[k]]);
    const double diagonal = glm::distance(lo, hi);
    if (!(diagonal > 0.0)) throw Error(name + ": all vertices are at one point (zero-size mesh)");
    repairZeroAreaTriangles(mesh, options.zeroAreaTolerance * diagonal * diagonal, options.zeroAreaRepairPasses, report);
    if (mesh.triangles.empty()) throw Error(name + ": every triangle has zero area (nothing left after cleaning)");
    edges = buildMeshEdges(mesh);

    // Keep the largest component by area.
    FaceComponents components = findFaceComponents(mesh, edges);
    report.components = components.count;
    if (components.count > 1) {
        std::vector<double> area(components.count, 0.0);
        double total = 0.0;
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
            double a = triangleArea(mesh, mesh.triangles[f]);
            area[components.componentOfFace[f]] += a;
            total += a;
        }
        const uint32_t largest = uint32_t(std::max_element(area.begin(), area.end()) - area.begin());
        std::vector<glm::uvec3> kept;
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
            if (components.componentOfFace[f] == largest) kept.push_back(mesh.triangles[f]);
        report.droppedComponentTriangles = mesh.triangles.size() - kept.size();
        report.keptAreaFraction = total > 0.0 ? area[largest] / total : 1.0;
        mesh.triangles = std::move(kept);
        std::ostringstream warning;
        warning << name << ": the mesh has " << components.count << " connected components; baking only the largest ("
                << mesh.triangles.size() << " triangles, " << 100.0 * report.keptAreaFraction << "% of the area), dropping "
                << report.droppedComponentTriangles << " triangles";
        report.warnings.push_back(warning.str());
        edges = buildMeshEdges(mesh);
    }

    // Non-manifold vertices: corners of one vertex joined across shared edges; each extra fan
    // gets its own copy of the vertex.
    {
        UnionFind corners(mesh.triangles.size() * 3);
        auto corner = [&](uint32_t f, uint32_t v) {
            for (uint32_t k = 0; k < 3; ++k)
                if (mesh.triangles[f][k] == v) return f * 3 + k;
            return f * 3;
        };
        for (uint32_t e = 0; e < edges.vertices.size(); ++e) {
            if (edges.isBoundary(e)) continue;
            for (uint32_t v : {edges.vertices[e].x, edges.vertices[e].y})
                corners.unite(corner(edges.faces[e].x, v), corner(edges.faces[e].y, v));
        }
        std::vector<uint32_t> fanOfVertex(mesh.positions.size(), kNoFace);  // first fan's root
        std::vector<std::pair<uint32_t, uint32_t>> extraFans;               // (root, new vertex)
        for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t v = mesh.triangles[f][k], root = corners.find(f * 3 + k);
                if (fanOfVertex[v] == kNoFace) fanOfVertex[v] = root;
                if (fanOfVertex[v] == root) continue;
                auto it = std::find_if(extraFans.begin(), extraFans.end(), [&](const auto& p) { return p.first == root; });
                if (it == extraFans.end()) {
                    extraFans.push_back({root, uint32_t(mesh.positions.size())});
                    mesh.positions.push_back(mesh.positions[v]);
                    it = extraFans.end() - 1;
                }
                mesh.triangles[f][k] = it->second;
            }
        report.splitNonManifoldVertices = extraFans.size();
    }

    // Compact: drop unreferenced vertices, keep the order of the rest.
    {
        std::vector<uint32_t> remap(mesh.positions.size(), kNoFace);
        for (const glm::uvec3& t : mesh.triangles) remap[t.x] = remap[t.y] = remap[t.z] = 0;
        TriangleMesh compact;
        for (uint32_t v = 0; v < mesh.positions.size(); ++v)
            if (remap[v] == 0) {
                remap[v] = uint32_t(compact.positions.size());
                compact.positions.push_back(mesh.positions[v]);
            }
        for (const glm::uvec3& t : mesh.triangles) compact.triangles.push_back({remap[t.x], remap[t.y], remap[t.z]});
        // Merged duplicates and dropped components also leave vertices unreferenced.
        report.removedUnreferencedVertices = mesh.positions.size() - compact.positions.size();
        mesh = std::move(compact);
    }

    // A closed mesh is turned outward (positive enclosed volume).
    edges = buildMeshEdges(mesh);
    bool closed = std::none_of(edges.faces.begin(), edges.faces.end(), [](const glm::uvec2& f) { return f.y == kNoFace; });
    if (closed) {
        glm::dvec3 centre(0.0);
        for (const glm::dvec3& p : mesh.positions) centre += p;
        centre /= double(mesh.positions.size());
        double volume = 0.0;
        for (const glm::uvec3& t : mesh.triangles)
            volume += glm::dot(mesh.positions[t.x] - centre,
                               glm::cross(mesh.positions[t.y] - centre, mesh.positions[t.z] - centre));
        if (volume < 0.0) {
            for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
            report.reversedToOutward = true;
        }
    }
    if (report.droppedZeroAreaTriangles > 0)
        report.warnings.push_back(name + ": " + std::to_string(report.droppedZeroAreaTriangles) +
                                  " zero-area triangles could not be repaired and were dropped (zero-width holes)");
    result.mesh = std::move(mesh);
    return result;
}

} // namespace ngi
