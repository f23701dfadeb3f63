// ngi offline: Chamfer and Hausdorff distance between two triangle surfaces, exactly as
// docs/DESIGN.md "Metrics" fixes them (the numbers every report and table of ngi is built on):
//
//   Frame      both meshes are translated by minus the reference's bounding-box centre and
//              scaled by 1 / (the reference's longest bounding-box side).
//   Sampling   `sampleCount` points per surface (default 200,000), uniform by area, fixed seed.
//   Distance   point-to-SURFACE: d(a, B) = distance from a to the closest point on B's
//              triangles (CGAL AABB tree), and the same from B's samples to A.
//   CD         mean_a d(a,B)^2 + mean_b d(b,A)^2          (reported x1e-4)
//   HD         max( max_a d(a,B), max_b d(b,A) )          (reported x1e-2)
//
// The paper (reference/paper.tex) reports CD x1e-4 and HD x1e-2 in Tables 1-4.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace ngi {

inline constexpr double kChamferReportScale = 1e4;    // report CD x1e-4: multiply by this
inline constexpr double kHausdorffReportScale = 1e2;  // report HD x1e-2: multiply by this

struct SurfaceDistanceOptions {
    uint32_t sampleCount = 200000;          // points per surface (docs/DESIGN.md: 200,000)
    uint64_t seed = 0x6e67692d6576616cull;  // fixed; both surfaces are sampled with this seed
    unsigned threadCount = 2;               // closest-point queries run on this many threads
};

// The normalization frame of docs/DESIGN.md: normalized = (p - centre) * scale.
struct ReferenceFrame {
    glm::dvec3 centre{0.0};  // the reference's bounding-box centre
    double scale = 1.0;      // 1 / the reference's longest bounding-box side
};

// Distances are in the normalized frame (the reference's longest bbox side = 1).
struct SurfaceDistance {
    double chamfer = 0.0;    // CD = meanSquaredReferenceToCandidate + meanSquaredCandidateToReference
    double hausdorff = 0.0;  // HD = max(maxReferenceToCandidate, maxCandidateToReference)
    double meanSquaredReferenceToCandidate = 0.0;  // mean over reference samples of d(a, B)^2
    double meanSquaredCandidateToReference = 0.0;  // mean over candidate samples of d(b, A)^2
    double maxReferenceToCandidate = 0.0;          // max over reference samples of d(a, B)
    double maxCandidateToReference = 0.0;          // max over candidate samples of d(b, A)
    double p99ReferenceToCandidate = 0.0;          // 99th percentile of d(a, B) over the samples
    double p99CandidateToReference = 0.0;          // 99th percentile of d(b, A)
    // Where the one-sided maxima are: the sample, in the REFERENCE's original coordinates (not
    // normalized), so a user can find the spot that sets HD in their own modelling tool.
    glm::dvec3 farthestReferenceSample{0.0};
    glm::dvec3 farthestCandidateSample{0.0};
    ReferenceFrame frame;      // the frame used (from the reference)
    uint32_t sampleCount = 0;  // per surface
};

// The docs/DESIGN.md frame of `reference`. Throws ngi::Error if the mesh has no vertices used by
// a triangle, a non-finite coordinate, or a zero-size bounding box.
ReferenceFrame referenceFrame(const TriangleMesh& reference);

// `count` points uniformly distributed by area on the triangles of `mesh`, drawn from a
// std::mt19937_64 seeded with `seed` (identical output on every platform: the conversion to
// [0,1) and the triangle choice are written out, not left to <random>'s distributions).
// Zero-area triangles receive no samples. Throws ngi::Error if an index is out of range, a
// coordinate is not finite, or the total area is zero.
std::vector<glm::dvec3> sampleSurface(const TriangleMesh& mesh, uint32_t count, uint64_t seed);

// One point of sampleSurfacePoints: where it lies on the mesh as well as its position.
struct SurfaceSample {
    glm::dvec3 position{0.0};
    uint32_t triangle = 0;        // index into mesh.triangles
    glm::dvec3 barycentric{0.0};  // weights of the triangle's corners x, y, z (sum 1)
};

// sampleSurface's points (the same positions for the same mesh, count and seed) with the
// triangle and barycentric coordinates of each, so that attributes can be read there.
// Same errors as sampleSurface.
std::vector<SurfaceSample> sampleSurfacePoints(const TriangleMesh& mesh, uint32_t count, uint64_t seed);

// CD, HD and their one-sided parts between `reference` (A) and `candidate` (B), both in the
// reference's frame. Deterministic for given options, whatever the thread count. Triangles
// of zero area are left out of the AABB trees (they hold no area, and CGAL's point-triangle
// distance is not defined for them). Throws ngi::Error (naming "reference mesh" or
// "candidate mesh") on empty meshes, out-of-range indices, non-finite coordinates, zero
// total area, a zero-size reference bounding box, or sampleCount == 0.
SurfaceDistance surfaceDistance(const TriangleMesh& reference, const TriangleMesh& candidate,
                                const SurfaceDistanceOptions& options = {});

// Chamfer distance CD of docs/DESIGN.md (normalized frame; multiply by kChamferReportScale to
// report it x1e-4). Same contract as surfaceDistance, of which it is the `chamfer` field.
double chamferDistance(const TriangleMesh& reference, const TriangleMesh& candidate,
                       const SurfaceDistanceOptions& options = {});

// Hausdorff distance HD of docs/DESIGN.md (normalized frame; multiply by kHausdorffReportScale to
// report it x1e-2). Same contract as surfaceDistance, of which it is the `hausdorff` field.
double hausdorffDistance(const TriangleMesh& reference, const TriangleMesh& candidate,
                         const SurfaceDistanceOptions& options = {});

}  // namespace ngi
