// ngi offline: mesh reading (OpenMesh readers for OBJ/PLY/STL and binary OFF, our own ASCII
// OFF reader, tinygltf for glTF 2.0)
// and writing (OBJ/OFF/PLY, written here in full double precision, atomically).
//
// OpenMesh's own mesh kernels refuse non-manifold faces (and only print a warning), which
// would hide exactly the defects the cleaning stage must report. So the readers feed a
// polygon-soup importer instead: every vertex and polygon is recorded as read, and the
// cleaning stage (clean.h) decides what is repairable.
#include "ngi/mesh/mesh_io.h"

#include "ngi/asset.h"
#include "ngi/error.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/ImporterT.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>

namespace ngi {
namespace {

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

// ---------------------------------------------------------------- OpenMesh (OBJ, OFF, PLY, STL)

struct DoubleTraits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
using PolyMesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

// Records vertices and polygons as the reader delivers them; builds no connectivity.
// Vertices are also added to the (face-less) kernel so that per-vertex attribute calls the
// readers make on the returned handles stay valid.
class SoupImporter : public OpenMesh::IO::ImporterT<PolyMesh> {
public:
    SoupImporter(PolyMesh& kernel, TriangleMesh& soup, size_t& polygons)
        : OpenMesh::IO::ImporterT<PolyMesh>(kernel), soup_(soup), polygons_(polygons) {}

    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3f& p) override {
        soup_.positions.push_back({p[0], p[1], p[2]});
        return OpenMesh::IO::ImporterT<PolyMesh>::add_vertex(p);
    }
    OpenMesh::VertexHandle add_vertex(const OpenMesh::Vec3d& p) override {
        soup_.positions.push_back({p[0], p[1], p[2]});
        return OpenMesh::IO::ImporterT<PolyMesh>::add_vertex(p);
    }
    OpenMesh::VertexHandle add_vertex() override {  // PLY: the point follows through set_point
        soup_.positions.push_back({0.0, 0.0, 0.0});
        return OpenMesh::IO::ImporterT<PolyMesh>::add_vertex();
    }
    void set_point(OpenMesh::VertexHandle v, const OpenMesh::Vec3f& p) override {
        if (v.is_valid() && size_t(v.idx()) < soup_.positions.size()) soup_.positions[size_t(v.idx())] = {p[0], p[1], p[2]};
        OpenMesh::IO::ImporterT<PolyMesh>::set_point(v, p);
    }
    OpenMesh::FaceHandle add_face(const VHandles& indices) override {
        ++polygons_;
        for (size_t k = 0; k < indices.size(); ++k)
            if (!indices[k].is_valid() || size_t(indices[k].idx()) >= soup_.positions.size()) {
                badIndex_ = true;
                return OpenMesh::FaceHandle();
            }
        for (size_t k = 1; k + 1 < indices.size(); ++k)  // fan triangulation
            soup_.triangles.push_back({uint32_t(indices[0].idx()), uint32_t(indices[k].idx()), uint32_t(indices[k + 1].idx())});
        return OpenMesh::FaceHandle();  // no kernel face: attribute calls on it are ignored below
    }
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle, const std::vector<OpenMesh::Vec2f>&) override {}
    void add_face_texcoords(OpenMesh::FaceHandle, OpenMesh::VertexHandle, const std::vector<OpenMesh::Vec3f>&) override {}
    void set_face_texindex(OpenMesh::FaceHandle, int) override {}
    size_t n_faces() const override { return polygons_; }

    bool badIndex() const { return badIndex_; }

private:
    TriangleMesh& soup_;
    size_t& polygons_;
    bool badIndex_ = false;
};

TriangleMesh readWithOpenMesh(const std::filesystem::path& path) {
    TriangleMesh mesh;
    size_t polygons = 0;
    PolyMesh kernel;
    SoupImporter importer(kernel, mesh, polygons);
    OpenMesh::IO::Options options;
    // OpenMesh reports problems on its own error stream; library code stays silent.
    omerr().disable();
    omlog().disable();
    bool ok = OpenMesh::IO::IOManager().read(path.string(), importer, options);
    omerr().enable();
    omlog().enable();
    if (!ok) throw Error(path.string() + ": cannot parse the file as " + lowerExtension(path).substr(1) + " (corrupt or unsupported variant)");
    if (importer.badIndex()) throw Error(path.string() + ": a face refers to a vertex that does not exist");
    return mesh;
}

