// ngi offline: the appearance of an input mesh (texture coordinates, vertex colours,
// materials and their decoded textures), as the readers find it. The bake carries it into
// each chart's attribute images (Gu, Gortler and Hoppe 2002, "Geometry images", section 6:
// colours and normals as more images over the same parameterization).
//
// Conventions shared by every reader:
//   - per-corner attributes are indexed t * 3 + k for corner k of TriangleMesh::triangles[t],
//     in the triangles' order as the reader returns them (before any cleaning);
//   - texture coordinates follow glTF: (0, 0) is the top-left texel of the image, v grows
//     downwards (an OBJ `vt` is read as (u, 1 - v));
//   - colours and colour factors are linear RGBA; 8-bit colours of PLY and OBJ are read as
//     sRGB and converted; texture texels stay as stored (base colour and emissive are sRGB
//     encoded, the rest linear, as glTF defines).
#pragma once

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace ngi {

// A decoded texture: 8-bit RGBA, row-major, top row first (grey and RGB are expanded; a
// missing alpha is 255).
struct TextureImage {
    std::string name;  // the file or glTF image it came from (messages)
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgba;  // width * height * 4
};

enum class TextureWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };

// One use of a texture by a material.
struct TextureRef {
    int32_t image = -1;  // index into MeshAppearance::images; -1: no texture
    TextureWrap wrapU = TextureWrap::Repeat, wrapV = TextureWrap::Repeat;
    // KHR_texture_transform (identity where absent): uv' = (transform * vec3(uv, 1)).xy.
    glm::dmat3 transform{1.0};
    bool present() const { return image >= 0; }
};

enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

// A PBR metallic-roughness material as glTF 2.0 defines it; OBJ's MTL maps onto it (Kd ->
// baseColorFactor, map_Kd -> baseColorTexture, d -> alpha, map_Bump/norm -> normalTexture).
struct Material {
    std::string name;
    glm::dvec4 baseColorFactor{1.0};
    TextureRef baseColorTexture;  // sRGB
    double metallicFactor = 1.0, roughnessFactor = 1.0;
    TextureRef metallicRoughnessTexture;  // G roughness, B metallic (linear)
    TextureRef normalTexture;             // tangent space, linear
    double normalScale = 1.0;
    TextureRef occlusionTexture;  // R (linear)
    double occlusionStrength = 1.0;
    glm::dvec3 emissiveFactor{0.0};
    TextureRef emissiveTexture;  // sRGB
    AlphaMode alphaMode = AlphaMode::Opaque;
    double alphaCutoff = 0.5;
    bool doubleSided = false;
};

// Everything about a mesh's look that its file holds. Each vector is either empty (the file
// has no such attribute) or complete (3 per triangle, or 1 per triangle for the material).
struct MeshAppearance {
    std::vector<glm::dvec2> cornerUVs;       // TEXCOORD_0 / vt, per corner
    std::vector<glm::vec4> cornerColors;     // COLOR_0 / PLY / OBJ vertex colours, per corner
    std::vector<uint32_t> triangleMaterial;  // per triangle: index into `materials`
    std::vector<Material> materials;         // a triangle without one uses the default Material
    std::vector<TextureImage> images;
    std::vector<std::string> warnings;  // each names the file (what was read but not used)

    // True when nothing here changes how the mesh looks from the default grey material.
    bool empty() const { return cornerUVs.empty() && cornerColors.empty() && materials.empty(); }
};

}  // namespace ngi
