// ngi offline: the Wavefront OBJ reader.
//
// Reads `v` (the first three numbers; a w or colour after them is ignored) and `f` (a/b/c,
// a/b, a//c, negative indices relative to the vertices read so far; polygon_triangulation.h).
// With appearance it also reads `vt` (as (u, 1 - v)), the vertex colours some writers append
// (`v x y z r g b`, sRGB in [0, 1]), `mtllib` (mesh_io_mtl.h; the libraries and their
// textures must lie in the mesh's directory or below) and `usemtl`. A missing library or an
// unknown material name is a warning and its faces get the default material, as other
// importers do; a missing texture is an error. Every other statement (vn,
// o, g, s, l, p, ...) is skipped. A line ending in '\' continues on the next one. A UTF-8 byte
// order mark is skipped; UTF-16 text is refused with a message saying so.
#include "mesh_io_internal.h"
#include "ngi/srgb.h"
#include "mesh_io_mtl.h"
#include "polygon_triangulation.h"
#include "texture_io.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace ngi::mesh_io {
namespace {

constexpr uint32_t kNone = UINT32_MAX;

std::string_view trim(std::string_view text)
{
    while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) text.remove_prefix(1);
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.remove_suffix(1);
    return text;
}

// What an OBJ's appearance statements left behind, resolved into a MeshAppearance once the
// whole file (and so every vertex, texture coordinate and face) is read.
struct ObjAppearance {
    std::vector<glm::dvec2> texcoords;     // vt, as (u, 1 - v)
    std::vector<glm::vec4> vertexColours;  // per vertex (white where a vertex has none)
    bool anyColour = false;
    std::vector<uint32_t> cornerTexcoords;       // per polygon corner in file order: vt index or kNone
    std::vector<uint32_t> triangleMaterialName;  // per triangle: index into usedNames, or kNone
    std::vector<std::string> usedNames;          // usemtl names in order of first use
    std::unordered_map<std::string, uint32_t> nameIndex;
    uint32_t current = kNone;                                             // the material of the next faces
    std::vector<MtlMaterial> library;                                     // every mtllib's materials, in order
    std::vector<std::filesystem::path> libraryFiles, libraryDirectories;  // per material: where it came from
    std::vector<std::filesystem::path> readLibraries;
};

// Reads a `mtllib` statement: one or more files, or one name with spaces when that is a file.
void readLibraries(const Input& input, std::string_view rest, ObjAppearance& obj, MeshAppearance& appearance,
                   const std::string& where)
{
    if (!input.directory) {
        appearance.warnings.push_back(input.name + ": " + where +
                                      ": mtllib not read (a mesh read from memory has no directory)");
        return;
    }
    std::vector<std::string> files;
    const std::string whole(trim(rest));
    std::error_code ec;
    if (whole.find_first_of(" \t") != std::string::npos &&
        std::filesystem::is_regular_file(meshDirectory(input) / whole, ec))
        files.push_back(whole);
    else
        for (std::string_view token = nextToken(rest); !token.empty(); token = nextToken(rest))
            files.emplace_back(token);
    for (const std::string& file : files) {
        const std::filesystem::path path = referencedFile(input, meshDirectory(input), file, "material library");
        if (std::find(obj.readLibraries.begin(), obj.readLibraries.end(), path) != obj.readLibraries.end()) continue;
        if (!std::filesystem::exists(path, ec)) {  // common in the wild: the faces get the default material
            appearance.warnings.push_back(input.name + ": " + where + ": the material library " + path.string() +
                                          " does not exist");
            continue;
        }
        const std::vector<uint8_t> bytes = readReferencedFile(input, path, "material library");
        obj.readLibraries.push_back(path);
        const Input library{bytes, input.name + ": material library " + path.string(), path.parent_path()};
        for (MtlMaterial& m : parseMtl(library, appearance.warnings)) {
            obj.library.push_back(std::move(m));
            obj.libraryFiles.push_back(path);
        }
    }
}