// ---------------------------------------------------------------- ASCII OFF
// OpenMesh's OFF reader rejects '#' comments before the header or between sections, which
// CGAL's own data set uses (e.g. "# Output of a CGAL tool"). ASCII OFF is read here, line by
// line: comments stripped, [C][N][ST]OFF header, counts, then one vertex (first three numbers;
// colours or normals after them are ignored) or one polygon per line. Binary OFF goes to
// OpenMesh.
bool isBinaryOff(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::string line;
    while (std::getline(in, line)) {
        const size_t hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        return line.find("BINARY") != std::string::npos;
    }
    return false;
}

TriangleMesh readAsciiOff(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path.string() + ": cannot open the file");
    auto fail = [&](const std::string& problem) -> TriangleMesh { throw Error(path.string() + ": corrupt OFF file: " + problem); };
    std::vector<std::string> lines;  // non-empty lines without comments
    std::string line;
    while (std::getline(in, line)) {
        const size_t hash = line.find('#');
        if (hash != std::string::npos) line.resize(hash);
        if (line.find_first_not_of(" \t\r") != std::string::npos) lines.push_back(line);
    }
    size_t at = 0;
    if (lines.empty()) return fail("the file is empty");
    std::istringstream header(lines[at++]);
    std::string keyword;
    header >> keyword;
    if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0) return fail("no OFF header");
    if (keyword.find('4') != std::string::npos || keyword.find("nOFF") != std::string::npos)
        return fail("only 3D OFF is supported");
    long long counts[3] = {-1, -1, 0};
    int got = 0;
    while (got < 2) {  // counts may follow the keyword on its line
        long long value;
        if (header >> value) {
            if (got < 3) counts[got++] = value;
            continue;
        }
        if (at >= lines.size()) return fail("missing vertex and face counts");
        header = std::istringstream(lines[at++]);
    }
    if (counts[0] < 0 || counts[1] < 0 || counts[0] > (1ll << 31) || counts[1] > (1ll << 31)) return fail("bad counts");
    const size_t vertexCount = size_t(counts[0]), faceCount = size_t(counts[1]);
    if (lines.size() - at < vertexCount + faceCount) return fail("truncated (fewer lines than the counts promise)");
    TriangleMesh mesh;
    mesh.positions.reserve(vertexCount);
    for (size_t v = 0; v < vertexCount; ++v) {
        const char* p = lines[at].c_str();
        const char* end = p + lines[at].size();
        ++at;
        glm::dvec3 position;
        for (int c = 0; c < 3; ++c) {
            while (p < end && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
            char* next = nullptr;
            position[c] = std::strtod(p, &next);  // accepts nan/inf: rejected by readMesh
            if (next == p) return fail("vertex " + std::to_string(v) + " does not have three coordinates");
            p = next;
        }
        mesh.positions.push_back(position);
    }
    for (size_t f = 0; f < faceCount; ++f) {
        std::istringstream polygon(lines[at++]);
        long long n = 0;
        if (!(polygon >> n) || n < 0 || n > 1 << 20) return fail("face " + std::to_string(f) + " has no valid vertex count");
        std::vector<uint32_t> indices;
        for (long long k = 0; k < n; ++k) {
            long long index;
            if (!(polygon >> index)) return fail("face " + std::to_string(f) + " has fewer than " + std::to_string(n) + " indices");
            if (index < 0 || size_t(index) >= vertexCount)
                return fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(index) + " of " + std::to_string(vertexCount));
            indices.push_back(uint32_t(index));
        }
        for (size_t k = 1; k + 1 < indices.size(); ++k) mesh.triangles.push_back({indices[0], indices[k], indices[k + 1]});
    }
    return mesh;
}

// ---------------------------------------------------------------- tinygltf (.gltf, .glb)

