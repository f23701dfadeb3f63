// ngi offline: the glTF 2.0 reader (.gltf and .glb, through tinygltf).
//
// Node transforms are applied and every triangle primitive (TRIANGLES, TRIANGLE_STRIP,
// TRIANGLE_FAN) of the default scene is merged into one mesh; points and lines are skipped.
// A file without scenes reads every root node, and one without nodes every mesh. With
// appearance, TEXCOORD_0 and COLOR_0 become per-corner arrays (float or normalized
// integers) and the primitives' materials are converted (mesh_io_gltf_materials.h).
// Primitives compressed with KHR_draco_mesh_compression are decoded (mesh_io_gltf_draco.h).
// tinygltf parses the JSON and the buffers; everything it hands back is checked here before
// it is used: every index into the model's arrays, and every accessor against its buffer
// view and buffer with overflow-safe arithmetic (a count of 2^60 must not wrap a product).
// Buffer files are read only from the mesh's own directory or below it; data: URIs and the
// GLB BIN chunk are always allowed.
#include "mesh_io_gltf_draco.h"
#include "mesh_io_gltf_materials.h"
#include "mesh_io_internal.h"
#include "mesh_io_tinygltf.h"

#include "ngi/asset.h"
#include "ngi/error.h"

#include <nlohmann/json.hpp>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <system_error>
#include <vector>

namespace ngi::mesh_io {
namespace {

namespace gltf = ngi_tinygltf;

// ---------------------------------------------------------------- file access for tinygltf

// What tinygltf may open: regular files inside `directory` (lexically: no "..", no absolute
// path that leads elsewhere). Refusals are remembered for the error message.
struct FileAccess {
    std::optional<std::filesystem::path> directory;  // absolute, normalized
    std::string refused;

    bool allowed(const std::string& path)
    {
        // tinygltf joins the directory and the URI with '/': an absolute URI ("/etc/passwd",
        // "file:///...") shows as "//" in the joined path.
        if (path.find("//") != std::string::npos) {
            if (refused.empty())
                refused = "refusing to read '" + path + "': a buffer URI must be a relative path (or a data: URI)";
            return false;
        }
        if (directory && insideDirectory(*directory, path)) return true;
        if (refused.empty())
            refused = directory ? "refusing to read '" + path +
                    "': a buffer URI must name a file in the directory of the mesh or below it"
                                : "refusing to read '" + path +
                    "': a mesh read from memory may only use embedded (data: or GLB) buffers";
        return false;
    }
};

bool fileExists(const std::string& path, void* user)
{
    FileAccess& access = *static_cast<FileAccess*>(user);
    if (!access.allowed(path)) return false;
    std::error_code ec;
    return std::filesystem::is_regular_file(path, ec);
}

std::string expandFilePath(const std::string& path, void*) { return path; }  // no ~ or $VAR expansion

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user)
{
    FileAccess& access = *static_cast<FileAccess*>(user);
    if (!access.allowed(path)) {
        if (err) *err += access.refused;
        return false;
    }
    try {
        const std::vector<uint8_t> bytes = readFileBytes(path);
        out->assign(bytes.begin(), bytes.end());
        return true;
    } catch (const Error& e) {
        if (err) *err += e.what();
        return false;
    }
}

bool writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&, void*)
{
    if (err) *err += "writing is not supported";
    return false;
}

// Images are never decoded here. Geometry only: nothing is kept. With appearance, the bytes
// of an image from a data: URI are kept in Image::image (its URI is gone by then), for
// GltfMaterials to decode if a used material names it; images in buffer views and files are
// read from there instead.
bool skipImage(gltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*)
{
    return true;
}
bool keepDataUriImage(gltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
                      int size, void*)
{
    if (image->bufferView < 0 && bytes && size > 0) image->image.assign(bytes, bytes + size);
    return true;
}

// ---------------------------------------------------------------- the model

glm::dmat4 nodeTransform(const gltf::Node& node)
{
    if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3)
        m[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
    if (node.rotation.size() == 4) {
        glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF stores x, y, z, w
        m = m * glm::mat4_cast(q);
    }
    if (node.scale.size() == 3)
        m = m * glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return m;
}

