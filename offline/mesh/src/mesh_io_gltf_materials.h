// ngi offline: glTF 2.0 materials, textures, samplers and images into a MeshAppearance
// (private to the glTF reader).
#pragma once

#include "mesh_io_internal.h"
#include "mesh_io_tinygltf.h"

#include <cstdint>
#include <vector>

namespace ngi::mesh_io {

// Converts the model's materials on first use, so that only the images a used material
// names are read and decoded. The model must come from the glTF reader: an image from a
// data: URI holds its undecoded bytes in Image::image, as the reader's image callback keeps
// them.
class GltfMaterials {
public:
    GltfMaterials(const ngi_tinygltf::Model& model, const Input& input, MeshAppearance& appearance);

    // The index in appearance.materials of glTF material `material` (-1: glTF's default
    // material), converted with its textures on first use. Throws one ngi::Error naming the
    // input for a material, texture, sampler or image index out of range, a non-finite
    // factor, or an image that cannot be read or decoded (texture_io.h).
    uint32_t materialIndex(int material);

private:
    Material convert(const ngi_tinygltf::Material& source, int index);
    TextureRef texture(int textureIndex, int texCoord, const ngi_tinygltf::ExtensionMap& extensions,
                       const std::string& role);
    int32_t image(int imageIndex);

    const ngi_tinygltf::Model& model_;
    const Input& input_;
    MeshAppearance& appearance_;
    std::vector<int64_t> materials_;  // glTF material -> appearance.materials, -1 until used
    int64_t defaultMaterial_ = -1;
    std::vector<int32_t> images_;  // glTF image -> appearance.images, -1 until used
};

}  // namespace ngi::mesh_io