glm::dmat4 nodeTransform(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());
    glm::dmat4 m(1.0);
    if (node.translation.size() == 3) m[3] = glm::dvec4(node.translation[0], node.translation[1], node.translation[2], 1.0);
    if (node.rotation.size() == 4) {
        glm::dquat q(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF stores x, y, z, w
        m = m * glm::mat4_cast(q);
    }
    if (node.scale.size() == 3) m = m * glm::scale(glm::dmat4(1.0), glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    return m;
}

// Reads accessor element `i`, component `c` as double, with bounds checks.
class AccessorReader {
public:
    AccessorReader(const tinygltf::Model& model, int accessorIndex, const std::string& file) : file_(file) {
        if (accessorIndex < 0 || size_t(accessorIndex) >= model.accessors.size()) fail("accessor index out of range");
        accessor_ = &model.accessors[accessorIndex];
        if (accessor_->sparse.isSparse) fail("sparse accessors are not supported");
        if (accessor_->bufferView < 0 || size_t(accessor_->bufferView) >= model.bufferViews.size()) fail("accessor without a buffer view");
        const tinygltf::BufferView& view = model.bufferViews[accessor_->bufferView];
        if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size()) fail("buffer view without a buffer");
        const std::vector<unsigned char>& buffer = model.buffers[view.buffer].data;
        componentSize_ = size_t(tinygltf::GetComponentSizeInBytes(uint32_t(accessor_->componentType)));
        components_ = size_t(tinygltf::GetNumComponentsInType(uint32_t(accessor_->type)));
        if (componentSize_ == size_t(-1) || components_ == size_t(-1)) fail("unknown accessor type");
        stride_ = view.byteStride ? view.byteStride : componentSize_ * components_;
        const size_t begin = view.byteOffset + accessor_->byteOffset;
        const size_t need = accessor_->count ? (accessor_->count - 1) * stride_ + componentSize_ * components_ : 0;
        if (begin > buffer.size() || need > buffer.size() - begin || accessor_->byteOffset + need > view.byteLength)
            fail("accessor reaches past the end of its buffer");
        data_ = buffer.data() + begin;
    }
    size_t count() const { return accessor_->count; }
    size_t components() const { return components_; }
    int componentType() const { return accessor_->componentType; }
    double get(size_t i, size_t c) const {
        const unsigned char* p = data_ + i * stride_ + c * componentSize_;
        switch (accessor_->componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; std::memcpy(&v, p, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_DOUBLE: { double v; std::memcpy(&v, p, 8); return v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; std::memcpy(&v, p, 2); return v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; std::memcpy(&v, p, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_BYTE: { int8_t v; std::memcpy(&v, p, 1); return v; }
        case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t v; std::memcpy(&v, p, 2); return v; }
        default: fail("unsupported component type");
        }
        return 0.0;
    }

private:
    [[noreturn]] void fail(const std::string& problem) const { throw Error(file_ + ": glTF " + problem); }
    std::string file_;
    const tinygltf::Accessor* accessor_ = nullptr;
    const unsigned char* data_ = nullptr;
    size_t componentSize_ = 0, components_ = 0, stride_ = 0;
};

void appendPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive, const glm::dmat4& transform,
                     TriangleMesh& mesh, const std::string& file) {
    const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN)
        return;  // points and lines carry no surface
    auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) throw Error(file + ": glTF triangle primitive without POSITION");
    AccessorReader positions(model, position->second, file);
    if (positions.components() != 3) throw Error(file + ": glTF POSITION is not a VEC3");
    if (positions.componentType() != TINYGLTF_COMPONENT_TYPE_FLOAT)
        throw Error(file + ": glTF quantized POSITION (KHR_mesh_quantization) is not supported");
    const uint32_t base = uint32_t(mesh.positions.size());
    for (size_t i = 0; i < positions.count(); ++i) {
        glm::dvec4 p = transform * glm::dvec4(positions.get(i, 0), positions.get(i, 1), positions.get(i, 2), 1.0);
        mesh.positions.push_back(glm::dvec3(p));
    }
    std::vector<uint32_t> indices;
    if (primitive.indices >= 0) {
        AccessorReader reader(model, primitive.indices, file);
        for (size_t i = 0; i < reader.count(); ++i) {
            double v = reader.get(i, 0);
            if (v < 0 || v >= double(positions.count())) throw Error(file + ": glTF index out of range");
            indices.push_back(uint32_t(v));
        }
    } else {
        for (size_t i = 0; i < positions.count(); ++i) indices.push_back(uint32_t(i));
    }
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
}

