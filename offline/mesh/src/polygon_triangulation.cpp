// ngi offline: triangles of a mesh file's polygons (see polygon_triangulation.h). Outlines
// that a fan cannot triangulate go to CGAL's hole triangulation (Liepa 2003, "Filling holes
// in meshes", section 3: the minimum-weight triangulation of a 3D polyline, restricted to a
// Delaunay search space; CGAL tries a 2D constrained Delaunay triangulation first).
#include "polygon_triangulation.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <exception>
#include <iterator>

namespace ngi::mesh_io {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Above this many corners CGAL's cubic search (its last resort) would take seconds: only the
// Delaunay-restricted searches are tried.
constexpr size_t kMaxCubicCorners = 256;

void writeFan(std::span<const uint32_t> polygon, glm::uvec3* out) {
    for (size_t k = 1; k + 1 < polygon.size(); ++k) *out++ = {polygon[0], polygon[k], polygon[k + 1]};
}

// True when every fan triangle from the first corner faces the polygon's Newell normal (the
// polygon is star-shaped from that corner, e.g. convex). Degenerate fan triangles (collinear
// corners) do not count against it: the fan was always read that way.
bool fanFacesTheNormal(std::span<const uint32_t> polygon, const TriangleMesh& mesh) {
    glm::dvec3 normal(0.0);
    for (size_t k = 0; k < polygon.size(); ++k) {
        const glm::dvec3 a = mesh.positions[polygon[k]], b = mesh.positions[polygon[(k + 1) % polygon.size()]];
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    const double normalLength = glm::length(normal);
    if (!(normalLength > 0.0)) return true;  // no plane to be folded in: keep the fan
    const glm::dvec3 first = mesh.positions[polygon[0]];
    for (size_t k = 1; k + 1 < polygon.size(); ++k) {
        const glm::dvec3 t = glm::cross(mesh.positions[polygon[k]] - first, mesh.positions[polygon[k + 1]] - first);
        if (glm::dot(t, normal) < -1e-12 * glm::length(t) * normalLength) return false;
    }
    return true;
}

// True when two corners of the polygon are the same point. CGAL's hole triangulation assumes
// distinct points (its Delaunay search merges coincident ones) and checks that only in debug
// builds; such a polygon keeps the fan.
bool hasCoincidentCorners(std::span<const uint32_t> polygon, const TriangleMesh& mesh) {
    std::vector<glm::dvec3> points;
    points.reserve(polygon.size());
    for (uint32_t v : polygon) points.push_back(mesh.positions[v]);
    const auto less = [](const glm::dvec3& a, const glm::dvec3& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    };
    std::sort(points.begin(), points.end(), less);
    return std::adjacent_find(points.begin(), points.end()) != points.end();
}

// The outline's n - 2 triangles by CGAL into out, oriented as the polygon; false (nothing
// written) if CGAL finds none.
bool writeOutlineTriangulation(std::span<const uint32_t> polygon, const TriangleMesh& mesh, glm::uvec3* out) {
    if (hasCoincidentCorners(polygon, mesh)) return false;
    std::vector<Kernel::Point_3> outline;
    outline.reserve(polygon.size());
    for (uint32_t v : polygon) outline.emplace_back(mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z);
    std::vector<CGAL::Triple<int, int, int>> patch;
    try {
        namespace PMP = CGAL::Polygon_mesh_processing;
        PMP::triangulate_hole_polyline(outline, std::back_inserter(patch),
                                       CGAL::parameters::do_not_use_cubic_algorithm(polygon.size() > kMaxCubicCorners));
    } catch (const std::exception&) {
        return false;  // a CGAL precondition (coincident corners, ...): the caller fans
    }
    // A triangulation of an n-gon's outline has n - 2 triangles using corners only.
    if (patch.size() != polygon.size() - 2) return false;
    const int n = int(polygon.size());
    for (const auto& t : patch)
        if (t.first < 0 || t.second < 0 || t.third < 0 || t.first >= n || t.second >= n || t.third >= n) return false;
    for (const auto& t : patch) {
        // Corners in increasing outline order: every triangle of a polygon's triangulation then
        // has the polygon's orientation.
        int c[3] = {t.first, t.second, t.third};
        std::sort(c, c + 3);
        *out++ = {polygon[size_t(c[0])], polygon[size_t(c[1])], polygon[size_t(c[2])]};
    }
    return true;
}

} // namespace

void PolygonTriangulator::add(std::span<const uint32_t> polygon, TriangleMesh& mesh) {
    if (polygon.size() == 3) {
        mesh.triangles.push_back({polygon[0], polygon[1], polygon[2]});
        return;
    }
    starts_.push_back(corners_.size());
    corners_.insert(corners_.end(), polygon.begin(), polygon.end());
    firstTriangles_.push_back(mesh.triangles.size());
    mesh.triangles.resize(mesh.triangles.size() + polygon.size() - 2);
}

void PolygonTriangulator::finish(TriangleMesh& mesh) {
    for (size_t p = 0; p < starts_.size(); ++p) {
        const size_t begin = starts_[p], end = p + 1 < starts_.size() ? starts_[p + 1] : corners_.size();
        const std::span<const uint32_t> polygon(corners_.data() + begin, end - begin);
        glm::uvec3* out = mesh.triangles.data() + firstTriangles_[p];
        if (polygon.size() > kMaxOutlineCorners || fanFacesTheNormal(polygon, mesh) ||
            !writeOutlineTriangulation(polygon, mesh, out))
            writeFan(polygon, out);
    }
    corners_.clear();
    starts_.clear();
    firstTriangles_.clear();
}

} // namespace ngi::mesh_io
