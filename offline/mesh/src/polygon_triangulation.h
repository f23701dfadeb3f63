// ngi offline: triangles of the polygons a mesh file holds (private to ngi_mesh's readers).
//
// A fan from the first corner is right only for convex polygons: on a non-convex one (the
// L-shaped hexagons of CGAL's corner_poly.off) fan triangles leave the polygon and fold over
// each other, and the remesher then tears the surface. Every reader hands its polygons here;
// convex ones still get the fan (the triangles earlier versions read), the others CGAL's
// hole triangulation of the polygon's outline (Polygon_mesh_processing::
// triangulate_hole_polyline: a constrained Delaunay triangulation when the outline is nearly
// planar, else the minimum-area triangulation of Barequet & Sharir / Liepa 2003).
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>
#include <span>
#include <vector>

namespace ngi::mesh_io {

// Collects the faces of one file while it is read (the positions may come after the faces),
// then triangulates them once every position is known.
class PolygonTriangulator {
public:
    // With `trackCorners`, the triangulator also records where each triangle corner came
    // from (cornerSources()); the geometry-only readers leave it off and pay nothing.
    explicit PolygonTriangulator(bool trackCorners = false) : trackCorners_(trackCorners) {}

    // Triangles go straight into `mesh`; a polygon of n >= 4 corners gets n - 2 placeholder
    // triangles, filled in by finish() (so the triangles keep the file's face order). The
    // indices must already be checked against the vertex count the file declares; fewer than
    // 3 corners is an ngi::Error (the readers refuse such faces first, naming the line).
    void add(std::span<const uint32_t> polygon, TriangleMesh& mesh);

    // Fills in the triangles of every kept polygon (`mesh`'s positions must be complete and
    // finite: the readers check each coordinate as they read it), each oriented as the
    // polygon's corner order. A polygon is fan-triangulated when every fan
    // triangle faces the polygon's (Newell) normal, or when it has more than
    // kMaxOutlineCorners corners (bounds the cubic fallback's time on hostile files), two
    // corners at one point, or CGAL finds no triangulation of the outline (checked: each
    // outline edge once, every other edge twice); otherwise its outline is triangulated. The
    // cubic search, CGAL's last resort, runs on polygons of at most 256 corners and within a
    // budget per file.
    void finish(TriangleMesh& mesh);

    // After finish(), with trackCorners: for corner k of mesh.triangles[t], entry t * 3 + k is
    // the polygon corner it came from, counting every corner of every polygon passed to add()
    // from 0 in the order given (so a reader keeps per-corner attributes, an OBJ `vt` or
    // material, in that order and looks them up here). Covers the triangles added through
    // this triangulator, which must be all of `mesh`'s; add() throws ngi::Error past 2^32-1
    // corners.
    const std::vector<uint32_t>& cornerSources() const { return sources_; }

    static constexpr size_t kMaxOutlineCorners = 1024;

private:
    bool trackCorners_ = false;
    uint64_t cornerCount_ = 0;            // polygon corners passed to add() so far
    std::vector<uint32_t> sources_;       // with trackCorners_: 3 per triangle
    std::vector<uint32_t> firstCorners_;  // with trackCorners_: each kept polygon's first corner id
    std::vector<uint32_t> corners_;       // the kept polygons, back to back
    std::vector<size_t> starts_;          // where each begins in corners_
    std::vector<size_t> firstTriangles_;  // its first placeholder in mesh.triangles
};

}  // namespace ngi::mesh_io
