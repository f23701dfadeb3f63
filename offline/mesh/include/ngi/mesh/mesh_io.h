// ngi offline: reading and writing triangle meshes.
// Reads OBJ, OFF, PLY, STL (OpenMesh; ASCII OFF by our own reader, which accepts the # comments
// of CGAL's data) and glTF 2.0 .gltf/.glb (tinygltf: node transforms
// applied, all triangle primitives merged). Writes OBJ, OFF, PLY (ASCII, full double precision).
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <filesystem>

namespace ngi {

// Reads a mesh by its extension. Polygons are fan-triangulated. Throws ngi::Error naming the
// file and the problem (missing, unknown format, corrupt, no triangles, NaN/Inf coordinates).
TriangleMesh readMesh(const std::filesystem::path& path);

// Writes a mesh by its extension, atomically. Throws ngi::Error on failure.
void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh);

} // namespace ngi
