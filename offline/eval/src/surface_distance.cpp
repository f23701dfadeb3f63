// ngi offline eval: point-to-surface Chamfer and Hausdorff distances, docs/DESIGN.md "Metrics".
// CD = mean_a d(a,B)^2 + mean_b d(b,A)^2, HD = max of the one-sided maxima, both meshes in
// the reference's frame, d = exact distance to the closest point on the other mesh's
// triangles via a CGAL AABB tree. The only CGAL translation unit of ngi_eval.
#include "ngi/eval/surface_distance.h"

#include "ngi/error.h"
#include "surface_checks.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <thread>

namespace ngi {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point = Kernel::Point_3;
using Triangle = Kernel::Triangle_3;
using TriangleIterator = std::vector<Triangle>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<Kernel, TriangleIterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

TriangleMesh toFrame(const TriangleMesh& mesh, const ReferenceFrame& frame)
{
    TriangleMesh out;
    out.triangles = mesh.triangles;
    out.positions.reserve(mesh.positions.size());
    for (const glm::dvec3& p : mesh.positions) out.positions.push_back((p - frame.centre) * frame.scale);
    return out;
}

// The non-degenerate triangles of `mesh` (a zero-area triangle is a segment or a point: it
// holds no area, and CGAL's point-triangle projection assumes a proper triangle).
std::vector<Triangle> surfaceTriangles(const TriangleMesh& mesh)
{
    std::vector<Triangle> triangles;
    triangles.reserve(mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles) {
        const glm::dvec3 a = mesh.positions[t.x], b = mesh.positions[t.y], c = mesh.positions[t.z];
        if (glm::length(glm::cross(b - a, c - a)) == 0.0) continue;
        triangles.emplace_back(Point(a.x, a.y, a.z), Point(b.x, b.y, b.z), Point(c.x, c.y, c.z));
    }
    return triangles;
}

struct OneSided {
    double meanSquared = 0.0;
    double max = 0.0;
    double p99 = 0.0;
    size_t farthest = 0;  // index of the sample at `max`
};

// Distances from `samples` to the surface made of `triangles`, on `threadCount` threads.
// Distances are stored per sample and reduced in sample order: the result does not depend
// on the number of threads.
OneSided oneSidedDistance(const std::vector<glm::dvec3>& samples, const std::vector<Triangle>& triangles,
                          unsigned threadCount)
{
    Tree tree(triangles.begin(), triangles.end());
    tree.build();
    tree.accelerate_distance_queries();  // build the kd-tree now: queries below are then const

    std::vector<double> squared(samples.size());
    auto query = [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            const Point p(samples[i].x, samples[i].y, samples[i].z);
            squared[i] = CGAL::squared_distance(p, tree.closest_point(p));
        }
    };
    const size_t threads = std::clamp<size_t>(threadCount, 1, std::max<size_t>(1, samples.size()));
    std::vector<std::thread> workers;
    const size_t chunk = (samples.size() + threads - 1) / threads;
    for (size_t t = 1; t < threads; ++t)
        workers.emplace_back(query, std::min(samples.size(), t * chunk), std::min(samples.size(), (t + 1) * chunk));
    query(0, std::min(samples.size(), chunk));
    for (std::thread& w : workers) w.join();

    OneSided result;
    double sum = 0.0, maxSquared = 0.0;
    for (size_t i = 0; i < squared.size(); ++i) {
        sum += squared[i];
        if (squared[i] > maxSquared) {
            maxSquared = squared[i];
            result.farthest = i;
        }
    }
    result.meanSquared = sum / double(squared.size());
    result.max = std::sqrt(maxSquared);
    // The 99th percentile tells one far spot (HD >> p99) from a far region (HD ~ p99).
    const size_t rank = std::min(squared.size() - 1, size_t(0.99 * double(squared.size())));
    std::nth_element(squared.begin(), squared.begin() + ptrdiff_t(rank), squared.end());
    result.p99 = std::sqrt(squared[rank]);
    return result;
}

}  // namespace

SurfaceDistance surfaceDistance(const TriangleMesh& reference, const TriangleMesh& candidate,
                                const SurfaceDistanceOptions& options)
{
    if (options.sampleCount == 0) throw Error("surface distance: sampleCount must be at least 1");
    detail::checkSurface(reference, "reference mesh");
    detail::checkSurface(candidate, "candidate mesh");
    const ReferenceFrame frame = referenceFrame(reference);
    const TriangleMesh a = toFrame(reference, frame);
    const TriangleMesh b = toFrame(candidate, frame);

    std::vector<glm::dvec3> samplesA, samplesB;
    try {
        samplesA = sampleSurface(a, options.sampleCount, options.seed);
    } catch (const Error& e) {
        throw Error(std::string("reference ") + e.what());
    }
    try {
        samplesB = sampleSurface(b, options.sampleCount, options.seed);
    } catch (const Error& e) {
        throw Error(std::string("candidate ") + e.what());
    }

    const OneSided ab = oneSidedDistance(samplesA, surfaceTriangles(b), options.threadCount);
    const OneSided ba = oneSidedDistance(samplesB, surfaceTriangles(a), options.threadCount);

    SurfaceDistance result;
    result.meanSquaredReferenceToCandidate = ab.meanSquared;
    result.maxReferenceToCandidate = ab.max;
    result.meanSquaredCandidateToReference = ba.meanSquared;
    result.maxCandidateToReference = ba.max;
    result.p99ReferenceToCandidate = ab.p99;
    result.p99CandidateToReference = ba.p99;
    result.farthestReferenceSample = samplesA[ab.farthest] / frame.scale + frame.centre;
    result.farthestCandidateSample = samplesB[ba.farthest] / frame.scale + frame.centre;
    result.chamfer = ab.meanSquared + ba.meanSquared;
    result.hausdorff = std::max(ab.max, ba.max);
    result.frame = frame;
    result.sampleCount = options.sampleCount;
    return result;
}

double chamferDistance(const TriangleMesh& reference, const TriangleMesh& candidate,
                       const SurfaceDistanceOptions& options)
{
    return surfaceDistance(reference, candidate, options).chamfer;
}

double hausdorffDistance(const TriangleMesh& reference, const TriangleMesh& candidate,
                         const SurfaceDistanceOptions& options)
{
    return surfaceDistance(reference, candidate, options).hausdorff;
}

}  // namespace ngi
