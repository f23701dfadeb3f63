// ngi offline: ngi-bake stage 2, mesh cleaning (see clean.h for the contract).
// Plain connectivity work (sorting, union-find, breadth-first orientation); no CGAL.
#include "ngi/mesh/clean.h"

#include "ngi/error.h"
#include "ngi/mesh/manifold_repair.h"
#include "ngi/mesh/mesh_topology.h"
#include "union_find.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <unordered_set>

namespace ngi {
namespace {

std::string describe(const glm::dvec3& p)
{
    std::ostringstream out;
    out << "(" << p.x << ", " << p.y << ", " << p.z << ")";
    return out.str();
}

double triangleArea(const TriangleMesh& mesh, const glm::uvec3& t)
{
    return 0.5 *
        glm::length(glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
}

bool hasDirectedEdge(const glm::uvec3& t, uint32_t a, uint32_t b)
{
    for (int k = 0; k < 3; ++k)
        if (t[k] == a && t[(k + 1) % 3] == b) return true;
    return false;
}

// Merges vertices at identical positions; returns how many were merged.
size_t mergeDuplicateVertices(TriangleMesh& mesh)
{
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
// Conflicting edges (where the breadth-first orientation meets itself reversed: a
// Moebius-like strip) are appended to `conflicts`; the caller cuts them and orients again.
size_t orientConsistently(TriangleMesh& mesh, const MeshEdges& edges, std::vector<glm::uvec2>& conflicts)
{
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
                    if (std::minmax(edges.vertices[candidate].x, edges.vertices[candidate].y) == std::minmax(a, b))
                        edge = candidate;
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
                    conflicts.push_back(edges.vertices[edge]);
                }
            }
        }
    }
    return flipped;
}

// Removes zero-area triangles; see CleanOptions::zeroAreaRepairPasses.
void repairZeroAreaTriangles(TriangleMesh& mesh, double minimumArea, int passes, CleanReport& report)
{
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

// Drops the components of (near) zero area (CleanOptions::nearZeroAreaRatio) with a warning;
// returns how many components are kept. Throws where none would be.
size_t dropNearZeroAreaComponents(TriangleMesh& mesh, const MeshEdges& edges, const CleanOptions& options,
                                  CleanReport& report)
{
    const FaceComponents components = findFaceComponents(mesh, edges);
    if (!(options.nearZeroAreaRatio > 0.0)) return components.count;
    std::vector<double> area(components.count, 0.0);
    std::vector<glm::dvec3> lo(components.count, glm::dvec3(std::numeric_limits<double>::max()));
    std::vector<glm::dvec3> hi(components.count, glm::dvec3(-std::numeric_limits<double>::max()));
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const uint32_t c = components.componentOfFace[f];
        area[c] += triangleArea(mesh, mesh.triangles[f]);
        for (int k = 0; k < 3; ++k) {
            lo[c] = glm::min(lo[c], mesh.positions[mesh.triangles[f][k]]);
            hi[c] = glm::max(hi[c], mesh.positions[mesh.triangles[f][k]]);
        }
    }
    std::vector<uint8_t> drop(components.count, 0);
    double totalArea = 0.0, droppedArea = 0.0, worstRatio = std::numeric_limits<double>::max(), worstDiagonal = 0.0;
    for (uint32_t c = 0; c < components.count; ++c) {
        const double diagonal = glm::distance(lo[c], hi[c]), ratio = area[c] / (diagonal * diagonal);
        totalArea += area[c];
        if (!(ratio < options.nearZeroAreaRatio)) continue;
        drop[c] = 1;
        droppedArea += area[c];
        ++report.droppedZeroAreaComponents;
        if (ratio < worstRatio) worstRatio = ratio, worstDiagonal = diagonal;
    }
    if (report.droppedZeroAreaComponents == 0) return components.count;
    std::ostringstream figures;
    figures << "area " << droppedArea << "; area / bounding box diagonal^2 = " << worstRatio << " over a diagonal of "
            << worstDiagonal << ", below " << options.nearZeroAreaRatio
            << ": a sliver or a needle no geometry image samples";
    if (report.droppedZeroAreaComponents == components.count)
        throw Error(options.sourceName + ": the surface has (near) zero area (" + figures.str() + "): nothing to bake");
    std::vector<glm::uvec3> kept;
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
        if (!drop[components.componentOfFace[f]]) kept.push_back(mesh.triangles[f]);
    report.droppedComponentTriangles = mesh.triangles.size() - kept.size();
    report.keptAreaFraction = (totalArea - droppedArea) / totalArea;
    mesh.triangles = std::move(kept);
    report.warnings.push_back(options.sourceName + ": dropped " + std::to_string(report.droppedZeroAreaComponents) +
                              " of " + std::to_string(components.count) + " components for (near) zero area (" +
                              std::to_string(report.droppedComponentTriangles) + " triangles, " + figures.str() + ")");
    return components.count - report.droppedZeroAreaComponents;
}

}  // namespace