TriangleMesh readGltf(const std::filesystem::path& path, bool binary) {
    tinygltf::TinyGLTF loader;
    tinygltf::Model model;
    std::string errors, warnings;
    const bool ok = binary ? loader.LoadBinaryFromFile(&model, &errors, &warnings, path.string())
                           : loader.LoadASCIIFromFile(&model, &errors, &warnings, path.string());
    if (!ok) {
        while (!errors.empty() && (errors.back() == '\n' || errors.back() == ' ')) errors.pop_back();
        throw Error(path.string() + ": cannot parse glTF: " + (errors.empty() ? std::string("unknown error") : errors));
    }
    TriangleMesh mesh;
    std::vector<int> roots;
    if (!model.scenes.empty()) {
        int scene = model.defaultScene >= 0 && size_t(model.defaultScene) < model.scenes.size() ? model.defaultScene : 0;
        roots = model.scenes[scene].nodes;
    } else {  // no scene: every node that is nobody's child
        std::vector<uint8_t> isChild(model.nodes.size(), 0);
        for (const auto& node : model.nodes)
            for (int c : node.children)
                if (c >= 0 && size_t(c) < isChild.size()) isChild[c] = 1;
        for (size_t n = 0; n < model.nodes.size(); ++n)
            if (!isChild[n]) roots.push_back(int(n));
    }
    struct Pending {
        int node;
        glm::dmat4 parent;
        int depth;
    };
    std::vector<Pending> stack;
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.push_back({*r, glm::dmat4(1.0), 0});  // scene order
    while (!stack.empty()) {
        Pending item = stack.back();
        stack.pop_back();
        if (item.node < 0 || size_t(item.node) >= model.nodes.size()) throw Error(path.string() + ": glTF node index out of range");
        if (item.depth > 256) throw Error(path.string() + ": glTF node hierarchy too deep (cycle?)");
        const tinygltf::Node& node = model.nodes[item.node];
        const glm::dmat4 world = item.parent * nodeTransform(node);
        if (node.mesh >= 0) {
            if (size_t(node.mesh) >= model.meshes.size()) throw Error(path.string() + ": glTF mesh index out of range");
            for (const auto& primitive : model.meshes[node.mesh].primitives) appendPrimitive(model, primitive, world, mesh, path.string());
        }
        for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back({*c, world, item.depth + 1});
    }
    return mesh;
}

// ---------------------------------------------------------------- writers

void appendNumber(std::string& out, double v) {
    char buffer[32];
    auto result = std::to_chars(buffer, buffer + sizeof buffer, v);  // shortest exact round trip
    out.append(buffer, result.ptr);
}

std::string formatMesh(const TriangleMesh& mesh, const std::string& ext) {
    std::string out;
    out.reserve(mesh.positions.size() * 60 + mesh.triangles.size() * 30);
    if (ext == ".off") {
        out += "OFF\n" + std::to_string(mesh.positions.size()) + " " + std::to_string(mesh.triangles.size()) + " 0\n";
    } else if (ext == ".ply") {
        out += "ply\nformat ascii 1.0\ncomment written by ngi\nelement vertex " + std::to_string(mesh.positions.size()) +
               "\nproperty double x\nproperty double y\nproperty double z\nelement face " + std::to_string(mesh.triangles.size()) +
               "\nproperty list uchar int vertex_indices\nend_header\n";
    } else {
        out += "# written by ngi\n";
    }
    for (const glm::dvec3& p : mesh.positions) {
        if (ext == ".obj") out += "v ";
        for (int c = 0; c < 3; ++c) {
            appendNumber(out, p[c]);
            out += c < 2 ? ' ' : '\n';
        }
    }
    const uint32_t base = ext == ".obj" ? 1 : 0;
    for (const glm::uvec3& t : mesh.triangles)
        out += (ext == ".obj" ? "f " : "3 ") + std::to_string(t.x + base) + " " + std::to_string(t.y + base) + " " +
               std::to_string(t.z + base) + "\n";
    return out;
}

} // namespace

TriangleMesh readMesh(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(path.string() + ": no such file");
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path.string() + ": not a regular file");
    const std::string ext = lowerExtension(path);
    TriangleMesh mesh;
    if (ext == ".off" && !isBinaryOff(path))
        mesh = readAsciiOff(path);
    else if (ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl")
        mesh = readWithOpenMesh(path);
    else if (ext == ".gltf" || ext == ".glb")
        mesh = readGltf(path, ext == ".glb");
    else
        throw Error(path.string() + ": unknown mesh format '" + ext + "' (expected .obj, .off, .ply, .stl, .gltf or .glb)");
    if (mesh.triangles.empty()) throw Error(path.string() + ": the mesh has no triangles");
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        if (!std::isfinite(mesh.positions[i].x) || !std::isfinite(mesh.positions[i].y) || !std::isfinite(mesh.positions[i].z))
            throw Error(path.string() + ": vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
    return mesh;
}

void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh) {
    const std::string ext = lowerExtension(path);
    if (ext != ".obj" && ext != ".off" && ext != ".ply")
        throw Error(path.string() + ": cannot write mesh format '" + ext + "' (expected .obj, .off or .ply)");
    for (const glm::uvec3& t : mesh.triangles)
        if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size())
            throw Error(path.string() + ": cannot write a mesh whose triangles refer to missing vertices");
    const std::string text = formatMesh(mesh, ext);
    writeFileAtomic(path, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

} // namespace ngi
