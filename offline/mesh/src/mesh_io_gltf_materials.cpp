// ngi offline: glTF 2.0 materials into appearance.h's Material (glTF 2.0 spec, 3.9
// "Materials", 3.8 "Textures, images and samplers"; KHR_texture_transform).
#include "mesh_io_gltf_materials.h"

#include "texture_io.h"

#include <cmath>
#include <string>

namespace ngi::mesh_io {
namespace {

namespace gltf = ngi_tinygltf;

TextureWrap wrapMode(int mode)
{
    switch (mode) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::ClampToEdge;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::MirroredRepeat;
    default: return TextureWrap::Repeat;
    }
}

// RFC 4648 base64 (no line breaks); false on any other character or a bad length.
bool decodeBase64(std::string_view text, std::vector<uint8_t>& out)
{
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        if (c == '+') return 62;
        if (c == '/') return 63;
        return -1;
    };
    while (!text.empty() && text.back() == '=') text.remove_suffix(1);
    if (text.size() % 4 == 1) return false;
    out.clear();
    out.reserve(text.size() / 4 * 3 + 2);
    uint32_t bits = 0;
    int count = 0;
    for (char c : text) {
        const int v = value(c);
        if (v < 0) return false;
        bits = bits << 6 | uint32_t(v);
        if (++count == 4) {
            out.push_back(uint8_t(bits >> 16)), out.push_back(uint8_t(bits >> 8)), out.push_back(uint8_t(bits));
            bits = 0, count = 0;
        }
    }
    if (count == 2) out.push_back(uint8_t(bits >> 4));
    if (count == 3) out.push_back(uint8_t(bits >> 10)), out.push_back(uint8_t(bits >> 2));
    return true;
}