// Decodes `t`'s file once per resolved path; returns the TextureRef with its image set.
TextureRef loadTexture(const Input& input, const MtlTexture& t, const std::filesystem::path& libraryFile,
                       MeshAppearance& appearance, std::map<std::filesystem::path, int32_t>& images)
{
    TextureRef ref = t.ref;
    if (t.file.empty()) return ref;
    const std::filesystem::path path = referencedFile(input, libraryFile.parent_path(), t.file, "texture");
    auto found = images.find(path);
    if (found == images.end()) {
        appearance.images.push_back(
            decodeTexture(readReferencedFile(input, path, "texture"), input.name, path.string()));
        found = images.emplace(path, int32_t(appearance.images.size() - 1)).first;
    }
    ref.image = found->second;
    return ref;
}

// The per-corner and per-triangle arrays and the used materials, from what the file said.
void resolveAppearance(const Input& input, const TriangleMesh& mesh, const PolygonTriangulator& polygons,
                       const ObjAppearance& obj, MeshAppearance& appearance)
{
    const size_t corners = mesh.triangles.size() * 3;
    const std::vector<uint32_t>& sources = polygons.cornerSources();
    if (!obj.texcoords.empty()) {
        appearance.cornerUVs.resize(corners, glm::dvec2(0.0));
        for (size_t i = 0; i < corners; ++i) {
            const uint32_t vt = obj.cornerTexcoords[sources[i]];
            if (vt != kNone) appearance.cornerUVs[i] = obj.texcoords[vt];
        }
    }
    if (obj.anyColour) {
        appearance.cornerColors.reserve(corners);
        for (const glm::uvec3& t : mesh.triangles)
            for (int k = 0; k < 3; ++k)
                appearance.cornerColors.push_back(t[k] < obj.vertexColours.size() ? obj.vertexColours[t[k]]
                                                                                  : glm::vec4(1.0f));
    }
    // usemtl names -> materials (the first library definition of a name wins); unknown: default.
    std::vector<int64_t> byName(obj.usedNames.size(), -1);  // index into obj.library
    for (size_t n = 0; n < obj.usedNames.size(); ++n) {
        for (size_t m = 0; m < obj.library.size() && byName[n] < 0; ++m)
            if (obj.library[m].material.name == obj.usedNames[n]) byName[n] = int64_t(m);
        if (byName[n] < 0)
            appearance.warnings.push_back(input.name + ": usemtl '" + obj.usedNames[n] + "' names no material of " +
                                          (obj.readLibraries.empty() ? std::string("any material library (none read)")
                                                                     : "the material libraries read") +
                                          ": its faces get the default material");
    }
    bool anyMaterial = false;
    for (uint32_t n : obj.triangleMaterialName) anyMaterial = anyMaterial || (n != kNone && byName[n] >= 0);
    if (!anyMaterial) return;
    std::map<std::filesystem::path, int32_t> images;
    std::vector<int64_t> materialOf(obj.usedNames.size(), -1);  // usedNames -> appearance.materials
    int64_t defaultMaterial = -1;
    appearance.triangleMaterial.reserve(mesh.triangles.size());
    for (uint32_t n : obj.triangleMaterialName) {
        int64_t& slot = n != kNone && byName[n] >= 0 ? materialOf[n] : defaultMaterial;
        if (slot < 0) {
            slot = int64_t(appearance.materials.size());
            if (&slot == &defaultMaterial) {
                appearance.materials.emplace_back().name = "default";
            } else {
                const MtlMaterial& m = obj.library[size_t(byName[n])];
                const std::filesystem::path& file = obj.libraryFiles[size_t(byName[n])];
                Material material = m.material;
                material.baseColorTexture = loadTexture(input, m.baseColor, file, appearance, images);
                material.normalTexture = loadTexture(input, m.normal, file, appearance, images);
                material.emissiveTexture = loadTexture(input, m.emissive, file, appearance, images);
                appearance.materials.push_back(std::move(material));
            }
        }
        appearance.triangleMaterial.push_back(uint32_t(slot));
    }
}

}  // namespace

