// ngi offline eval (private): input checks shared by sampling and distance queries.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <string>

namespace ngi::detail {

// Throws ngi::Error "WHAT: problem" if `mesh` has no triangles, an index out of range or a
// non-finite coordinate on a vertex used by a triangle.
void checkSurface(const TriangleMesh& mesh, const std::string& what);

}  // namespace ngi::detail
