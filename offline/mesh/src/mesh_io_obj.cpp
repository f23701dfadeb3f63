// ngi offline: the Wavefront OBJ reader.
//
// Reads `v` (the first three numbers; a w or colour after them is ignored) and `f` (a/b/c,
// a//c, negative indices relative to the vertices read so far; polygon_triangulation.h).
// Every other statement (vt, vn, o, g, s, usemtl, mtllib, l, p, ...) is skipped. A line
// ending in '\' continues on the next one.
#include "mesh_io_internal.h"
#include "polygon_triangulation.h"

#include <string>
#include <vector>

namespace ngi::mesh_io {

TriangleMesh readObj(const Input& input) {
    TriangleMesh mesh;
    LineReader lines(input);
    auto lineFail = [&](const std::string& problem) { fail(input, "line " + std::to_string(lines.lineNumber()) + ": " + problem); };
    struct PendingIndex {  // a positive index, checked once every vertex is known
        size_t line;
        long long index;
    };
    std::vector<PendingIndex> forward;  // faces referring to vertices not read yet (lenient)
    std::vector<uint32_t> face;
    PolygonTriangulator polygons;  // triangulated once every vertex is read
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
        } else if (keyword == "f" || keyword == "fo") {
            face.clear();
            for (std::string_view token = nextToken(rest); !token.empty(); token = nextToken(rest)) {
                const std::string_view vertex = token.substr(0, token.find('/'));
                long long index = 0;
                if (!parseInteger(vertex, index)) lineFail("face vertex '" + std::string(token) + "' is not an index");
                if (index == 0) lineFail("face refers to vertex 0 (OBJ indices start at 1)");
                if (index < 0) {  // relative: -1 is the last vertex read
                    if (-index > (long long)mesh.positions.size())
                        lineFail("face refers to vertex " + std::to_string(index) + ", but only " +
                                 std::to_string(mesh.positions.size()) + " vertices precede it");
                    index += (long long)mesh.positions.size() + 1;
                } else if (index > (long long)mesh.positions.size()) {
                    if (index > (long long)UINT32_MAX) lineFail("face refers to vertex " + std::to_string(index) + " (beyond 2^32-1)");
                    forward.push_back({lines.lineNumber(), index});
                }
                face.push_back(uint32_t(index - 1));
            }
            if (face.size() < 3) lineFail("face with " + std::to_string(face.size()) + " vertices (a face needs at least 3)");
            polygons.add(face, mesh);
        }
    }
    for (const PendingIndex& p : forward)
        if (p.index > (long long)mesh.positions.size())
            fail(input, "line " + std::to_string(p.line) + ": face refers to vertex " + std::to_string(p.index) + ", but the file has only " +
                            std::to_string(mesh.positions.size()) + " vertices");
    polygons.finish(mesh);
    if (mesh.triangles.empty())
        fail(input, mesh.positions.empty() ? "no vertices and no faces (is this an OBJ file?)" : "no faces ('f' lines): the mesh has no triangles");
    return mesh;
}

} // namespace ngi::mesh_io