TriangleMesh readObj(const Input& input, MeshAppearance* appearance)
{
    const std::span<const uint8_t> bytes = input.bytes;
    if (bytes.size() >= 2 && ((bytes[0] == 0xFF && bytes[1] == 0xFE) || (bytes[0] == 0xFE && bytes[1] == 0xFF)))
        fail(input, "is UTF-16 text; save it as UTF-8");
    const bool utf8Mark = bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF;
    TriangleMesh mesh;
    LineReader lines(input, utf8Mark ? 3 : 0);
    auto lineFail = [&](const std::string& problem) {
        fail(input, "line " + std::to_string(lines.lineNumber()) + ": " + problem);
    };
    struct PendingIndex {  // a positive index, checked once every vertex (or vt) is known
        size_t line;
        long long index;
        bool texcoord;
    };
    std::vector<PendingIndex> forward;  // faces referring to vertices not read yet (lenient)
    std::vector<uint32_t> face;
    PolygonTriangulator polygons(appearance != nullptr);  // triangulated once every vertex is read
    ObjAppearance obj;
    std::string joined;  // a statement continued over several lines
    std::string_view line;
    while (lines.next(line)) {
        if (!line.empty() && line.back() == '\\') {
            joined.assign(line.substr(0, line.size() - 1));
            std::string_view more;
            while (lines.next(more)) {
                const bool continues = !more.empty() && more.back() == '\\';
                joined += ' ';
                joined.append(more.substr(0, more.size() - (continues ? 1 : 0)));
                if (!continues) break;
            }
            line = joined;
        }
        const size_t hash = line.find('#');
        if (hash != std::string_view::npos) line = line.substr(0, hash);
        std::string_view rest = line;
        const std::string_view keyword = nextToken(rest);
        if (keyword == "v") {
            double xyz[3];
            for (double& c : xyz) {
                const std::string_view token = nextToken(rest);
                if (token.empty()) lineFail("vertex has fewer than three coordinates");
                if (!parseDouble(token, c)) lineFail("vertex coordinate '" + std::string(token) + "' is not a number");
                if (!usableCoordinate(c)) lineFail(coordinateProblem(token, c));
            }
            if (mesh.positions.size() >= size_t(UINT32_MAX)) lineFail("more than 2^32-1 vertices");
            mesh.positions.push_back({xyz[0], xyz[1], xyz[2]});
            if (appearance) {  // "v x y z r g b": a colour; "v x y z w": not one
                std::string_view tokens[3];
                for (std::string_view& token : tokens) token = nextToken(rest);
                if (!tokens[2].empty()) {
                    glm::vec4 rgba(1.0f);
                    for (int c = 0; c < 3; ++c) {
                        double value;
                        if (!parseDouble(tokens[c], value) || !std::isfinite(value))
                            lineFail("vertex colour '" + std::string(tokens[c].substr(0, 40)) +
                                     "' is not a finite number");
                        rgba[c] = float(srgbToLinear(value));
                    }
                    obj.vertexColours.resize(mesh.positions.size(), glm::vec4(1.0f));
                    obj.vertexColours.back() = rgba;
                    obj.anyColour = true;
                }
            }
        } else if (keyword == "vt" && appearance) {
            double uv[2] = {0.0, 0.0};
            for (int c = 0; c < 2; ++c) {
                const std::string_view token = nextToken(rest);
                if (token.empty()) {
                    if (c == 0) lineFail("texture coordinate without a value");
                    break;  // "vt u": v is 0
                }
                if (!parseDouble(token, uv[c]))
                    lineFail("texture coordinate '" + std::string(token.substr(0, 40)) + "' is not a number");
                if (!std::isfinite(uv[c]))
                    lineFail("texture coordinate '" + std::string(token.substr(0, 40)) + "' is NaN or infinite");
            }
            if (obj.texcoords.size() >= size_t(UINT32_MAX) - 1) lineFail("more than 2^32-2 texture coordinates");
            obj.texcoords.push_back({uv[0], 1.0 - uv[1]});
        } else if (keyword == "f" || keyword == "fo") {
            face.clear();
            for (std::string_view token = nextToken(rest); !token.empty(); token = nextToken(rest)) {
                const size_t slash = token.find('/');
                const std::string_view vertex = token.substr(0, slash);
                long long index = 0;
                if (!parseInteger(vertex, index)) lineFail("face vertex '" + std::string(token) + "' is not an index");
                if (index == 0) lineFail("face refers to vertex 0 (OBJ indices start at 1)");
                if (index < 0) {  // relative: -1 is the last vertex read
                    if (-index > (long long)mesh.positions.size())
                        lineFail("face refers to vertex " + std::to_string(index) + ", but only " +
                                 std::to_string(mesh.positions.size()) + " vertices precede it");
                    index += (long long)mesh.positions.size() + 1;
                } else if (index > (long long)mesh.positions.size()) {
                    if (index > (long long)UINT32_MAX)
                        lineFail("face refers to vertex " + std::to_string(index) + " (beyond 2^32-1)");
                    forward.push_back({lines.lineNumber(), index, false});
                }
                face.push_back(uint32_t(index - 1));
                if (!appearance) continue;
                // The texture coordinate: between the first and the second '/', if any.
                uint32_t texcoord = kNone;
                if (slash != std::string_view::npos) {
                    std::string_view vt = token.substr(slash + 1);
                    vt = vt.substr(0, vt.find('/'));
                    if (!vt.empty()) {
                        long long t = 0;
                        if (!parseInteger(vt, t) || t == 0)
                            lineFail("face texture coordinate '" + std::string(token) + "' is not an index");
                        if (t < 0) {
                            if (-t > (long long)obj.texcoords.size())
                                lineFail("face refers to texture coordinate " + std::to_string(t) + ", but only " +
                                         std::to_string(obj.texcoords.size()) + " precede it");
                            t += (long long)obj.texcoords.size() + 1;
                        } else if (t > (long long)obj.texcoords.size()) {
                            if (t >= (long long)UINT32_MAX)
                                lineFail("face refers to texture coordinate " + std::to_string(t) + " (beyond 2^32-2)");
                            forward.push_back({lines.lineNumber(), t, true});
                        }
                        texcoord = uint32_t(t - 1);
                    }
                }
                obj.cornerTexcoords.push_back(texcoord);
            }
            if (face.size() < 3)
                lineFail("face with " + std::to_string(face.size()) + " vertices (a face needs at least 3)");
            if (appearance && obj.cornerTexcoords.size() > size_t(UINT32_MAX))
                lineFail("more than 2^32-1 face corners");
            polygons.add(face, mesh);
            if (appearance) obj.triangleMaterialName.resize(mesh.triangles.size(), obj.current);
        } else if (keyword == "usemtl" && appearance) {
            const std::string name(trim(rest));
            auto found = obj.nameIndex.find(name);
            if (found == obj.nameIndex.end()) {
                found = obj.nameIndex.emplace(name, uint32_t(obj.usedNames.size())).first;
                obj.usedNames.push_back(name);
            }
            obj.current = found->second;
        } else if (keyword == "mtllib" && appearance) {
            readLibraries(input, rest, obj, *appearance, lines.where());
        }
    }
    for (const PendingIndex& p : forward) {
        const size_t count = p.texcoord ? obj.texcoords.size() : mesh.positions.size();
        if (p.index > (long long)count)
            fail(input,
                 "line " + std::to_string(p.line) + ": face refers to " +
                     (p.texcoord ? "texture coordinate " : "vertex ") + std::to_string(p.index) +
                     ", but the file has only " + std::to_string(count) +
                     (p.texcoord ? " texture coordinates" : " vertices"));
    }
    polygons.finish(mesh);
    if (mesh.triangles.empty())
        fail(input,
             mesh.positions.empty() ? "no vertices and no faces (is this an OBJ file?)"
                                    : "no faces ('f' lines): the mesh has no triangles");
    if (appearance) resolveAppearance(input, mesh, polygons, obj, *appearance);
    return mesh;
}

}  // namespace ngi::mesh_io
