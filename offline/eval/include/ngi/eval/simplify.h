// ngi offline eval, peers: QSlim-style simplification (Garland & Heckbert 1997, "Surface
// Simplification Using Quadric Error Metrics", the paper's QSlim baseline), by
// meshoptimizer's meshopt_simplify (edge collapses ordered by quadric error, topology kept).
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>

namespace ngi {

struct SimplifyOptions {
    uint32_t targetTriangleCount = 0;  // stop at or below this many triangles, if reachable
    float maxRelativeError = 1.0f;     // stop before a collapse moves the surface more than this
                                       // fraction of the mesh extent (1 = no limit)
    bool lockBorder = false;           // keep the vertices of open boundaries in place
};

struct SimplifyResult {
    TriangleMesh mesh;           // kept vertices only (original double positions), compacted
    double relativeError = 0.0;  // meshoptimizer's error estimate, relative to the mesh extent
    bool reachedTarget = false;  // false: topology or maxRelativeError stopped it short
};

// Simplifies `mesh` by quadric-error edge collapses down to options.targetTriangleCount.
// Collapses keep one endpoint, so every output vertex is an input vertex (bitwise); the
// triangles keep their orientation. The simplifier can stop short of the target (it does
// not change topology): see reachedTarget. For tiny targets on closed meshes it may also
// collapse everything and return an empty mesh. Unused vertices are dropped. Throws ngi::Error
// on an index out of range, a non-finite coordinate or an empty mesh.
SimplifyResult simplifyMesh(const TriangleMesh& mesh, const SimplifyOptions& options);

}  // namespace ngi
