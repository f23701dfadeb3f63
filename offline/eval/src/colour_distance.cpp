// ngi offline eval: colour PSNR of Y, Cb, Cr between two textured surfaces (colour_distance.h),
// after the attribute metric of MPEG's point cloud compression common test conditions
// (pc_error: each point's colour against its nearest neighbour's, PSNR per channel on 8-bit
// BT.709 YCbCr), on surfaces: area-uniform reference samples against the closest point of the
// candidate's triangles (CGAL AABB tree), colours from SurfaceColor.
#include "ngi/eval/colour_distance.h"

#include "ngi/error.h"
#include "ngi/mesh/surface_color.h"
#include "surface_checks.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <thread>

namespace ngi {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

// `appearance` with each triangle's base colour texture transform applied to its corners'
// texture coordinates and every base colour transform then the identity (SurfaceColor reads
// the texel density from the untransformed coordinates).
MeshAppearance withBaseColourTransformsApplied(const MeshAppearance& appearance, size_t triangles)
{
    MeshAppearance out = appearance;
    if (out.cornerUVs.size() == triangles * 3 && !out.materials.empty())
        for (size_t t = 0; t < triangles; ++t) {
            const size_t m = out.triangleMaterial.empty() ? 0 : out.triangleMaterial[t];
            if (m >= out.materials.size()) continue;  // SurfaceColor reports it
            const glm::dmat3& transform = out.materials[m].baseColorTexture.transform;
            if (transform == glm::dmat3(1.0)) continue;
            for (size_t k = 0; k < 3; ++k) {
                glm::dvec2& uv = out.cornerUVs[t * 3 + k];
                uv = glm::dvec2(transform * glm::dvec3(uv, 1.0));
            }
        }
    for (Material& m : out.materials) m.baseColorTexture.transform = glm::dmat3(1.0);
    return out;
}

// The barycentric coordinates of `p` (a point of the triangle's plane, e.g. its closest point)
// in triangle (a, b, c), clamped to the triangle (Ericson 2005, 3.4).
glm::dvec3 barycentric(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c)
{
    const glm::dvec3 v0 = b - a, v1 = c - a, v2 = p - a;
    const double d00 = glm::dot(v0, v0), d01 = glm::dot(v0, v1), d11 = glm::dot(v1, v1);
    const double d20 = glm::dot(v2, v0), d21 = glm::dot(v2, v1);
    const double denominator = d00 * d11 - d01 * d01;
    if (!(denominator > 0.0)) return {1.0, 0.0, 0.0};
    glm::dvec3 w;
    w.y = (d11 * d20 - d01 * d21) / denominator;
    w.z = (d00 * d21 - d01 * d20) / denominator;
    w.x = 1.0 - w.y - w.z;
    w = glm::max(w, glm::dvec3(0.0));
    return w / (w.x + w.y + w.z);
}

// 8-bit sRGB of a linear colour (alpha dropped).
glm::dvec3 srgb8(const glm::dvec4& linear)
{
    return {std::round(255.0 * linearToSrgb(linear.r)), std::round(255.0 * linearToSrgb(linear.g)),
            std::round(255.0 * linearToSrgb(linear.b))};
}

double surfaceArea(const TriangleMesh& mesh)
{
    double area = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        area += 0.5 *
            glm::length(
                    glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
    return area;
}

}  // namespace

glm::dvec3 ycbcrBt709(const glm::dvec3& rgb)
{
    const double y = 0.2126 * rgb.r + 0.7152 * rgb.g + 0.0722 * rgb.b;
    return {y, (rgb.b - y) / 1.8556 + 128.0, (rgb.r - y) / 1.5748 + 128.0};
}

double psnr8(double mse)
{
    return mse > 0.0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : std::numeric_limits<double>::infinity();
}

ColourDistance colourDistance(const TriangleMesh& reference, const MeshAppearance& referenceAppearance,
                              const TriangleMesh& candidate, const MeshAppearance& candidateAppearance,
                              const ColourDistanceOptions& options)
{
    if (options.sampleCount == 0) throw Error("colour distance: sampleCount must be at least 1");
    detail::checkSurface(reference, "reference mesh");
    detail::checkSurface(candidate, "candidate mesh");
    const MeshAppearance referenceLook =
        withBaseColourTransformsApplied(referenceAppearance, reference.triangles.size());
    const MeshAppearance candidateLook =
        withBaseColourTransformsApplied(candidateAppearance, candidate.triangles.size());
    auto colours = [](const TriangleMesh& mesh, const MeshAppearance& look, const char* what) {
        try {
            return SurfaceColor(mesh, look);
        } catch (const Error& e) {
            throw Error(std::string(what) + ": " + e.what());
        }
    };
    const SurfaceColor referenceColour = colours(reference, referenceLook, "reference mesh");
    const SurfaceColor candidateColour = colours(candidate, candidateLook, "candidate mesh");

    std::vector<SurfaceSample> samples;
    try {
        samples = sampleSurfacePoints(reference, options.sampleCount, options.seed);
    } catch (const Error& e) {
        throw Error(std::string("reference ") + e.what());
    }
    const double footprint = std::sqrt(surfaceArea(reference) / double(options.sampleCount));

    // The candidate's proper triangles (CGAL's projection assumes them), with their indices.
    std::vector<Triangle> triangles;
    std::vector<uint32_t> triangleIndex;
    for (size_t t = 0; t < candidate.triangles.size(); ++t) {
        const glm::uvec3& tri = candidate.triangles[t];
        const glm::dvec3 a = candidate.positions[tri.x], b = candidate.positions[tri.y], c = candidate.positions[tri.z];
        if (glm::length(glm::cross(b - a, c - a)) == 0.0) continue;
        triangles.emplace_back(Point(a.x, a.y, a.z), Point(b.x, b.y, b.z), Point(c.x, c.y, c.z));
        triangleIndex.push_back(uint32_t(t));
    }
    if (triangles.empty()) throw Error("candidate mesh: its surface has zero area");
    Tree tree(triangles.begin(), triangles.end());
    tree.build();
    tree.accelerate_distance_queries();

    // Squared errors per sample, reduced in sample order: the result does not depend on threads.
    std::vector<glm::dvec3> squared(samples.size());
    auto measure = [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const SurfaceSample& s = samples[i];
            const Point p(s.position.x, s.position.y, s.position.z);
            const auto [closest, primitive] = tree.closest_point_and_primitive(p);
            const uint32_t t = triangleIndex[size_t(primitive - triangles.cbegin())];
            const glm::uvec3& tri = candidate.triangles[t];
            const glm::dvec3 q(closest.x(), closest.y(), closest.z());
            const glm::dvec3 w =
                barycentric(q, candidate.positions[tri.x], candidate.positions[tri.y], candidate.positions[tri.z]);
            const glm::dvec3 a = ycbcrBt709(srgb8(referenceColour.baseColor(s.triangle, s.barycentric, footprint)));
            const glm::dvec3 b = ycbcrBt709(srgb8(candidateColour.baseColor(t, w, footprint)));
            squared[i] = (a - b) * (a - b);
        }
    };
    const size_t threads = std::clamp<size_t>(options.threadCount, 1, samples.size());
    const size_t chunk = (samples.size() + threads - 1) / threads;
    std::vector<std::thread> workers;
    for (size_t t = 1; t < threads; ++t)
        workers.emplace_back(measure, std::min(samples.size(), t * chunk), std::min(samples.size(), (t + 1) * chunk));
    measure(0, std::min(samples.size(), chunk));
    for (std::thread& w : workers) w.join();

    glm::dvec3 sum(0.0);
    for (const glm::dvec3& e : squared) sum += e;
    const glm::dvec3 mse = sum / double(samples.size());
    ColourDistance result;
    result.mseY = mse.x, result.mseCb = mse.y, result.mseCr = mse.z;
    result.psnrY = psnr8(mse.x), result.psnrCb = psnr8(mse.y), result.psnrCr = psnr8(mse.z);
    result.footprint = footprint;
    result.sampleCount = options.sampleCount;
    return result;
}

}  // namespace ngi
