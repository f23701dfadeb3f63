// ngi offline eval: glTF 2.0 writing (gltf_export.h): the JSON by nlohmann::json, the GLB
// container and the base64 data: URI by hand, the images as PNG through libpng.
#include "ngi/eval/gltf_export.h"

#include "ngi/error.h"
#include "ngi/output_files.h"

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>
#include <png.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <csetjmp>
#include <cstring>
#include <map>
#include <string>

namespace ngi {
namespace {

using nlohmann::json;

constexpr int kFloat = 5126, kUnsignedInt = 5125;                 // accessor component types
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;  // buffer view targets
constexpr int kLinear = 9729, kLinearMipmapLinear = 9987;
constexpr uint32_t kUnused = UINT32_MAX;

// ------------------------------------------------------------------------------- PNG bytes

void pngError(png_structp png, png_const_charp message)
{
    *static_cast<std::string*>(png_get_error_ptr(png)) = message;
    png_longjmp(png, 1);
}
void pngWarning(png_structp, png_const_charp) {}
void pngWrite(png_structp png, png_bytep data, png_size_t n)
{
    auto* out = static_cast<std::vector<uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + n);
}
void pngFlush(png_structp) {}

// An 8-bit RGBA PNG of `image`, in memory.
std::vector<uint8_t> encodePng(const TextureImage& image)
{
    std::vector<uint8_t> out;
    std::string message;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &message, pngError, pngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    if (!png || !info) {
        png_destroy_write_struct(&png, &info);
        throw Error("image '" + image.name + "': out of memory for the PNG encoder");
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        throw Error("image '" + image.name + "': PNG encoding failed (" + message + ")");
    }
    png_set_write_fn(png, &out, pngWrite, pngFlush);
    png_set_IHDR(png, info, image.width, image.height, 8, PNG_COLOR_TYPE_RGBA, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 9);
    png_write_info(png, info);
    for (uint32_t y = 0; y < image.height; ++y) png_write_row(png, image.rgba.data() + size_t(y) * image.width * 4);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

// ------------------------------------------------------------------------------- the asset

bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void checkInputs(const TriangleMesh& mesh, const MeshAppearance& a, const std::vector<glm::dvec3>& normals)
{
    const size_t triangles = mesh.triangles.size(), vertices = mesh.positions.size();
    if (triangles == 0) throw Error("the mesh has no triangles");
    for (size_t t = 0; t < triangles; ++t)
        for (int k = 0; k < 3; ++k)
            if (mesh.triangles[t][k] >= vertices)
                throw Error("triangle " + std::to_string(t) + " uses vertex " + std::to_string(mesh.triangles[t][k]) +
                            " of " + std::to_string(vertices));
    for (const glm::dvec3& p : mesh.positions)
        if (!finite(p)) throw Error("a vertex position is not finite");
    if (!normals.empty() && normals.size() != vertices)
        throw Error(std::to_string(normals.size()) + " normals for " + std::to_string(vertices) + " vertices");
    for (const glm::dvec3& n : normals)
        if (!finite(n)) throw Error("a normal is not finite");
    if (!a.cornerUVs.empty() && a.cornerUVs.size() != triangles * 3)
        throw Error(std::to_string(a.cornerUVs.size()) + " texture coordinates for " + std::to_string(triangles) +
                    " triangles");
    for (const glm::dvec2& uv : a.cornerUVs)
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) throw Error("a texture coordinate is not finite");
    if (!a.cornerColors.empty() && a.cornerColors.size() != triangles * 3)
        throw Error(std::to_string(a.cornerColors.size()) + " vertex colours for " + std::to_string(triangles) +
                    " triangles");
    for (const glm::vec4& c : a.cornerColors)
        if (!std::isfinite(c.x) || !std::isfinite(c.y) || !std::isfinite(c.z) || !std::isfinite(c.w))
            throw Error("a vertex colour is not finite");
    if (!a.triangleMaterial.empty() && a.triangleMaterial.size() != triangles)
        throw Error(std::to_string(a.triangleMaterial.size()) + " material indices for " + std::to_string(triangles) +
                    " triangles");
    for (uint32_t m : a.triangleMaterial)
        if (m >= a.materials.size())
            throw Error("material index " + std::to_string(m) + " of " + std::to_string(a.materials.size()) +
                        " materials");
    for (const Material& m : a.materials) {
        const TextureRef& ref = m.baseColorTexture;
        if (!ref.present()) continue;
        if (size_t(ref.image) >= a.images.size())
            throw Error("material '" + m.name + "' uses image " + std::to_string(ref.image) + " of " +
                        std::to_string(a.images.size()));
        if (ref.transform != glm::dmat3(1.0))
            throw Error("material '" + m.name +
                        "': a base colour texture transform is not written (KHR_texture_transform)");
        const TextureImage& image = a.images[size_t(ref.image)];
        if (image.width == 0 || image.height == 0 || image.rgba.size() != size_t(image.width) * image.height * 4)
            throw Error("image '" + image.name + "' has " + std::to_string(image.rgba.size()) + " bytes for " +
                        std::to_string(image.width) + " x " + std::to_string(image.height) + " RGBA texels");
    }
}

int wrapCode(TextureWrap wrap)
{
    switch (wrap) {
    case TextureWrap::ClampToEdge: return 33071;
    case TextureWrap::MirroredRepeat: return 33648;
    case TextureWrap::Repeat:
    default: return 10497;
    }
}

// The one buffer and the JSON arrays that point into it.
struct Builder {
    std::vector<uint8_t> buffer;
    json bufferViews = json::array(), accessors = json::array();