// Reads accessor element `i`, component `c` as double. The constructor proves that every
// element lies inside the accessor's buffer view and its buffer, so get() needs no check.
class AccessorReader {
public:
    AccessorReader(const gltf::Model& model, int accessorIndex, const Input& input, const char* role) : input_(input)
    {
        name_ = std::string("glTF accessor ") + std::to_string(accessorIndex) + " (" + role + ")";
        if (accessorIndex < 0 || size_t(accessorIndex) >= model.accessors.size())
            fail(input_,
                 name_ + " does not exist (the file has " + std::to_string(model.accessors.size()) + " accessors)");
        accessor_ = &model.accessors[size_t(accessorIndex)];
        if (accessor_->sparse.isSparse) problem("is sparse (not supported)");
        if (accessor_->bufferView < 0 || size_t(accessor_->bufferView) >= model.bufferViews.size())
            problem("has no buffer view (" + std::to_string(accessor_->bufferView) + ")");
        const gltf::BufferView& view = model.bufferViews[size_t(accessor_->bufferView)];
        if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
            problem("uses buffer view " + std::to_string(accessor_->bufferView) + " whose buffer " +
                    std::to_string(view.buffer) + " does not exist");
        const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
        const int componentSize = gltf::GetComponentSizeInBytes(uint32_t(accessor_->componentType));
        const int components = gltf::GetNumComponentsInType(uint32_t(accessor_->type));
        if (componentSize <= 0 || components <= 0) problem("has an unknown component type or type");
        componentSize_ = size_t(componentSize);
        components_ = size_t(components);
        const size_t elementSize = componentSize_ * components_;  // at most 8 * 16
        stride_ = view.byteStride ? view.byteStride : elementSize;
        if (stride_ < elementSize)
            problem("has byteStride " + std::to_string(stride_) + ", less than its element size " +
                    std::to_string(elementSize));
        // All in size_t, every subtraction guarded, no product that can wrap.
        const std::string viewName = "buffer view " + std::to_string(accessor_->bufferView);
        if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
            problem("uses " + viewName + " (byteOffset " + std::to_string(view.byteOffset) + ", byteLength " +
                    std::to_string(view.byteLength) + ") that reaches past the end of its buffer (" +
                    std::to_string(buffer.size()) + " bytes)");
        if (accessor_->byteOffset > view.byteLength)
            problem("has byteOffset " + std::to_string(accessor_->byteOffset) + " past the end of " + viewName);
        const size_t available = view.byteLength - accessor_->byteOffset;
        const size_t count = accessor_->count;
        if (count > 0 && (elementSize > available || (count - 1) > (available - elementSize) / stride_))
            problem("(count " + std::to_string(count) + ", stride " + std::to_string(stride_) + ", element size " +
                    std::to_string(elementSize) + ") reaches past the end of " + viewName + " (" +
                    std::to_string(available) + " bytes after the accessor's offset)");
        data_ = buffer.data() + view.byteOffset + accessor_->byteOffset;
    }
    size_t count() const { return accessor_->count; }
    size_t components() const { return components_; }
    int componentType() const { return accessor_->componentType; }
    bool normalized() const { return accessor_->normalized; }
    const std::string& name() const { return name_; }
    [[noreturn]] void problem(const std::string& what) const { fail(input_, name_ + " " + what); }