CleanResult cleanMesh(const TriangleMesh& input, const CleanOptions& options)
{
    const std::string& name = options.sourceName;
    CleanResult result;
    CleanReport& report = result.report;
    report.inputVertices = input.positions.size();
    report.inputTriangles = input.triangles.size();
    if (input.triangles.empty()) throw Error(name + ": the mesh is empty (no triangles)");
    for (size_t i = 0; i < input.positions.size(); ++i)
        if (!std::isfinite(input.positions[i].x) || !std::isfinite(input.positions[i].y) ||
            !std::isfinite(input.positions[i].z))
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
            return std::tie(l.first.x, l.first.y, l.first.z, l.second) <
                std::tie(r.first.x, r.first.y, r.first.z, r.second);
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

    // Non-manifold edges and vertices are cut apart, never refused.
    const ManifoldRepair repair = splitNonManifold(mesh);
    report.nonManifoldEdges = repair.nonManifoldEdges;
    report.cutEdgeSides = repair.cutEdgeSides;
    report.splitNonManifoldVertices = repair.splitVertices;
    report.droppedNonManifoldTriangles = repair.droppedTriangles;
    if (mesh.triangles.empty()) throw Error(name + ": no triangle is left after the non-manifold repair");

    // Orientation; a non-orientable strip is cut where its orientation conflicts, then
    // oriented again (a few rounds at most: each cut opens the strip further).
    MeshEdges edges = buildMeshEdges(mesh);
    for (int round = 0;; ++round) {
        std::vector<glm::uvec2> conflicts;
        TriangleMesh oriented = mesh;
        const size_t flipped = orientConsistently(oriented, edges, conflicts);
        if (conflicts.empty()) {
            mesh = std::move(oriented);
            report.flippedTriangles = flipped;
            break;
        }
        if (round == 3) {
            const uint32_t a = conflicts[0].x;
            throw Error(name + ": the surface is not orientable (a Moebius-like strip) near vertex " +
                        std::to_string(a) + " at " + describe(mesh.positions[a]) +
                        ", and cutting it open did not help");
        }
        const ManifoldRepair cut = splitNonManifold(mesh, conflicts);
        report.orientationCutEdges += conflicts.size();
        report.splitNonManifoldVertices += cut.splitVertices;
        edges = buildMeshEdges(mesh);
    }

    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::uvec3& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) lo = glm::min(lo, mesh.positions[t[k]]), hi = glm::max(hi, mesh.positions[t[k]]);
    const double diagonal = glm::distance(lo, hi);
    if (!(diagonal > 0.0)) throw Error(name + ": all vertices are at one point (zero-size mesh)");
    repairZeroAreaTriangles(mesh, options.zeroAreaTolerance * diagonal * diagonal, options.zeroAreaRepairPasses,
                            report);
    if (mesh.triangles.empty()) throw Error(name + ": every triangle has zero area (nothing left after cleaning)");
    edges = buildMeshEdges(mesh);

    // Every component with a surface is kept: the bake makes one chart of each.
    report.components = dropNearZeroAreaComponents(mesh, edges, options, report);

    // The zero-area repair can join two fans at a vertex again: split them.
    report.splitNonManifoldVertices += splitNonManifold(mesh).splitVertices;

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

    // Each closed component is turned outward (positive enclosed volume).
    edges = buildMeshEdges(mesh);
    const FaceComponents components = findFaceComponents(mesh, edges);
    std::vector<uint8_t> open(components.count, 0);
    std::vector<double> volume(components.count, 0.0);
    for (uint32_t e = 0; e < edges.faces.size(); ++e)
        if (edges.isBoundary(e)) open[components.componentOfFace[edges.faces[e].x]] = 1;
    glm::dvec3 centre(0.0);
    for (const glm::dvec3& p : mesh.positions) centre += p;
    centre /= double(mesh.positions.size());
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const glm::uvec3& t = mesh.triangles[f];
        volume[components.componentOfFace[f]] += glm::dot(
            mesh.positions[t.x] - centre, glm::cross(mesh.positions[t.y] - centre, mesh.positions[t.z] - centre));
    }
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const uint32_t c = components.componentOfFace[f];
        if (!open[c] && volume[c] < 0.0) std::swap(mesh.triangles[f].y, mesh.triangles[f].z);
    }
    for (uint32_t c = 0; c < components.count; ++c)
        if (!open[c] && volume[c] < 0.0) ++report.reversedComponents;
    report.reversedToOutward = report.reversedComponents > 0;
    if (report.nonManifoldEdges > 0 || report.orientationCutEdges > 0)
        report.warnings.push_back(name + ": repaired " + std::to_string(report.nonManifoldEdges) +
                                  " non-manifold edges and " + std::to_string(report.orientationCutEdges) +
                                  " orientation conflicts by cutting (" + std::to_string(report.cutEdgeSides) +
                                  " triangle sides opened, " + std::to_string(report.splitNonManifoldVertices) +
                                  " vertices split)");
    if (report.droppedNonManifoldTriangles > 0)
        report.warnings.push_back(name + ": dropped " + std::to_string(report.droppedNonManifoldTriangles) +
                                  " triangles that no cut could make manifold");
    if (report.droppedZeroAreaTriangles > 0)
        report.warnings.push_back(name + ": " + std::to_string(report.droppedZeroAreaTriangles) +
                                  " zero-area triangles could not be repaired and were dropped (zero-width holes)");
    result.mesh = std::move(mesh);
    return result;
}

}  // namespace ngi

