// ngi offline: detail transfer from the input surface into a geometry image (Gu, Gortler,
// Hoppe 2002, "Geometry images", section 5: sample the original surface through the map;
// closest points by CGAL's AABB tree, Alliez, Tayeb, Wormser, "3D Fast Intersection and
// Distance Computation"). See detail_transfer.h for why and when a sample moves.
#include "ngi/param/detail_transfer.h"

#include "ngi/error.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <optional>
#include <thread>

namespace ngi {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

// Barycentric coordinates of q (on the triangle's plane, closest point) in (a, b, c).
glm::dvec3 barycentric(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& q) {
    const glm::dvec3 e0 = b - a, e1 = c - a, d = q - a;
    const double d00 = glm::dot(e0, e0), d01 = glm::dot(e0, e1), d11 = glm::dot(e1, e1);
    const double d20 = glm::dot(d, e0), d21 = glm::dot(d, e1);
    const double det = d00 * d11 - d01 * d01;
    if (!(det > 0.0)) return {1.0, 0.0, 0.0};
    const double v = (d11 * d20 - d01 * d21) / det, w = (d00 * d21 - d01 * d20) / det;
    return {1.0 - v - w, v, w};
}

} // namespace

DetailTransferReport transferDetail(const TriangleMesh& input, GeometryImage& positions, GeometryImage& normals,
                                    const DetailTransferOptions& options) {
    if (positions.texels.size() != normals.texels.size())
        throw Error("detail transfer: position and normal images differ in size");
    // Area-weighted vertex normals of the input, and its non-degenerate triangles.
    std::vector<glm::dvec3> vertexNormal(input.positions.size(), glm::dvec3(0.0));
    std::vector<Triangle> triangles;
    std::vector<uint32_t> triangleIndex;
    triangles.reserve(input.triangles.size());
    for (size_t t = 0; t < input.triangles.size(); ++t) {
        const glm::uvec3 tri = input.triangles[t];
        const glm::dvec3 a = input.positions[tri.x], b = input.positions[tri.y], c = input.positions[tri.z];
        const glm::dvec3 n = glm::cross(b - a, c - a);
        if (!(glm::length(n) > 0.0)) continue;
        for (int k = 0; k < 3; ++k) vertexNormal[tri[k]] += n;
        triangles.emplace_back(Point(a.x, a.y, a.z), Point(b.x, b.y, b.z), Point(c.x, c.y, c.z));
        triangleIndex.push_back(uint32_t(t));
    }
    if (triangles.empty()) throw Error("detail transfer: the input surface has no non-degenerate triangle");
    for (glm::dvec3& n : vertexNormal) {
        const double length = glm::length(n);
        if (length > 0.0) n /= length;
    }
    Tree tree(triangles.begin(), triangles.end());
    tree.build();
    tree.accelerate_distance_queries();  // built now: the queries below are const

    const size_t count = positions.texels.size();
    std::vector<double> moved(count, -1.0);  // per sample: distance moved, or -1 if kept
    const double limit2 = options.maxDistance > 0.0 ? options.maxDistance * options.maxDistance : INFINITY;
    auto query = [&](size_t begin, size_t end) {
        // Neighbouring samples have neighbouring closest points: the previous answer bounds the
        // search of the next one (CGAL's hint), far cheaper than the tree's own start.
        std::optional<Tree::Point_and_primitive_id> hint;
        for (size_t i = begin; i < end; ++i) {
            const glm::dvec3 p(positions.texels[i]);
            const Point query(p.x, p.y, p.z);
            const auto hit = hint ? tree.closest_point_and_primitive(query, *hint) : tree.closest_point_and_primitive(query);
            hint = hit;
            const glm::dvec3 q(hit.first.x(), hit.first.y(), hit.first.z());
            const double d2 = glm::dot(q - p, q - p);
            if (!(d2 <= limit2)) continue;
            const glm::uvec3 tri = input.triangles[triangleIndex[size_t(hit.second - triangles.begin())]];
            const glm::dvec3 w = barycentric(input.positions[tri.x], input.positions[tri.y], input.positions[tri.z], q);
            glm::dvec3 n = w.x * vertexNormal[tri.x] + w.y * vertexNormal[tri.y] + w.z * vertexNormal[tri.z];
            const double length = glm::length(n);
            if (!(length > 0.0)) continue;
            n /= length;
            if (glm::dot(n, glm::dvec3(normals.texels[i])) < options.minNormalCosine) continue;
            positions.texels[i] = glm::vec3(q);
            normals.texels[i] = glm::vec3(n);
            moved[i] = std::sqrt(d2);
        }
    };
    const size_t threads = std::clamp<size_t>(options.threads, 1, std::max<size_t>(1, count));
    std::vector<std::thread> workers;
    const size_t chunk = (count + threads - 1) / threads;
    for (size_t t = 1; t < threads; ++t)
        workers.emplace_back(query, std::min(count, t * chunk), std::min(count, (t + 1) * chunk));
    query(0, std::min(count, chunk));
    for (std::thread& w : workers) w.join();

    DetailTransferReport report;
    double sum = 0.0;
    for (double d : moved) {
        if (d < 0.0) {
            ++report.kept;
            continue;
        }
        ++report.projected;
        sum += d;
        report.maxDistance = std::max(report.maxDistance, d);
    }
    report.meanDistance = report.projected ? sum / double(report.projected) : 0.0;
    return report;
}

} // namespace ngi
