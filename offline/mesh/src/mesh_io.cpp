// ngi offline: mesh reading (dispatch by extension to the per-format readers in
// mesh_io_{obj,off,ply,stl,gltf}.cpp, with or without appearance) and writing (OBJ/OFF/PLY, in full double precision,
// atomically).
//
// The readers are our own (glTF: tinygltf for the JSON), not OpenMesh's: those stopped at
// the first short read and returned what they had (a truncated PLY baked 64 of 320
// triangles), allocated whatever a header declared, and could not say on which line a file
// went wrong. Ours record every vertex and polygon as read (no connectivity, no repair: the
// cleaning stage, clean.h, decides what is repairable) and turn every problem into one
// ngi::Error that names the file.
#include "ngi/mesh/mesh_io.h"

#include "mesh_io_internal.h"

#include "ngi/asset.h"
#include "ngi/error.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <new>
#include <stdexcept>
#include <string>

namespace ngi {
namespace {

std::string lowerExtension(const std::filesystem::path& path)
{
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext;
}

std::string lower(std::string text)
{
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

// Backstops for what every reader's appearance must satisfy (appearance.h): complete
// per-corner and per-triangle arrays, finite values, indices in range.
void checkAppearance(const mesh_io::Input& input, const TriangleMesh& mesh, const MeshAppearance& appearance)
{
    const size_t corners = mesh.triangles.size() * 3;
    if (!appearance.cornerUVs.empty() && appearance.cornerUVs.size() != corners)
        throw Error(input.name + ": internal error: texture coordinates for " +
                    std::to_string(appearance.cornerUVs.size()) + " of " + std::to_string(corners) +
                    " triangle corners");
    if (!appearance.cornerColors.empty() && appearance.cornerColors.size() != corners)
        throw Error(input.name + ": internal error: colours for " + std::to_string(appearance.cornerColors.size()) +
                    " of " + std::to_string(corners) + " triangle corners");
    if (!appearance.triangleMaterial.empty() && appearance.triangleMaterial.size() != mesh.triangles.size())
        throw Error(input.name + ": internal error: materials for " +
                    std::to_string(appearance.triangleMaterial.size()) + " of " +
                    std::to_string(mesh.triangles.size()) + " triangles");
    for (size_t i = 0; i < appearance.cornerUVs.size(); ++i)
        if (!std::isfinite(appearance.cornerUVs[i].x) || !std::isfinite(appearance.cornerUVs[i].y))
            throw Error(input.name + ": triangle " + std::to_string(i / 3) +
                        " has a NaN or infinite texture coordinate");
    for (size_t i = 0; i < appearance.cornerColors.size(); ++i)
        for (int c = 0; c < 4; ++c)
            if (!std::isfinite(appearance.cornerColors[i][c]))
                throw Error(input.name + ": triangle " + std::to_string(i / 3) + " has a NaN or infinite colour");
    for (uint32_t m : appearance.triangleMaterial)
        if (m >= appearance.materials.size())
            throw Error(input.name + ": internal error: material " + std::to_string(m) + " of " +
                        std::to_string(appearance.materials.size()));
    for (const Material& material : appearance.materials)
        for (const TextureRef* t : {&material.baseColorTexture, &material.metallicRoughnessTexture,
                                    &material.normalTexture, &material.occlusionTexture, &material.emissiveTexture})
            if (t->image >= 0 && size_t(t->image) >= appearance.images.size())
                throw Error(input.name + ": internal error: material '" + material.name + "' refers to image " +
                            std::to_string(t->image) + " of " + std::to_string(appearance.images.size()));
}

TriangleMesh readFormat(const mesh_io::Input& input, const std::string& format, MeshAppearance* appearance)
{
    TriangleMesh mesh;
    if (appearance) *appearance = MeshAppearance{};
    try {
        if (format == ".obj")
            mesh = mesh_io::readObj(input, appearance);
        else if (format == ".off")
            mesh = mesh_io::readOff(input);
        else if (format == ".ply")
            mesh = mesh_io::readPly(input, appearance);
        else if (format == ".stl")
            mesh = mesh_io::readStl(input);
        else if (format == ".gltf" || format == ".glb")
            mesh = mesh_io::readGltf(input, format == ".glb", appearance);
        else
            throw Error(input.name + ": unknown mesh format '" + format +
                        "' (expected .obj, .off, .ply, .stl, .gltf or .glb)");
    } catch (const std::bad_alloc&) {
        throw Error(input.name + ": out of memory reading the mesh (" + std::to_string(input.bytes.size()) +
                    " bytes of " + format.substr(1) + ")");
    } catch (const std::length_error&) {
        throw Error(input.name + ": out of memory reading the mesh (a size beyond what a vector holds)");
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {  // from tinygltf or the JSON parser: still one ngi::Error
        throw Error(input.name + ": cannot read the mesh: " + e.what());
    }
    // Backstops for what every format must satisfy (the readers say more where they can).
    if (mesh.triangles.empty()) throw Error(input.name + ": the mesh has no triangles");
    for (const glm::uvec3& t : mesh.triangles)
        if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size())
            throw Error(input.name + ": a triangle refers to a vertex that does not exist");
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        for (int c = 0; c < 3; ++c)
            if (!mesh_io::usableCoordinate(mesh.positions[i][c]))
                throw Error(input.name + ": vertex " + std::to_string(i) +
                            " has a NaN or infinite coordinate (or one beyond single precision)");
    if (appearance) checkAppearance(input, mesh, *appearance);
    return mesh;
}

// ---------------------------------------------------------------- writers

void appendNumber(std::string& out, double v)
{
    char buffer[32];
    auto result = std::to_chars(buffer, buffer + sizeof buffer, v);  // shortest exact round trip
    out.append(buffer, result.ptr);
}

std::string formatMesh(const TriangleMesh& mesh, const std::string& ext)
{
    std::string out;
    out.reserve(mesh.positions.size() * 60 + mesh.triangles.size() * 30);
    if (ext == ".off") {
        out += "OFF\n" + std::to_string(mesh.positions.size()) + " " + std::to_string(mesh.triangles.size()) + " 0\n";
    } else if (ext == ".ply") {
        out += "ply\nformat ascii 1.0\ncomment written by ngi\nelement vertex " +
            std::to_string(mesh.positions.size()) +
            "\nproperty double x\nproperty double y\nproperty double z\nelement face " +
            std::to_string(mesh.triangles.size()) + "\nproperty list uchar int vertex_indices\nend_header\n";
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

TriangleMesh readMeshFile(const std::filesystem::path& path, MeshAppearance* appearance)
{
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(path.string() + ": no such file");
    if (!std::filesystem::is_regular_file(path, ec)) throw Error(path.string() + ": not a regular file");
    const std::string ext = lowerExtension(path);
    if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl" && ext != ".gltf" && ext != ".glb")
        throw Error(path.string() + ": unknown mesh format '" + ext +
                    "' (expected .obj, .off, .ply, .stl, .gltf or .glb)");
    std::vector<uint8_t> bytes;
    try {
        bytes = readFileBytes(path);
    } catch (const std::bad_alloc&) {
        throw Error(path.string() + ": out of memory reading the file");
    }
    mesh_io::Input input{bytes, path.string(),
                         path.has_parent_path() ? path.parent_path() : std::filesystem::path(".")};
    return readFormat(input, ext, appearance);
}

TriangleMesh readMemory(std::span<const uint8_t> bytes, const std::string& format, const std::string& name,
                        MeshAppearance* appearance)
{
    mesh_io::Input input{bytes, name, std::nullopt};
    return readFormat(input, lower(format.empty() || format[0] == '.' ? format : "." + format), appearance);
}

}  // namespace

TriangleMesh readMesh(const std::filesystem::path& path) { return readMeshFile(path, nullptr); }

TriangleMesh readMesh(const std::filesystem::path& path, MeshAppearance& appearance)
{
    return readMeshFile(path, &appearance);
}

TriangleMesh readMeshFromMemory(std::span<const uint8_t> bytes, const std::string& format, const std::string& name)
{
    return readMemory(bytes, format, name, nullptr);
}

TriangleMesh readMeshFromMemory(std::span<const uint8_t> bytes, const std::string& format, const std::string& name,
                                MeshAppearance& appearance)
{
    return readMemory(bytes, format, name, &appearance);
}

void checkMeshOutputFormat(const std::filesystem::path& path)
{
    const std::string ext = lowerExtension(path);
    if (ext.empty())
        throw Error((path.empty() ? std::string("''") : path.string()) +
                    ": the output path has no extension (expected .obj, .off or .ply)");
    if (ext != ".obj" && ext != ".off" && ext != ".ply")
        throw Error(path.string() + ": cannot write mesh format '" + ext + "' (expected .obj, .off or .ply)");
}

void writeMesh(const std::filesystem::path& path, const TriangleMesh& mesh)
{
    checkMeshOutputFormat(path);
    const std::string ext = lowerExtension(path);
    for (const glm::uvec3& t : mesh.triangles)
        if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size())
            throw Error(path.string() + ": cannot write a mesh whose triangles refer to missing vertices");
    const std::string text = formatMesh(mesh, ext);
    writeFileAtomic(path, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

}  // namespace ngi
