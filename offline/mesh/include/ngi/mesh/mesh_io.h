// ngi offline: reading and writing triangle meshes.
// Reads OBJ, OFF (ASCII and binary), PLY (ASCII and binary), STL (ASCII and binary) with
// our own readers, and glTF 2.0 .gltf/.glb (tinygltf: node transforms applied, all triangle
// primitives merged). Writes OBJ, OFF, PLY (ASCII, full double precision).
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

namespace ngi {

// Reads a mesh by its extension. Polygons become triangles: a fan where that fan faces the
// polygon's normal (convex ones), else CGAL's triangulation of the outline. STL corners at
// the same position become one vertex. Throws one ngi::Error whose message starts with the path and
// names the problem: missing file, unknown format, corrupt or truncated data (what the
// header declared against what the file holds, or the line), an index out of range, no
// triangles, a NaN/infinite coordinate or one beyond single precision (every later stage
// stores floats), out of memory. Counts a header declares are checked against the file's
// size before anything is allocated. glTF buffer files are read only from the mesh's
// directory or below it (data: URIs and the GLB BIN chunk always).
TriangleMesh readMesh(const std::filesystem::path& path);

// readMesh on bytes in memory: `format` is the extension (".obj", "ply", ...), `name` starts
// every message. glTF may then use only embedded buffers (data: URIs, GLB BIN chunk).
TriangleMesh readMeshFromMemory(std::span<const uint8_t> bytes, const std::string& format, const std::string& name);

// Writes a mesh by its extension, atomically. Throws ngi::Error on failure, and as
// checkMeshOutputFormat does for an extension it cannot write.
void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh);

// Throws ngi::Error naming `path` unless writeMesh can write its format, so that a tool can
// check its output path before the work: "PATH: the output path has no extension (expected
// .obj, .off or .ply)" or "PATH: cannot write mesh format '.EXT' (expected .obj, .off or .ply)".
void checkMeshOutputFormat(const std::filesystem::path& path);

} // namespace ngi
