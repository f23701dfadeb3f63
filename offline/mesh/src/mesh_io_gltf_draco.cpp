// ngi offline: glTF primitives compressed with KHR_draco_mesh_compression, decoded with
// libdraco (see mesh_io_gltf_draco.h).
#include "mesh_io_gltf_draco.h"

#include <draco/compression/decode.h>
#include <draco/core/decoder_buffer.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <string>
#include <string_view>

namespace ngi::mesh_io {
namespace {

namespace gltf = ngi_tinygltf;

constexpr const char* kExtension = "KHR_draco_mesh_compression";

uint32_t readU32(const uint8_t* p)
{
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
}

void appendU32(std::vector<uint8_t>& out, uint32_t v)
{
    uint8_t b[4];
    std::memcpy(b, &v, 4);
    out.insert(out.end(), b, b + 4);
}

// Drops "indices" from every primitive of `json` that has the extension; false where none has.
bool dropDracoIndices(nlohmann::json& json)
{
    bool any = false;
    const auto meshes = json.find("meshes");
    if (meshes == json.end() || !meshes->is_array()) return false;
    for (nlohmann::json& mesh : *meshes) {
        if (!mesh.is_object()) continue;
        const auto primitives = mesh.find("primitives");
        if (primitives == mesh.end() || !primitives->is_array()) continue;
        for (nlohmann::json& primitive : *primitives) {
            if (!primitive.is_object()) continue;
            const auto extensions = primitive.find("extensions");
            if (extensions == primitive.end() || !extensions->is_object() || !extensions->contains(kExtension))
                continue;
            primitive.erase("indices");
            any = true;
        }
    }
    return any;
}

// The named attribute of the bitstream `mesh` (its unique id from the extension's
// "attributes"), read per point as `components` doubles; empty where the extension does not
// name it.
std::vector<glm::dvec4> pointValues(const draco::Mesh& mesh, const gltf::Value& attributes, const char* name,
                                    int minComponents, int maxComponents, const Input& input)
{
    if (!attributes.Has(name)) return {};
    const gltf::Value& id = attributes.Get(name);
    const std::string what = std::string("glTF ") + kExtension + " attribute " + name;
    if (!id.IsNumber()) fail(input, what + " is not an attribute id");
    const double number = id.GetNumberAsDouble();
    if (!(number >= 0.0 && number <= double(INT32_MAX)) || number != std::floor(number))
        fail(input, what + " is not an attribute id");
    const draco::PointAttribute* attribute = mesh.GetAttributeByUniqueId(uint32_t(number));
    if (!attribute) fail(input, what + " (id " + std::to_string(uint32_t(number)) + ") is not in the bitstream");
    const int components = attribute->num_components();
    if (components < minComponents || components > maxComponents)
        fail(input, what + " has " + std::to_string(components) + " components");
    std::vector<glm::dvec4> values(mesh.num_points(), glm::dvec4(0.0, 0.0, 0.0, 1.0));
    float v[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    for (uint32_t i = 0; i < mesh.num_points(); ++i) {
        const draco::AttributeValueIndex index = attribute->mapped_index(draco::PointIndex(i));
        if (index.value() >= attribute->size() || !attribute->ConvertValue<float>(index, int8_t(components), v))
            fail(input, what + ": point " + std::to_string(i) + " has no value");
        for (int c = 0; c < components; ++c) {
            if (!std::isfinite(v[c])) fail(input, what + ": point " + std::to_string(i) + " is NaN or infinite");
            values[i][c] = v[c];
        }
    }
    return values;
}

}  // namespace

std::optional<std::vector<uint8_t>> dracoParsable(std::span<const uint8_t> bytes, bool binary)
{
    if (std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()).find(kExtension) ==
        std::string_view::npos)
        return std::nullopt;
    if (!binary) {
        nlohmann::json json = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
        if (!json.is_object() || !dropDracoIndices(json)) return std::nullopt;
        const std::string text = json.dump();
        return std::vector<uint8_t>(text.begin(), text.end());
    }
    // GLB: a 12-byte header (magic, version, length), then chunks of (length, type, data);
    // the first is the JSON. The rest is copied as it is.
    if (bytes.size() < 20 || std::memcmp(bytes.data(), "glTF", 4) != 0) return std::nullopt;
    const uint32_t jsonLength = readU32(bytes.data() + 12);
    if (std::memcmp(bytes.data() + 16, "JSON", 4) != 0 || jsonLength > bytes.size() - 20) return std::nullopt;
    const std::span<const uint8_t> jsonBytes = bytes.subspan(20, jsonLength);
    nlohmann::json json = nlohmann::json::parse(jsonBytes.begin(), jsonBytes.end(), nullptr, false);
    if (!json.is_object() || !dropDracoIndices(json)) return std::nullopt;
    std::string text = json.dump();
    while (text.size() % 4) text.push_back(' ');  // chunks stay 4-byte aligned
    const std::span<const uint8_t> rest = bytes.subspan(20 + size_t(jsonLength));
    const size_t total = 20 + text.size() + rest.size();
    if (total > UINT32_MAX) return std::nullopt;
    std::vector<uint8_t> out(bytes.begin(), bytes.begin() + 8);  // magic and version
    out.reserve(total);
    appendU32(out, uint32_t(total));
    appendU32(out, uint32_t(text.size()));
    out.insert(out.end(), {'J', 'S', 'O', 'N'});
    out.insert(out.end(), text.begin(), text.end());
    out.insert(out.end(), rest.begin(), rest.end());
    return out;
}

DracoPrimitive decodeDracoPrimitive(const gltf::Model& model, const gltf::Value& extension, const Input& input,
                                    bool withAppearance)
{
    const std::string what = std::string("glTF ") + kExtension;
    if (!extension.IsObject()) fail(input, what + " is not an object");
    const gltf::Value& viewId = extension.Get("bufferView");
    if (!viewId.IsNumber()) fail(input, what + " has no bufferView");
    const double viewNumber = viewId.GetNumberAsDouble();
    if (!(viewNumber >= 0.0 && viewNumber < double(model.bufferViews.size())) || viewNumber != std::floor(viewNumber))
        fail(input,
             what + " names buffer view " + std::to_string(viewNumber) + ", which does not exist (the file has " +
                 std::to_string(model.bufferViews.size()) + ")");
    const gltf::BufferView& view = model.bufferViews[size_t(viewNumber)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
        fail(input, what + "'s buffer view uses buffer " + std::to_string(view.buffer) + ", which does not exist");
    const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
        fail(input,
             what + "'s buffer view (byteOffset " + std::to_string(view.byteOffset) + ", byteLength " +
                 std::to_string(view.byteLength) + ") reaches past the end of its buffer (" +
                 std::to_string(buffer.size()) + " bytes)");
    const gltf::Value& attributes = extension.Get("attributes");
    if (!attributes.IsObject() || !attributes.Has("POSITION")) fail(input, what + " has no POSITION attribute");

    draco::DecoderBuffer stream;
    stream.Init(reinterpret_cast<const char*>(buffer.data() + view.byteOffset), view.byteLength);
    const auto type = draco::Decoder::GetEncodedGeometryType(&stream);
    if (!type.ok() || type.value() != draco::TRIANGULAR_MESH)
        fail(input,
             what + ": the bitstream is not a Draco triangle mesh" +
                 (type.ok() ? std::string() : " (" + type.status().error_msg_string() + ")"));
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&stream);
    if (!decoded.ok())
        fail(input, what + ": the Draco bitstream does not decode: " + decoded.status().error_msg_string());
    const draco::Mesh& mesh = *decoded.value();

    DracoPrimitive out;
    for (const glm::dvec4& p : pointValues(mesh, attributes, "POSITION", 3, 3, input))
        out.positions.push_back(glm::dvec3(p));
    out.indices.reserve(size_t(mesh.num_faces()) * 3);
    for (uint32_t f = 0; f < mesh.num_faces(); ++f)
        for (const draco::PointIndex& p : mesh.face(draco::FaceIndex(f))) {
            if (p.value() >= out.positions.size())
                fail(input,
                     what + ": triangle " + std::to_string(f) + " refers to point " + std::to_string(p.value()) +
                         " of " + std::to_string(out.positions.size()));
            out.indices.push_back(p.value());
        }
    if (withAppearance) {
        out.uvs = pointValues(mesh, attributes, "TEXCOORD_0", 2, 2, input);
        out.colours = pointValues(mesh, attributes, "COLOR_0", 3, 4, input);
    }
    return out;
}

}  // namespace ngi::mesh_io
