// ngi offline: triangles of a mesh file's polygons (see polygon_triangulation.h). Outlines
// that a fan cannot triangulate go to CGAL's hole triangulation (Liepa 2003, "Filling holes
// in meshes", section 3: the minimum-weight triangulation of a 3D polyline, restricted to a
// Delaunay search space; CGAL tries a 2D constrained Delaunay triangulation first).
#include "polygon_triangulation.h"

#include "ngi/error.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/exceptions.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>

namespace ngi::mesh_io {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

// Above this many corners CGAL's cubic search (its last resort) would take seconds: only the
// Delaunay-restricted searches are tried.
constexpr size_t kMaxCubicCorners = 256;
// A hostile file of thousands of twisted polygons must not take minutes to read. Planar
// outlines go to CGAL's constrained Delaunay triangulation (n log n); a non-planar one to its
// 3D searches, ~27 ms for a twisted 250-gon (measured), so those get a budget per file in
// corners^2 (~160 such polygons, ~4 s), and the cubic search one in corners^3 (~40). Past a
// budget a polygon keeps its fan.
constexpr double kSearchBudget = 1e7;
constexpr double kCubicBudget = 7e8;

// A polygon's triangles as corners of the polygon (0 .. n-1), before they become vertices.
using LocalTriangles = std::vector<glm::uvec3>;

void fan(size_t corners, LocalTriangles& out)
{
    out.clear();
    for (uint32_t k = 1; k + 1 < corners; ++k) out.push_back({0u, k, k + 1});
}

// The polygon's Newell normal (twice its area vector for a planar polygon; robust to
// non-planar and non-convex outlines).
glm::dvec3 newellNormal(std::span<const uint32_t> polygon, const TriangleMesh& mesh)
{
    glm::dvec3 normal(0.0);
    for (size_t k = 0; k < polygon.size(); ++k) {
        const glm::dvec3 a = mesh.positions[polygon[k]], b = mesh.positions[polygon[(k + 1) % polygon.size()]];
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    return normal;
}

// True when every fan triangle from the first corner faces the polygon's Newell normal (the
// polygon is star-shaped from that corner, e.g. convex). Degenerate fan triangles (collinear
// corners) do not count against it: the fan was always read that way.
bool fanFacesTheNormal(std::span<const uint32_t> polygon, const TriangleMesh& mesh)
{
    const glm::dvec3 normal = newellNormal(polygon, mesh);
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
bool hasCoincidentCorners(std::span<const uint32_t> polygon, const TriangleMesh& mesh)
{
    std::vector<glm::dvec3> points;
    points.reserve(polygon.size());
    for (uint32_t v : polygon) points.push_back(mesh.positions[v]);
    const auto less = [](const glm::dvec3& a, const glm::dvec3& b) {
        return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    };
    std::sort(points.begin(), points.end(), less);
    return std::adjacent_find(points.begin(), points.end()) != points.end();
}

// True when `patch` triangulates the n-gon's outline: no triangle repeats a corner, every
// outline edge (i, i + 1 mod n) is used once and every other edge twice.
bool triangulatesTheOutline(const std::vector<CGAL::Triple<int, int, int>>& patch, int n)
{
    std::vector<std::pair<int, int>> edges;
    edges.reserve(patch.size() * 3);
    for (const auto& t : patch) {
        const int c[3] = {t.first, t.second, t.third};
        for (int k = 0; k < 3; ++k) {
            if (c[k] < 0 || c[k] >= n || c[k] == c[(k + 1) % 3]) return false;
            edges.emplace_back(std::min(c[k], c[(k + 1) % 3]), std::max(c[k], c[(k + 1) % 3]));
        }
    }
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        const auto [a, b] = edges[i];
        const bool outline = b == a + 1 || (a == 0 && b == n - 1);
        if (j - i != (outline ? 1u : 2u)) return false;
        i = j;
    }
    return true;
}

// True when every corner lies within 1e-6 of the polygon's extent from its Newell plane
// through the centroid: CGAL then triangulates it in that plane.
bool isPlanar(std::span<const uint32_t> polygon, const TriangleMesh& mesh)
{
    glm::dvec3 normal = newellNormal(polygon, mesh), centroid(0.0), lo(INFINITY), hi(-INFINITY);
    for (uint32_t v : polygon) {
        const glm::dvec3 a = mesh.positions[v];
        centroid += a, lo = glm::min(lo, a), hi = glm::max(hi, a);
    }
    const double length = glm::length(normal);
    if (!(length > 0.0)) return false;
    normal /= length;
    centroid /= double(polygon.size());
    const double tolerance = 1e-6 * glm::length(hi - lo);
    for (uint32_t v : polygon)
        if (std::abs(glm::dot(mesh.positions[v] - centroid, normal)) > tolerance) return false;
    return true;
}

// The outline's n - 2 triangles by CGAL into out (as polygon corners), oriented as the
// polygon; false if CGAL finds none or a budget (kSearchBudget, kCubicBudget) is spent.
bool outlineTriangulation(std::span<const uint32_t> polygon, const TriangleMesh& mesh, LocalTriangles& out,
                          double& searchBudget, double& cubicBudget)
{
    if (hasCoincidentCorners(polygon, mesh)) return false;
    if (!isPlanar(polygon, mesh)) {
        const double searchCost = std::pow(double(polygon.size()), 2.0);
        if (searchCost > searchBudget) return false;
        searchBudget -= searchCost;
    }
    const double cubicCost = std::pow(double(polygon.size()), 3.0);
    const bool cubic = polygon.size() <= kMaxCubicCorners && cubicCost <= cubicBudget;
    if (cubic) cubicBudget -= cubicCost;
    std::vector<Kernel::Point_3> outline;
    outline.reserve(polygon.size());
    for (uint32_t v : polygon) outline.emplace_back(mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z);
    std::vector<CGAL::Triple<int, int, int>> patch;
    try {
        namespace PMP = CGAL::Polygon_mesh_processing;
        PMP::triangulate_hole_polyline(outline, std::back_inserter(patch),
                                       CGAL::parameters::do_not_use_cubic_algorithm(!cubic));
    } catch (const CGAL::Failure_exception&) {
        return false;  // a CGAL precondition or assertion: the caller fans (out of memory is not caught)
    }
    // A triangulation of an n-gon's outline: n - 2 triangles, each outline edge once.
    if (patch.size() != polygon.size() - 2 || !triangulatesTheOutline(patch, int(polygon.size()))) return false;
    out.clear();
    for (const auto& t : patch) {
        // Corners in increasing outline order: every triangle of a polygon's triangulation then
        // has the polygon's orientation.
        int c[3] = {t.first, t.second, t.third};
        std::sort(c, c + 3);
        out.push_back({uint32_t(c[0]), uint32_t(c[1]), uint32_t(c[2])});
    }
    return true;
}

}  // namespace

void PolygonTriangulator::add(std::span<const uint32_t> polygon, TriangleMesh& mesh)
{
    if (polygon.size() < 3) throw Error("polygon triangulation: a polygon needs at least 3 corners");
    const uint64_t first = cornerCount_;
    cornerCount_ += polygon.size();
    if (trackCorners_ && cornerCount_ > UINT32_MAX)
        throw Error("polygon triangulation: more than 2^32-1 polygon corners");
    if (polygon.size() == 3) {
        mesh.triangles.push_back({polygon[0], polygon[1], polygon[2]});
        if (trackCorners_) {
            sources_.resize(mesh.triangles.size() * 3 - 3);  // triangles of other origin: none
            for (uint32_t k = 0; k < 3; ++k) sources_.push_back(uint32_t(first) + k);
        }
        return;
    }
    if (trackCorners_) firstCorners_.push_back(uint32_t(first));
    starts_.push_back(corners_.size());
    corners_.insert(corners_.end(), polygon.begin(), polygon.end());
    firstTriangles_.push_back(mesh.triangles.size());
    mesh.triangles.resize(mesh.triangles.size() + polygon.size() - 2);
}

void PolygonTriangulator::finish(TriangleMesh& mesh)
{
    double searchBudget = kSearchBudget, cubicBudget = kCubicBudget;
    if (trackCorners_) sources_.resize(mesh.triangles.size() * 3);
    LocalTriangles local;
    for (size_t p = 0; p < starts_.size(); ++p) {
        const size_t begin = starts_[p], end = p + 1 < starts_.size() ? starts_[p + 1] : corners_.size();
        const std::span<const uint32_t> polygon(corners_.data() + begin, end - begin);
        if (polygon.size() > kMaxOutlineCorners || fanFacesTheNormal(polygon, mesh) ||
            !outlineTriangulation(polygon, mesh, local, searchBudget, cubicBudget))
            fan(polygon.size(), local);
        const size_t firstTriangle = firstTriangles_[p];
        for (size_t i = 0; i < local.size(); ++i) {
            const glm::uvec3 c = local[i];
            mesh.triangles[firstTriangle + i] = {polygon[c.x], polygon[c.y], polygon[c.z]};
            if (trackCorners_)
                for (int k = 0; k < 3; ++k) sources_[(firstTriangle + i) * 3 + size_t(k)] = firstCorners_[p] + c[k];
        }
    }
    corners_.clear();
    starts_.clear();
    firstTriangles_.clear();
    firstCorners_.clear();
}

}  // namespace ngi::mesh_io
