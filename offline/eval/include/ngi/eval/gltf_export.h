// ngi offline eval: a textured triangle mesh written as glTF 2.0 (The Khronos Group, "glTF 2.0
// Specification": 3.7 geometry, 3.8 textures, images and samplers, 3.9 metallic-roughness
// materials, 4.4 the GLB container), so that the mesh ngi draws opens in Blender or any glTF
// viewer, and reads back through ngi's own reader (mesh_io.h) with the same texture
// coordinates and texels.
#pragma once

#include "ngi/mesh/appearance.h"
#include "ngi/mesh/triangle_mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <vector>

namespace ngi {

enum class GltfContainer {
    Binary,    // .glb: the JSON chunk and one BIN chunk holding every buffer view and image
    Embedded,  // .gltf: the JSON, its one buffer a base64 data: URI (images are buffer views in it)
};

// True when `path` ends in .glb or .gltf (any case): a path encodeGltf's writer takes.
bool isGltfPath(const std::filesystem::path& path);

// The bytes of a glTF 2.0 asset of `mesh` with `appearance` (as appearance.h defines it): one
// scene, one node without a transform, one mesh with one TRIANGLES primitive per material used
// (triangles in their order within each), vertices split where a vertex's corners differ in
// texture coordinate or colour. Attributes are 32-bit floats: POSITION (with min and max),
// NORMAL when `normals` is not empty (one per vertex of `mesh`, normalized here), TEXCOORD_0
// from cornerUVs, COLOR_0 (linear RGBA) from cornerColors; indices are 32-bit. Each material
// keeps its name, base colour factor and texture (with its sampler's wrap modes, linear
// filtering with mipmaps), metallic and roughness factors, emissive factor, alpha mode and
// cutoff and double-sidedness; every image a base colour texture uses is stored as an 8-bit
// RGBA PNG. Other textures (metallic-roughness, normal, occlusion, emissive) are not written,
// nor are images no base colour uses. Without materials the primitive has none (the glTF
// default material).
// Throws ngi::Error if the mesh has no triangles, an index is out of range, a coordinate,
// normal, uv or colour is not finite, an attribute array's size does not match the mesh,
// a base colour texture has a transform other than the identity (KHR_texture_transform is not
// written), or an image's texel count does not match its size.
std::vector<uint8_t> encodeGltf(const TriangleMesh& mesh, const MeshAppearance& appearance,
                                const std::vector<glm::dvec3>& normals, GltfContainer container);

// encodeGltf with the container its extension names (.glb Binary, .gltf Embedded), written
// atomically (writeFileAtomic, ngi/output_files.h). Throws what encodeGltf throws, prefixed
// with the path, and ngi::Error naming the path for another extension or a failed write.
void writeGltf(const std::filesystem::path& path, const TriangleMesh& mesh, const MeshAppearance& appearance,
               const std::vector<glm::dvec3>& normals);

}  // namespace ngi
