// ngi offline: Wavefront MTL material libraries, as the OBJ reader uses them (private).
// An MTL material maps onto a glTF metallic-roughness Material (appearance.h) the way
// Blender's and obj2gltf's importers map it: Kd -> baseColorFactor (linear, as written; 1
// when map_Kd is given), d (or 1 - Tr) -> its alpha and alphaMode Blend below 1, map_Kd ->
// baseColorTexture, map_Bump / bump / norm (-bm: normalScale) -> normalTexture, Ke ->
// emissiveFactor (1 when only map_Ke is given), map_Ke -> emissiveTexture, Pm / Pr ->
// metallic / roughness (else 0 and 1: an OBJ material is a dielectric). A texture's -clamp
// on sets clamp-to-edge wrapping; -o and -s become its transform in glTF's uv (v down).
#pragma once

#include "mesh_io_internal.h"

#include <filesystem>
#include <string>
#include <vector>

namespace ngi::mesh_io {

// A texture statement: the file as written, and the TextureRef it becomes (image unset).
struct MtlTexture {
    std::string file;  // empty: none
    TextureRef ref;
};

struct MtlMaterial {
    Material material;  // factors only: its TextureRefs' images are set by the OBJ reader
    MtlTexture baseColor, normal, emissive;
    bool hasDissolve = false, hasEmissiveFactor = false;  // d and Ke were given
};

// Parses one MTL file; `library` is its bytes and the name messages start with ("mesh.obj:
// material library /dir/a.mtl"). Statements ngi does not use (map_Ks, map_d, refl, ...) are
// warnings; numbers that are not numbers, or NaN, are errors naming the line.
std::vector<MtlMaterial> parseMtl(const Input& library, std::vector<std::string>& warnings);

}  // namespace ngi::mesh_io
