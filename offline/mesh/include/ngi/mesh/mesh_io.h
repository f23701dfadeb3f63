// ngi offline: reading and writing triangle meshes.
// Reads OBJ, OFF (ASCII and binary), PLY (ASCII and binary), STL (ASCII and binary) with
// our own readers, and glTF 2.0 .gltf/.glb (tinygltf: node transforms applied, all triangle
// primitives merged, KHR_draco_mesh_compression decoded with libdraco), with or without their appearance (appearance.h: UVs, colours,
// materials, decoded textures). Writes OBJ, OFF, PLY (ASCII, full double precision).
#pragma once

#include "ngi/mesh/appearance.h"
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

// readMesh, and the mesh's appearance into `appearance` (replaced), as appearance.h defines
// it: per-corner arrays follow the returned triangles (polygons' triangles take their
// corners' attributes), and every texture a used material names is decoded.
//   - glTF: TEXCOORD_0, COLOR_0, the pbrMetallicRoughness materials with their textures,
//     samplers' wrap modes and KHR_texture_transform. Images: the GLB BIN chunk, data: URIs,
//     files in the mesh's directory or below.
//   - OBJ: vt, vertex colours (v x y z r g b, sRGB), mtllib/usemtl with MTL files and their
//     textures in the mesh's directory or below (Kd, d/Tr, map_Kd, map_Bump/bump/norm,
//     Ke/map_Ke, Pm/Pr).
//   - PLY: vertex colours (red/green/blue[/alpha], diffuse_*; 8-bit and float are sRGB).
//   - OFF, STL: none (the appearance stays empty).
// Textures are PNG, JPEG or WebP of at most 16384 pixels a side and 2^28 pixels (checked
// from the header before decoding). Throws what readMesh throws, and one ngi::Error starting
// with the path for: a material library or texture that is missing, unreadable, outside the
// mesh's directory, corrupt, truncated, too large or of another format; a UV or colour that
// is NaN or infinite; a glTF material, texture, image or sampler index out of range. What
// is read but not used (an unknown usemtl name, a texCoord other than 0, a material's
// unsupported map) is a warning in appearance.warnings, each naming the file.
TriangleMesh readMesh(const std::filesystem::path& path, MeshAppearance& appearance);

// readMesh(path, appearance) on bytes in memory (as readMeshFromMemory): glTF images must
// be embedded; an OBJ's mtllib is not read (a warning says so).
TriangleMesh readMeshFromMemory(std::span<const uint8_t> bytes, const std::string& format, const std::string& name,
                                MeshAppearance& appearance);

// Writes a mesh by its extension, atomically. Throws ngi::Error on failure, and as
// checkMeshOutputFormat does for an extension it cannot write.
void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh);

// Throws ngi::Error naming `path` unless writeMesh can write its format, so that a tool can
// check its output path before the work: "PATH: the output path has no extension (expected
// .obj, .off or .ply)" or "PATH: cannot write mesh format '.EXT' (expected .obj, .off or .ply)".
void checkMeshOutputFormat(const std::filesystem::path& path);

}  // namespace ngi