    double get(size_t i, size_t c) const
    {
        const unsigned char* p = data_ + i * stride_ + c * componentSize_;
        switch (accessor_->componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: {
            float v;
            std::memcpy(&v, p, 4);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_DOUBLE: {
            double v;
            std::memcpy(&v, p, 8);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            uint16_t v;
            std::memcpy(&v, p, 2);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
            uint32_t v;
            std::memcpy(&v, p, 4);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            int8_t v;
            std::memcpy(&v, p, 1);
            return v;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            int16_t v;
            std::memcpy(&v, p, 2);
            return v;
        }
        default: problem("has an unsupported component type");
        }
    }

    // get() for a normalized integer accessor maps to [0, 1] (unsigned) or [-1, 1] (signed),
    // as glTF 2.0, 3.11 defines; floats and unnormalized integers are returned as stored.
    double getNormalized(size_t i, size_t c) const
    {
        const double v = get(i, c);
        if (!accessor_->normalized) return v;
        switch (accessor_->componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return v / 255.0;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return v / 65535.0;
        case TINYGLTF_COMPONENT_TYPE_BYTE: return std::max(v / 127.0, -1.0);
        case TINYGLTF_COMPONENT_TYPE_SHORT: return std::max(v / 32767.0, -1.0);
        default: return v;
        }
    }

private:
    const Input& input_;
    std::string name_;
    const gltf::Accessor* accessor_ = nullptr;
    const unsigned char* data_ = nullptr;
    size_t componentSize_ = 0, components_ = 0, stride_ = 0;
};

// The appearance the primitives add up to, kept complete over the triangles read so far once
// any primitive has an attribute (appearance.h: each array is empty or complete).
struct GltfAppearance {
    MeshAppearance& appearance;
    std::vector<int> triangleMaterial;  // per triangle: the glTF material (-1: none)
    bool anyMaterial = false;
};

// A per-vertex attribute of a primitive (TEXCOORD_0, COLOR_0), checked against its POSITION
// count and for finite values.
std::vector<glm::dvec4> readVertexAttribute(const gltf::Model& model, const gltf::Primitive& primitive,
                                            const char* name, size_t vertexCount, const Input& input)
{
    auto found = primitive.attributes.find(name);
    if (found == primitive.attributes.end()) return {};
    AccessorReader reader(model, found->second, input, name);
    const bool texcoord = std::string(name) == "TEXCOORD_0";
    const int type = reader.componentType();
    if (texcoord ? reader.components() != 2 : (reader.components() != 3 && reader.components() != 4))
        reader.problem(texcoord ? "is not a VEC2" : "is not a VEC3 or VEC4");
    if (type != TINYGLTF_COMPONENT_TYPE_FLOAT && !reader.normalized() && !texcoord)
        reader.problem("is neither float nor normalized integers");
    if (reader.count() != vertexCount)
        reader.problem("has " + std::to_string(reader.count()) + " elements, POSITION has " +
                       std::to_string(vertexCount));
    std::vector<glm::dvec4> values(reader.count(), glm::dvec4(0.0, 0.0, 0.0, 1.0));
    for (size_t i = 0; i < reader.count(); ++i)
        for (size_t c = 0; c < reader.components(); ++c) {
            const double v = reader.getNormalized(i, c);
            if (!std::isfinite(v)) reader.problem("element " + std::to_string(i) + " is NaN or infinite");
            values[i][int(c)] = v;
        }
    return values;
}

// Appends one primitive's corners to `out` (empty until some primitive has the attribute;
// then `fill` for the corners of those without).
template <typename T, typename Get>
void appendCorners(std::vector<T>& out, const TriangleMesh& mesh, size_t firstTriangle, bool has, T fill, Get get)
{
    if (!has) {
        if (!out.empty()) out.resize(mesh.triangles.size() * 3, fill);
        return;
    }
    out.resize(firstTriangle * 3, fill);
    for (size_t t = firstTriangle; t < mesh.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) out.push_back(get(mesh.triangles[t][k]));
}

void appendPrimitive(const gltf::Model& model, const gltf::Primitive& primitive, const glm::dmat4& transform,
                     TriangleMesh& mesh, const Input& input, GltfAppearance* appearance)
{
    int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
        mode == TINYGLTF_MODE_LINE_STRIP)
        return;  // points and lines carry no surface
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
        fail(input, "glTF primitive has unknown mode " + std::to_string(mode));
    // The primitive's points (untransformed) and corner indices: from its accessors, or from
    // its Draco bitstream (always a triangle list, whatever the mode says).
    std::vector<glm::dvec3> points;
    std::vector<uint32_t> indices;
    std::optional<DracoPrimitive> draco;
    if (const auto found = primitive.extensions.find("KHR_draco_mesh_compression");
        found != primitive.extensions.end()) {
        draco = decodeDracoPrimitive(model, found->second, input, appearance != nullptr);
        points = std::move(draco->positions);
        indices = std::move(draco->indices);
        mode = TINYGLTF_MODE_TRIANGLES;
    } else {
        auto position = primitive.attributes.find("POSITION");
        if (position == primitive.attributes.end()) fail(input, "glTF triangle primitive without POSITION");
        AccessorReader positions(model, position->second, input, "POSITION");
        if (positions.components() != 3) positions.problem("is not a VEC3");
        if (positions.componentType() != TINYGLTF_COMPONENT_TYPE_FLOAT)
            positions.problem("is quantized (KHR_mesh_quantization is not supported)");
        points.reserve(positions.count());
        for (size_t i = 0; i < positions.count(); ++i)
            points.emplace_back(positions.get(i, 0), positions.get(i, 1), positions.get(i, 2));
        if (primitive.indices >= 0) {
            AccessorReader reader(model, primitive.indices, input, "indices");
            const int type = reader.componentType();
            if (reader.components() != 1 ||
                (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                 type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
                reader.problem("is not a SCALAR of unsigned integers");
            indices.reserve(reader.count());
            for (size_t i = 0; i < reader.count(); ++i) {
                const double v = reader.get(i, 0);
                if (v >= double(positions.count()))
                    reader.problem("element " + std::to_string(i) + " refers to vertex " + std::to_string(uint64_t(v)) +
                                   " of " + std::to_string(positions.count()));
                indices.push_back(uint32_t(v));
            }
        } else {
            indices.reserve(positions.count());
            for (size_t i = 0; i < positions.count(); ++i) indices.push_back(uint32_t(i));
        }
    }
    if (points.size() > size_t(UINT32_MAX) - mesh.positions.size())
        fail(input, "glTF scene has more than 2^32-1 vertices");
    const uint32_t base = uint32_t(mesh.positions.size());
    // No reserve here: reserving the exact size for each of thousands of primitives would copy
    // the whole array each time (quadratic); push_back grows it geometrically.
    for (const glm::dvec3& q : points) mesh.positions.push_back(glm::dvec3(transform * glm::dvec4(q, 1.0)));
    const bool mirrored = glm::determinant(glm::dmat3(transform)) < 0.0;
    auto emit = [&](uint32_t a, uint32_t b, uint32_t c) {
        if (mirrored) std::swap(b, c);
        mesh.triangles.push_back({base + a, base + b, base + c});
    };
    if (mode == TINYGLTF_MODE_TRIANGLES)
        for (size_t i = 0; i + 2 < indices.size(); i += 3) emit(indices[i], indices[i + 1], indices[i + 2]);
    else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP)
        for (size_t i = 0; i + 2 < indices.size(); ++i)
            i % 2 ? emit(indices[i + 1], indices[i], indices[i + 2]) : emit(indices[i], indices[i + 1], indices[i + 2]);
    else
        for (size_t i = 1; i + 1 < indices.size(); ++i) emit(indices[0], indices[i], indices[i + 1]);
    if (!appearance) return;
    // Per corner from its vertex (after `emit`, so a mirrored transform's swap is followed).
    const size_t firstTriangle = appearance->triangleMaterial.size();
    const std::vector<glm::dvec4> uvs =
        draco ? std::move(draco->uvs) : readVertexAttribute(model, primitive, "TEXCOORD_0", points.size(), input);
    const std::vector<glm::dvec4> colours =
        draco ? std::move(draco->colours) : readVertexAttribute(model, primitive, "COLOR_0", points.size(), input);
    MeshAppearance& out = appearance->appearance;
    appendCorners(out.cornerUVs, mesh, firstTriangle, !uvs.empty(), glm::dvec2(0.0),
                  [&](uint32_t v) { return glm::dvec2(uvs[v - base]); });
    appendCorners(out.cornerColors, mesh, firstTriangle, !colours.empty(), glm::vec4(1.0f),
                  [&](uint32_t v) { return glm::vec4(colours[v - base]); });
    appearance->triangleMaterial.resize(mesh.triangles.size(), primitive.material);
    appearance->anyMaterial =
        appearance->anyMaterial || (primitive.material >= 0 && mesh.triangles.size() > firstTriangle);
}

// Whether a file tinygltf could not parse is glTF 1.0, which it does not read: a binary
// container of version 1 (KHR_binary_glTF), or JSON whose asset says 1.x (a string, or a number
// as some 1.0 writers put it), or, without a version, whose meshes, accessors or buffers are
// dictionaries (2.0 has arrays).
bool looksLikeGltf1(std::span<const uint8_t> bytes, bool binary)
{
    if (binary) {
        if (bytes.size() < 8 || std::memcmp(bytes.data(), "glTF", 4) != 0) return false;
        uint32_t version = 0;
        std::memcpy(&version, bytes.data() + 4, 4);
        return version == 1;
    }
    const nlohmann::json json = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (!json.is_object()) return false;
    const auto asset = json.find("asset");
    if (asset != json.end() && asset->is_object()) {
        const auto version = asset->find("version");
        if (version != asset->end() && version->is_string()) return version->get<std::string>().rfind("1", 0) == 0;
        if (version != asset->end() && version->is_number()) return version->get<double>() < 2.0;  // 1.0 writers
    }
    for (const char* key : {"meshes", "accessors", "buffers"}) {
        const auto entry = json.find(key);
        if (entry != json.end() && entry->is_object()) return true;
    }
    return false;
}

// Where a GLB's BIN chunk (its 8-byte header, then its data) runs past the file's declared
// length, why; empty otherwise. tinygltf checks the chunk's data length without its header and
// would read up to 8 bytes past the file.
std::string glbBinChunkProblem(std::span<const uint8_t> bytes)
{
    auto u32 = [&](size_t at) {
        uint32_t v = 0;
        std::memcpy(&v, bytes.data() + at, 4);
        return v;
    };
    if (bytes.size() < 20) return {};  // tinygltf refuses it by itself
    const uint64_t length = std::min<uint64_t>(u32(8), bytes.size());
    const uint64_t binAt = 20 + uint64_t(u32(12));  // header and JSON chunk
    if (binAt >= length) return {};                 // no BIN chunk (or a JSON chunk tinygltf refuses)
    if (binAt + 8 > length) return "its BIN chunk's header is cut off";
    const uint64_t binLength = u32(size_t(binAt));
    if (binAt + 8 + binLength > length)
        return "its BIN chunk holds " + std::to_string(binLength) + " bytes but the file has " +
            std::to_string(length - binAt - 8) + " after the chunk's header";
    return {};
}

}  // namespace

