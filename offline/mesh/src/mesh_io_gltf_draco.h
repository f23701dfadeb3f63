// ngi offline: glTF 2.0 primitives compressed with KHR_draco_mesh_compression (Khronos'
// extension: the primitive's geometry is one Draco bitstream in a buffer view, and its
// accessors have no buffer view of their own), decoded with Debian's libdraco.
//
// tinygltf (without its own Draco path, which indexes the file's arrays unchecked) refuses an
// indices accessor without a buffer view while parsing, so dracoParsable rewrites the JSON
// first: a Draco primitive's "indices" is dropped (its faces come from the bitstream).
// Everything the bitstream is read from is checked here as mesh_io_gltf.cpp checks accessors.
#pragma once

#include "mesh_io_internal.h"
#include "mesh_io_tinygltf.h"

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace ngi::mesh_io {

// The glTF file `bytes` (JSON, or a GLB container when `binary`) with the "indices" of every
// primitive that has KHR_draco_mesh_compression removed, so that tinygltf parses it; nullopt
// where the file does not name the extension or is not well-formed enough to rewrite (tinygltf
// then parses the original and reports what is wrong with it).
std::optional<std::vector<uint8_t>> dracoParsable(std::span<const uint8_t> bytes, bool binary);

// One primitive's geometry as the bitstream holds it: POSITION per point, three point indices
// per triangle (TRIANGLES order), and where `withAppearance`, TEXCOORD_0 and COLOR_0 per point
// (empty where the extension does not name them; colours RGBA, alpha 1 for RGB).
struct DracoPrimitive {
    std::vector<glm::dvec3> positions;
    std::vector<uint32_t> indices;
    std::vector<glm::dvec4> uvs, colours;
};

// Decodes the primitive's KHR_draco_mesh_compression `extension` (its "bufferView" and
// "attributes" ids). Throws ngi::Error naming the input where the buffer view is missing or
// out of its buffer, the bitstream does not decode to a triangle mesh, an attribute is missing
// or of the wrong size, a value is NaN or infinite, or an index is out of range.
DracoPrimitive decodeDracoPrimitive(const ngi_tinygltf::Model& model, const ngi_tinygltf::Value& extension,
                                    const Input& input, bool withAppearance);

}  // namespace ngi::mesh_io
