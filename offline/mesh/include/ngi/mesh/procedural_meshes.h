// ngi offline: small procedural meshes built in code, for tests (docs/DESIGN.md, "Data": unit
// tests use small procedural meshes). Every mesh is manifold, consistently oriented with
// counter-clockwise triangles seen from outside, with no duplicate vertices.
//
//   mesh                      genus  boundary loops  Euler characteristic V - E + F
//   makeSphere                0      0               2
//   makeTorus                 1      0               0
//   makeGenusSurface(g)       g      0               2 - 2g   (g = 2: a double torus)
//   makeOpenCylinder          0      2               0
//   makePlanePatch            0      1               1
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>

namespace ngi {

// Icosphere: the icosahedron subdivided `subdivisions` times (4x triangles each time),
// vertices projected onto the sphere of `radius` centred at the origin.
// subdivisions = 0: 12 vertices, 20 triangles; 3: 642 vertices, 1280 triangles.
TriangleMesh makeSphere(uint32_t subdivisions = 3, double radius = 1.0);

// Ring torus around the z axis: `majorSegments` around the axis, `minorSegments` around the
// tube (each >= 3), major radius `majorRadius` > tube radius `minorRadius` > 0.
TriangleMesh makeTorus(uint32_t majorSegments = 32, uint32_t minorSegments = 16, double majorRadius = 1.0,
                       double minorRadius = 0.35);

// A closed surface of genus `genus` >= 1: the boundary of a slab of (2 genus + 1) x 3 x 1 unit
// cubes with `genus` square holes through it (a "pretzel" plate; genus 2 is a double torus).
// Every square face of the cube surface is split into `faceSubdivisions`^2 quads (>= 1), each
// into two triangles. The slab spans [0, 2g+1] x [0, 3] x [0, 1].
TriangleMesh makeGenusSurface(uint32_t genus = 2, uint32_t faceSubdivisions = 3);

// Open cylinder (no caps) of `radius` around the z axis, z in [0, height]: `segments` around
// (>= 3) and `rings` along the axis (>= 1). Two boundary loops.
TriangleMesh makeOpenCylinder(uint32_t segments = 32, uint32_t rings = 8, double radius = 0.5, double height = 1.0);

// Square patch [0, size]^2 in the z = 0 plane split into `cells`^2 quads (two triangles each),
// facing +z; `bumpHeight` != 0 lifts it by a smooth bump bumpHeight * sin(pi x) sin(pi y)
// (x, y relative to size), keeping the border flat. One boundary loop.
TriangleMesh makePlanePatch(uint32_t cells = 16, double size = 1.0, double bumpHeight = 0.0);

// A body with two long thin arms: makeSphere(subdivisions) whose caps |x| > 0.5 are narrowed
// to 0.3 of their width and stretched 10x along x (arms ~5 long, ~1.6 around). Its one-chart
// conformal map shrinks the arms' ends by far more than e^8 (the bake's sign of thin parts).
TriangleMesh makeTwoArmedBody(uint32_t subdivisions = 4);

}  // namespace ngi