TriangleMesh readGltf(const Input& input, bool binary, MeshAppearance* appearance)
{
    if (input.bytes.empty()) fail(input, "the file is empty");
    if (input.bytes.size() > std::numeric_limits<unsigned int>::max())
        fail(input, "glTF file of 4 GiB or more (not supported)");
    FileAccess access;
    std::string baseDirectory;
    if (input.directory) {
        access.directory = meshDirectory(input);
        baseDirectory = access.directory->string();
    }
    gltf::TinyGLTF loader;
    loader.SetFsCallbacks({&fileExists, &expandFilePath, &readWholeFile, &writeWholeFile, &access});
    loader.SetImageLoader(appearance ? &keepDataUriImage : &skipImage, nullptr);
    gltf::Model model;
    std::string errors, warnings;
    // A file with Draco primitives is parsed without their "indices" (mesh_io_gltf_draco.h).
    const std::optional<std::vector<uint8_t>> rewritten = dracoParsable(input.bytes, binary);
    const std::span<const uint8_t> parsed = rewritten ? std::span<const uint8_t>(*rewritten) : input.bytes;
    if (parsed.size() > std::numeric_limits<unsigned int>::max())
        fail(input, "glTF file of 4 GiB or more (not supported)");
    // A 1.0 container's header is laid out otherwise: its chunk checks would name a wrong problem.
    if (binary && looksLikeGltf1(input.bytes, true))
        fail(input, "glTF 1.0 is not supported (only glTF 2.0; Blender or gltf-pipeline convert 1.0 files)");
    if (binary)
        if (const std::string problem = glbBinChunkProblem(parsed); !problem.empty()) fail(input, "GLB: " + problem);
    const bool ok = binary
        ? loader.LoadBinaryFromMemory(&model, &errors, &warnings, parsed.data(), unsigned(parsed.size()), baseDirectory)
        : loader.LoadASCIIFromString(&model, &errors, &warnings, reinterpret_cast<const char*>(parsed.data()),
                                     unsigned(parsed.size()), baseDirectory);
    if (!ok) {
        if (looksLikeGltf1(input.bytes, binary))
            fail(input, "glTF 1.0 is not supported (only glTF 2.0; Blender or gltf-pipeline convert 1.0 files)");
        while (!errors.empty() && (errors.back() == '\n' || errors.back() == ' ')) errors.pop_back();
        if (!access.refused.empty()) errors = access.refused + (errors.empty() ? "" : " (" + errors + ")");
        fail(input, "cannot parse glTF: " + (errors.empty() ? std::string("unknown error") : errors));
    }
    if (!model.asset.version.empty() && model.asset.version[0] == '1')
        fail(input,
             "glTF " + model.asset.version +
                 " is not supported (only glTF 2.0; Blender or gltf-pipeline convert 1.0 files)");
    TriangleMesh mesh;
    std::optional<GltfAppearance> gltfAppearance;
    if (appearance) gltfAppearance.emplace(GltfAppearance{*appearance, {}, false});
    GltfAppearance* primitiveAppearance = gltfAppearance ? &*gltfAppearance : nullptr;
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        const size_t scene = model.defaultScene >= 0 && size_t(model.defaultScene) < model.scenes.size()
            ? size_t(model.defaultScene)
            : 0;
        roots = model.scenes[scene].nodes;
    } else {  // no scene: every node that is nobody's child
        std::vector<uint8_t> isChild(model.nodes.size(), 0);
        for (const auto& node : model.nodes)
            for (int c : node.children)
                if (c >= 0 && size_t(c) < isChild.size()) isChild[size_t(c)] = 1;
        for (size_t n = 0; n < model.nodes.size(); ++n)
            if (!isChild[n]) roots.push_back(int(n));
    }
    struct Pending {
        int node;
        glm::dmat4 parent;
    };
    // The hierarchy must be a set of strict trees (glTF 2.0, 3.5.3): a node reached twice is
    // a cycle or a shared child, and a shared child would let a small file instance a mesh
    // exponentially often.
    std::vector<uint8_t> visited(model.nodes.size(), 0);
    std::vector<Pending> stack;
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.push_back({*r, glm::dmat4(1.0)});  // scene order
    while (!stack.empty()) {
        const Pending item = stack.back();
        stack.pop_back();
        if (item.node < 0 || size_t(item.node) >= model.nodes.size())
            fail(input,
                 "glTF node " + std::to_string(item.node) + " does not exist (the file has " +
                     std::to_string(model.nodes.size()) + " nodes)");
        if (visited[size_t(item.node)]++)
            fail(input,
                 "glTF node " + std::to_string(item.node) +
                     " is reached twice (the node hierarchy must be a tree: a cycle or a shared child)");
        const gltf::Node& node = model.nodes[size_t(item.node)];
        const glm::dmat4 world = item.parent * nodeTransform(node);
        if (node.mesh >= 0) {
            if (size_t(node.mesh) >= model.meshes.size())
                fail(input,
                     "glTF node " + std::to_string(item.node) + " refers to mesh " + std::to_string(node.mesh) +
                         ", which does not exist");
            for (const auto& primitive : model.meshes[size_t(node.mesh)].primitives)
                appendPrimitive(model, primitive, world, mesh, input, primitiveAppearance);
        }
        for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world});
    }
    if (model.scenes.empty() && model.nodes.empty())  // meshes and nothing to place them: each once, as stored
        for (const auto& gltfMesh : model.meshes)
            for (const auto& primitive : gltfMesh.primitives)
                appendPrimitive(model, primitive, glm::dmat4(1.0), mesh, input, primitiveAppearance);
    if (mesh.triangles.empty()) fail(input, "the glTF scene has no triangle primitives: the mesh has no triangles");
    if (gltfAppearance && gltfAppearance->anyMaterial) {
        GltfMaterials materials(model, input, *appearance);
        appearance->triangleMaterial.reserve(mesh.triangles.size());
        for (int material : gltfAppearance->triangleMaterial)
            appearance->triangleMaterial.push_back(materials.materialIndex(material));
    }
    return mesh;
}

}  // namespace ngi::mesh_io
