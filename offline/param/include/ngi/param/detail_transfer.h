// ngi offline: detail transfer from the input surface into a rasterized geometry image. The
// map is computed on an isotropic remesh (paper section 4: remesh, cut, OT); the samples are
// then moved to the closest point of the INPUT surface, as Gu, Gortler and Hoppe (2002,
// "Geometry images", section 5) sample the original mesh, and as remeshers project their
// vertices back onto the input (Botsch and Kobbelt 2004, "A remeshing approach to
// multiresolution modeling"). The remesh then only has to carry the map, not the detail, so it
// can be far coarser than the image (fewer optimal-transport sites: the bake's main cost).
#pragma once

#include "ngi/geometry_image.h"
#include "ngi/mesh/triangle_mesh.h"

#include <cstddef>
#include <span>
#include <vector>

namespace ngi {

struct DetailTransferOptions {
    // A sample moves only to a closest point within this distance (object units; <= 0: no
    // limit). The bake passes half the remesh's edge length: the remesh lies within its chord
    // error of the input, so a closer point further away than that is on another sheet.
    double maxDistance = 0.0;
    // ... and only where the input's normal there agrees with the remesh's normal of the
    // sample (cosine), so a thin part never takes its other side's position.
    double minNormalCosine = 0.5;
    unsigned threads = 2;
};

struct DetailTransferReport {
    size_t projected = 0;       // samples moved onto the input
    size_t kept = 0;            // samples left on the remesh (too far, or normals disagree)
    double maxDistance = 0.0;   // largest move applied (object units)
    double meanDistance = 0.0;  // mean move over the projected samples
};

// Moves every sample of `positions` (object space, as rasterized) to its closest point on
// `input`'s triangles and sets `normals` there to the input's area-weighted vertex normals
// interpolated on the closest triangle, subject to the options. `positions` and `normals`
// must have the same size. Throws ngi::Error if `input` has no non-degenerate triangle or the
// images differ in size.
DetailTransferReport transferDetail(const TriangleMesh& input, GeometryImage& positions, GeometryImage& normals,
                                    const DetailTransferOptions& options = {});

// Where a sample lies on the input: the triangle (index into TriangleMesh::triangles) and the
// barycentric coordinates of its closest point there.
struct SurfaceLocation {
    uint32_t triangle = 0;
    glm::dvec3 bary{1.0, 0.0, 0.0};
};

// The closest point of `input`'s non-degenerate triangles to every sample of `positions`
// (object space): the same search transferDetail moves the samples with, so for samples it
// moved (they lie on the input) this names the triangle they lie on. Where two triangles are
// equally close (a sample on an edge, or on two coincident sheets) the one whose face normal
// agrees better with the sample's normal in `normals` is taken. Deterministic for any thread
// count. Throws ngi::Error if `input` has no non-degenerate triangle or the images differ in size.
std::vector<SurfaceLocation> locateOnSurface(const TriangleMesh& input, const GeometryImage& positions,
                                             const GeometryImage& normals, unsigned threads = 2);

// Fraction of the area of `surface` whose triangles' centroids lie farther than `distance`
// from `input`. With a remesh as `surface` and its source as `input` it measures where the
// remesh cuts through a thin part; with the two swapped, the input's parts the remesh cut off
// (a spike's tip): what the transfer cannot repair. Throws ngi::Error if `input` has no
// non-degenerate triangle.
double areaFartherThan(const TriangleMesh& surface, const TriangleMesh& input, double distance, unsigned threads = 2);

// The squared distance of every point (object units) to the closest point of `input`'s
// non-degenerate triangles: what the Chamfer distance's candidate-to-reference term measures per
// sample (the rate control scores restores against the input with it). Deterministic for any
// thread count. Throws ngi::Error if `input` has no non-degenerate triangle.
std::vector<double> squaredDistancesToSurface(const TriangleMesh& input, std::span<const glm::dvec3> points,
                                              unsigned threads = 2);

}  // namespace ngi