// "%20" -> ' ' (glTF URIs are percent-encoded); a malformed escape stays as written.
std::string percentDecode(const std::string& uri)
{
    std::string out;
    for (size_t i = 0; i < uri.size(); ++i) {
        auto hex = [](char c) {
            return c >= '0' && c <= '9' ? c - '0'
                : c >= 'a' && c <= 'f'  ? c - 'a' + 10
                : c >= 'A' && c <= 'F'  ? c - 'A' + 10
                                        : -1;
        };
        if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
            out += char(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

}  // namespace

GltfMaterials::GltfMaterials(const gltf::Model& model, const Input& input, MeshAppearance& appearance)
    : model_(model), input_(input), appearance_(appearance), materials_(model.materials.size(), -1),
      images_(model.images.size(), -1)
{}

uint32_t GltfMaterials::materialIndex(int material)
{
    if (material < 0) {
        if (defaultMaterial_ < 0) {
            defaultMaterial_ = int64_t(appearance_.materials.size());
            appearance_.materials.emplace_back().name = "default";
        }
        return uint32_t(defaultMaterial_);
    }
    if (size_t(material) >= model_.materials.size())
        fail(input_,
             "glTF material " + std::to_string(material) + " does not exist (the file has " +
                 std::to_string(model_.materials.size()) + " materials)");
    int64_t& slot = materials_[size_t(material)];
    if (slot < 0) {
        Material converted = convert(model_.materials[size_t(material)], material);
        slot = int64_t(appearance_.materials.size());
        appearance_.materials.push_back(std::move(converted));
    }
    return uint32_t(slot);
}

Material GltfMaterials::convert(const gltf::Material& source, int index)
{
    const std::string name = "glTF material " + std::to_string(index);
    auto finite = [&](double v, const char* what) {
        if (!std::isfinite(v)) fail(input_, name + " has a NaN or infinite " + what);
        return v;
    };
    Material m;
    m.name = source.name.empty() ? name : source.name;
    const gltf::PbrMetallicRoughness& pbr = source.pbrMetallicRoughness;
    if (pbr.baseColorFactor.size() == 4)
        for (int c = 0; c < 4; ++c) m.baseColorFactor[c] = finite(pbr.baseColorFactor[size_t(c)], "baseColorFactor");
    m.metallicFactor = finite(pbr.metallicFactor, "metallicFactor");
    m.roughnessFactor = finite(pbr.roughnessFactor, "roughnessFactor");
    m.baseColorTexture = texture(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                                 pbr.baseColorTexture.extensions, name + " baseColorTexture");
    m.metallicRoughnessTexture = texture(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                                         pbr.metallicRoughnessTexture.extensions, name + " metallicRoughnessTexture");
    m.normalTexture = texture(source.normalTexture.index, source.normalTexture.texCoord,
                              source.normalTexture.extensions, name + " normalTexture");
    m.normalScale = finite(source.normalTexture.scale, "normalTexture.scale");
    m.occlusionTexture = texture(source.occlusionTexture.index, source.occlusionTexture.texCoord,
                                 source.occlusionTexture.extensions, name + " occlusionTexture");
    m.occlusionStrength = finite(source.occlusionTexture.strength, "occlusionTexture.strength");
    if (source.emissiveFactor.size() == 3)
        for (int c = 0; c < 3; ++c) m.emissiveFactor[c] = finite(source.emissiveFactor[size_t(c)], "emissiveFactor");
    m.emissiveTexture = texture(source.emissiveTexture.index, source.emissiveTexture.texCoord,
                                source.emissiveTexture.extensions, name + " emissiveTexture");
    if (source.alphaMode == "MASK")
        m.alphaMode = AlphaMode::Mask;
    else if (source.alphaMode == "BLEND")
        m.alphaMode = AlphaMode::Blend;
    else if (source.alphaMode != "OPAQUE" && !source.alphaMode.empty())
        appearance_.warnings.push_back(input_.name + ": " + name + " has unknown alphaMode '" + source.alphaMode +
                                       "' (read as OPAQUE)");
    m.alphaCutoff = finite(source.alphaCutoff, "alphaCutoff");
    m.doubleSided = source.doubleSided;
    return m;
}

TextureRef GltfMaterials::texture(int textureIndex, int texCoord, const gltf::ExtensionMap& extensions,
                                  const std::string& role)
{
    TextureRef ref;
    if (textureIndex < 0) return ref;
    if (size_t(textureIndex) >= model_.textures.size())
        fail(input_,
             role + " refers to texture " + std::to_string(textureIndex) + ", which does not exist (the file has " +
                 std::to_string(model_.textures.size()) + " textures)");
    const gltf::Texture& texture = model_.textures[size_t(textureIndex)];
    if (texCoord != 0)
        appearance_.warnings.push_back(input_.name + ": " + role + " uses TEXCOORD_" + std::to_string(texCoord) +
                                       "; only TEXCOORD_0 is read");
    // The image: EXT_texture_webp's source where it has one, else the core source.
    int source = texture.source;
    auto webp = texture.extensions.find("EXT_texture_webp");
    if (webp != texture.extensions.end() && webp->second.Has("source") && webp->second.Get("source").IsInt())
        source = webp->second.Get("source").GetNumberAsInt();
    if (source < 0) {
        appearance_.warnings.push_back(
            input_.name + ": " + role + ": texture " + std::to_string(textureIndex) +
            " has no image ngi can decode (only PNG, JPEG and WebP are read): the texture is not used");
        return ref;
    }
    ref.image = image(source);
    if (texture.sampler >= 0) {
        if (size_t(texture.sampler) >= model_.samplers.size())
            fail(input_,
                 "glTF texture " + std::to_string(textureIndex) + " refers to sampler " +
                     std::to_string(texture.sampler) + ", which does not exist (the file has " +
                     std::to_string(model_.samplers.size()) + " samplers)");
        const gltf::Sampler& sampler = model_.samplers[size_t(texture.sampler)];
        ref.wrapU = wrapMode(sampler.wrapS);
        ref.wrapV = wrapMode(sampler.wrapT);
    }
    auto transform = extensions.find("KHR_texture_transform");
    if (transform != extensions.end()) {
        const gltf::Value& t = transform->second;
        auto number = [&](const gltf::Value& v, double fallback) {
            if (!v.IsNumber()) return fallback;
            const double x = v.GetNumberAsDouble();
            if (!std::isfinite(x)) fail(input_, role + " has a NaN or infinite KHR_texture_transform value");
            return x;
        };
        glm::dvec2 offset(0.0), scale(1.0);
        if (t.Has("offset") && t.Get("offset").IsArray() && t.Get("offset").ArrayLen() == 2)
            offset = {number(t.Get("offset").Get(0), 0.0), number(t.Get("offset").Get(1), 0.0)};
        if (t.Has("scale") && t.Get("scale").IsArray() && t.Get("scale").ArrayLen() == 2)
            scale = {number(t.Get("scale").Get(0), 1.0), number(t.Get("scale").Get(1), 1.0)};
        const double rotation = t.Has("rotation") ? number(t.Get("rotation"), 0.0) : 0.0;
        if (t.Has("texCoord"))
            appearance_.warnings.push_back(input_.name + ": " + role +
                                           ": KHR_texture_transform's texCoord is ignored (TEXCOORD_0 is read)");
        // translation * rotation * scale, the rotation as glTF viewers apply it and Khronos'
        // TextureTransformTest sample checks (its arrow points at the green marker):
        // u' = u cos r + v sin r, v' = v cos r - u sin r (glm is column-major).
        const double c = std::cos(rotation), s = std::sin(rotation);
        const glm::dmat3 translationMatrix(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, offset.x, offset.y, 1.0);
        const glm::dmat3 rotationMatrix(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0);
        const glm::dmat3 scaleMatrix(scale.x, 0.0, 0.0, 0.0, scale.y, 0.0, 0.0, 0.0, 1.0);
        ref.transform = translationMatrix * rotationMatrix * scaleMatrix;
    }
    return ref;
}

int32_t GltfMaterials::image(int imageIndex)
{
    if (size_t(imageIndex) >= model_.images.size())
        fail(input_,
             "a glTF texture refers to image " + std::to_string(imageIndex) + ", which does not exist (the file has " +
                 std::to_string(model_.images.size()) + " images)");
    int32_t& slot = images_[size_t(imageIndex)];
    if (slot >= 0) return slot;
    const gltf::Image& source = model_.images[size_t(imageIndex)];
    std::string name = "glTF image " + std::to_string(imageIndex);
    std::vector<uint8_t> fileBytes;
    std::span<const uint8_t> bytes;
    if (source.bufferView >= 0) {
        if (size_t(source.bufferView) >= model_.bufferViews.size())
            fail(input_,
                 name + " refers to buffer view " + std::to_string(source.bufferView) + ", which does not exist");
        const gltf::BufferView& view = model_.bufferViews[size_t(source.bufferView)];
        if (view.buffer < 0 || size_t(view.buffer) >= model_.buffers.size())
            fail(input_,
                 name + " uses buffer view " + std::to_string(source.bufferView) + " whose buffer does not exist");
        const std::vector<unsigned char>& buffer = model_.buffers[size_t(view.buffer)].data;
        if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
            fail(input_,
                 name + " uses buffer view " + std::to_string(source.bufferView) +
                     ", which reaches past the end of its buffer");
        bytes = std::span<const uint8_t>(buffer.data() + view.byteOffset, view.byteLength);
    } else if (source.uri.rfind("data:", 0) == 0) {  // a data: URI tinygltf does not know (image/webp)
        const size_t comma = source.uri.find(',');
        if (comma == std::string::npos || source.uri.substr(0, comma).find(";base64") == std::string::npos ||
            !decodeBase64(std::string_view(source.uri).substr(comma + 1), fileBytes))
            fail(input_, name + " has a data: URI that is not valid base64");
        bytes = fileBytes;
    } else if (!source.uri.empty()) {
        const std::filesystem::path path =
            referencedFile(input_, meshDirectory(input_), percentDecode(source.uri), "texture");
        fileBytes = readReferencedFile(input_, path, "texture");
        name = path.string();
        bytes = fileBytes;
    } else {
        bytes = source.image;  // a data: URI, decoded by tinygltf and kept as it was
        if (bytes.empty()) fail(input_, name + " has no data");
    }
    appearance_.images.push_back(decodeTexture(bytes, input_.name, name));
    slot = int32_t(appearance_.images.size() - 1);
    return slot;
}

}  // namespace ngi::mesh_io