namespace ngi {

std::vector<TriangleMesh> splitComponents(const TriangleMesh& mesh)
{
    const MeshEdges edges = buildMeshEdges(mesh);
    const FaceComponents components = findFaceComponents(mesh, edges);
    std::vector<double> area(components.count, 0.0);
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f)
        area[components.componentOfFace[f]] += triangleArea(mesh, mesh.triangles[f]);
    std::vector<uint32_t> order(components.count);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return area[a] > area[b]; });
    std::vector<uint32_t> rank(components.count);
    for (uint32_t i = 0; i < order.size(); ++i) rank[order[i]] = i;
    std::vector<TriangleMesh> parts(components.count);
    std::vector<uint32_t> local(mesh.positions.size(), kNoFace), owner(mesh.positions.size(), kNoFace);
    for (uint32_t f = 0; f < mesh.triangles.size(); ++f) {
        const uint32_t c = rank[components.componentOfFace[f]];
        TriangleMesh& part = parts[c];
        glm::uvec3 t;
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = mesh.triangles[f][k];
            if (owner[v] != c) {
                owner[v] = c;
                local[v] = uint32_t(part.positions.size());
                part.positions.push_back(mesh.positions[v]);
            }
            t[k] = local[v];
        }
        part.triangles.push_back(t);
    }
    return parts;
}

}  // namespace ngi