    size_t view(const void* data, size_t bytes, int target)
    {
        while (buffer.size() % 4 != 0) buffer.push_back(0);
        const size_t offset = buffer.size();
        buffer.resize(offset + bytes);
        std::memcpy(buffer.data() + offset, data, bytes);
        json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
        if (target != 0) v["target"] = target;
        bufferViews.push_back(v);
        return bufferViews.size() - 1;
    }
    size_t accessor(const std::vector<float>& values, int components, const char* type, bool bounds)
    {
        json a = {{"bufferView", view(values.data(), values.size() * 4, kArrayBuffer)},
                  {"componentType", kFloat},
                  {"count", values.size() / size_t(components)},
                  {"type", type}};
        if (bounds) {
            std::vector<float> lo(size_t(components), INFINITY), hi(size_t(components), -INFINITY);
            for (size_t i = 0; i < values.size(); ++i) {
                lo[i % size_t(components)] = std::min(lo[i % size_t(components)], values[i]);
                hi[i % size_t(components)] = std::max(hi[i % size_t(components)], values[i]);
            }
            a["min"] = lo, a["max"] = hi;
        }
        accessors.push_back(a);
        return accessors.size() - 1;
    }
};

std::string base64(const std::vector<uint8_t>& bytes)
{
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const size_t n = std::min<size_t>(3, bytes.size() - i);
        uint32_t v = 0;
        for (size_t k = 0; k < 3; ++k) v = v << 8 | (k < n ? bytes[i + k] : 0u);
        for (size_t k = 0; k < 4; ++k) out += k <= n ? table[(v >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
}

void appendLittleEndian32(std::vector<uint8_t>& out, uint32_t v)
{
    for (int k = 0; k < 4; ++k) out.push_back(uint8_t(v >> (8 * k)));
}

}  // namespace

bool isGltfPath(const std::filesystem::path& path)
{
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    return ext == ".glb" || ext == ".gltf";
}

std::vector<uint8_t> encodeGltf(const TriangleMesh& mesh, const MeshAppearance& a,
                                const std::vector<glm::dvec3>& normals, GltfContainer container)
{
    checkInputs(mesh, a, normals);
    const size_t triangles = mesh.triangles.size();
    auto materialOf = [&](size_t t) -> uint32_t {
        if (a.materials.empty()) return kUnused;
        return a.triangleMaterial.empty() ? 0u : a.triangleMaterial[t];
    };
    // Materials in the order triangles first use them: one primitive each.
    std::vector<uint32_t> order;
    std::vector<std::vector<uint32_t>> groups;
    std::map<uint32_t, size_t> group;
    for (size_t t = 0; t < triangles; ++t) {
        auto [it, added] = group.try_emplace(materialOf(t), groups.size());
        if (added) order.push_back(materialOf(t)), groups.emplace_back();
        groups[it->second].push_back(uint32_t(t));
    }

    Builder b;
    json primitives = json::array();
    for (size_t g = 0; g < groups.size(); ++g) {
        // A vertex per distinct (vertex, uv, colour) of the group's corners.
        std::map<std::array<uint32_t, 7>, uint32_t> vertexOf;
        std::vector<float> positions, normalValues, uvs, colours;
        std::vector<uint32_t> indices;
        for (uint32_t t : groups[g])
            for (int k = 0; k < 3; ++k) {
                const size_t corner = size_t(t) * 3 + size_t(k);
                const uint32_t v = mesh.triangles[t][k];
                const glm::vec2 uv = a.cornerUVs.empty() ? glm::vec2(0.0f) : glm::vec2(a.cornerUVs[corner]);
                const glm::vec4 colour = a.cornerColors.empty() ? glm::vec4(0.0f) : a.cornerColors[corner];
                const std::array<uint32_t, 7> key = {v,
                                                     std::bit_cast<uint32_t>(uv.x),
                                                     std::bit_cast<uint32_t>(uv.y),
                                                     std::bit_cast<uint32_t>(colour.x),
                                                     std::bit_cast<uint32_t>(colour.y),
                                                     std::bit_cast<uint32_t>(colour.z),
                                                     std::bit_cast<uint32_t>(colour.w)};
                auto [it, added] = vertexOf.try_emplace(key, uint32_t(vertexOf.size()));
                indices.push_back(it->second);
                if (!added) continue;
                const glm::vec3 p(mesh.positions[v]);
                positions.insert(positions.end(), {p.x, p.y, p.z});
                if (!normals.empty()) {
                    const double length = glm::length(normals[v]);
                    const glm::vec3 n = length > 0.0 ? glm::vec3(normals[v] / length) : glm::vec3(0.0f, 0.0f, 1.0f);
                    normalValues.insert(normalValues.end(), {n.x, n.y, n.z});
                }
                if (!a.cornerUVs.empty()) uvs.insert(uvs.end(), {uv.x, uv.y});
                if (!a.cornerColors.empty()) colours.insert(colours.end(), {colour.x, colour.y, colour.z, colour.w});
            }
        json attributes = {{"POSITION", b.accessor(positions, 3, "VEC3", true)}};
        if (!normalValues.empty()) attributes["NORMAL"] = b.accessor(normalValues, 3, "VEC3", false);
        if (!uvs.empty()) attributes["TEXCOORD_0"] = b.accessor(uvs, 2, "VEC2", false);
        if (!colours.empty()) attributes["COLOR_0"] = b.accessor(colours, 4, "VEC4", false);
        b.accessors.push_back({{"bufferView", b.view(indices.data(), indices.size() * 4, kElementArrayBuffer)},
                               {"componentType", kUnsignedInt},
                               {"count", indices.size()},
                               {"type", "SCALAR"}});
        json primitive = {{"attributes", attributes}, {"indices", b.accessors.size() - 1}, {"mode", 4}};
        if (order[g] != kUnused) primitive["material"] = order[g];
        primitives.push_back(primitive);
    }

    // Materials, their base colour textures (one texture and sampler per use) and images.
    json materials = json::array(), textures = json::array(), samplers = json::array(), images = json::array();
    std::vector<size_t> imageIndex(a.images.size(), SIZE_MAX);
    for (const Material& m : a.materials) {
        json pbr = {
            {"baseColorFactor", {m.baseColorFactor.r, m.baseColorFactor.g, m.baseColorFactor.b, m.baseColorFactor.a}},
            {"metallicFactor", m.metallicFactor},
            {"roughnessFactor", m.roughnessFactor}};
        if (m.baseColorTexture.present() && !a.cornerUVs.empty()) {
            const size_t image = size_t(m.baseColorTexture.image);
            if (imageIndex[image] == SIZE_MAX) {
                const std::vector<uint8_t> png = encodePng(a.images[image]);
                imageIndex[image] = images.size();
                json entry = {{"bufferView", b.view(png.data(), png.size(), 0)}, {"mimeType", "image/png"}};
                if (!a.images[image].name.empty()) entry["name"] = a.images[image].name;
                images.push_back(entry);
            }
            samplers.push_back({{"magFilter", kLinear},
                                {"minFilter", kLinearMipmapLinear},
                                {"wrapS", wrapCode(m.baseColorTexture.wrapU)},
                                {"wrapT", wrapCode(m.baseColorTexture.wrapV)}});
            textures.push_back({{"sampler", samplers.size() - 1}, {"source", imageIndex[image]}});
            pbr["baseColorTexture"] = {{"index", textures.size() - 1}};
        }
        json material = {{"pbrMetallicRoughness", pbr}};
        if (!m.name.empty()) material["name"] = m.name;
        if (m.emissiveFactor != glm::dvec3(0.0))
            material["emissiveFactor"] = {m.emissiveFactor.r, m.emissiveFactor.g, m.emissiveFactor.b};
        if (m.alphaMode == AlphaMode::Mask) material["alphaMode"] = "MASK", material["alphaCutoff"] = m.alphaCutoff;
        if (m.alphaMode == AlphaMode::Blend) material["alphaMode"] = "BLEND";
        if (m.doubleSided) material["doubleSided"] = true;
        materials.push_back(material);
    }

    json document = {{"asset", {{"version", "2.0"}, {"generator", "ngi-eval"}}},
                     {"scene", 0},
                     {"scenes", {{{"nodes", {0}}}}},
                     {"nodes", {{{"mesh", 0}}}},
                     {"meshes", {{{"primitives", primitives}}}},
                     {"accessors", b.accessors},
                     {"bufferViews", b.bufferViews}};
    if (!materials.empty()) document["materials"] = materials;
    if (!textures.empty())
        document["textures"] = textures, document["samplers"] = samplers, document["images"] = images;
    while (b.buffer.size() % 4 != 0) b.buffer.push_back(0);
    json buffer = {{"byteLength", b.buffer.size()}};
    if (container == GltfContainer::Embedded) {
        buffer["uri"] = "data:application/octet-stream;base64," + base64(b.buffer);
        document["buffers"] = {buffer};
        const std::string text = document.dump(1) + "\n";
        return std::vector<uint8_t>(text.begin(), text.end());
    }
    document["buffers"] = {buffer};
    std::string text = document.dump();
    while (text.size() % 4 != 0) text += ' ';  // the JSON chunk is padded with spaces
    std::vector<uint8_t> out;
    appendLittleEndian32(out, 0x46546C67u);  // "glTF"
    appendLittleEndian32(out, 2);
    appendLittleEndian32(out, uint32_t(12 + 8 + text.size() + 8 + b.buffer.size()));
    appendLittleEndian32(out, uint32_t(text.size()));
    appendLittleEndian32(out, 0x4E4F534Au);  // "JSON"
    out.insert(out.end(), text.begin(), text.end());
    appendLittleEndian32(out, uint32_t(b.buffer.size()));
    appendLittleEndian32(out, 0x004E4942u);  // "BIN\0"
    out.insert(out.end(), b.buffer.begin(), b.buffer.end());
    return out;
}

void writeGltf(const std::filesystem::path& path, const TriangleMesh& mesh, const MeshAppearance& appearance,
               const std::vector<glm::dvec3>& normals)
{
    if (!isGltfPath(path)) throw Error(path.string() + ": not a glTF path (expected .glb or .gltf)");
    std::string ext = path.extension().string();
    for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
    std::vector<uint8_t> bytes;
    try {
        bytes = encodeGltf(mesh, appearance, normals, ext == ".glb" ? GltfContainer::Binary : GltfContainer::Embedded);
    } catch (const Error& e) {
        throw Error(path.string() + ": " + e.what());
    }
    writeFileAtomic(path, bytes);
}

}  // namespace ngi
