// ngi offline: the OFF reader (Geomview's format; ASCII and "OFF BINARY").
//
// ASCII: '#' comments anywhere (CGAL's data has them before the header and between
// sections), the [ST][C][N]OFF keyword, the vertex and face counts (on the keyword's line or
// the next), then one vertex per line (its first three numbers; colours or normals after
// them are ignored) and one polygon per line ("n i1 .. in", an optional colour after).
// Binary (Geomview): big-endian int32 counts, float32 vertices (plus the normal, colour and
// texture coordinates the keyword announces), polygons as int32 n, n indices, int32 colour
// count, that many float32.
#include "mesh_io_internal.h"
#include "polygon_triangulation.h"

#include <cstring>
#include <string>
#include <vector>

namespace ngi::mesh_io {
namespace {

struct OffKeyword {
    bool texture = false, colour = false, normal = false;
};

// Parses "[ST][C][N]OFF"; refuses 4OFF and nOFF (not 3D) and anything else.
OffKeyword parseKeyword(const Input& input, std::string_view keyword)
{
    if (keyword.size() < 3 || keyword.substr(keyword.size() - 3) != "OFF")
        fail(input,
             "not an OFF file (no OFF header; the file starts with '" + std::string(keyword.substr(0, 40)) + "')");
    std::string_view prefix = keyword.substr(0, keyword.size() - 3);
    OffKeyword k;
    if (prefix.substr(0, 2) == "ST") k.texture = true, prefix.remove_prefix(2);
    if (!prefix.empty() && prefix.front() == 'C') k.colour = true, prefix.remove_prefix(1);
    if (!prefix.empty() && prefix.front() == 'N') k.normal = true, prefix.remove_prefix(1);
    if (!prefix.empty()) {
        if (prefix.find('4') != std::string_view::npos || prefix.find('n') != std::string_view::npos)
            fail(input, "only 3D OFF is supported (keyword '" + std::string(keyword) + "')");
        fail(input, "unknown OFF keyword '" + std::string(keyword) + "'");
    }
    return k;
}

// Refuses counts beyond 32-bit indices. Returns "" if `remaining` bytes can hold the counts
// (then the caller reserves memory for them), else a note for the truncation message: the
// caller then allocates nothing up front, reads what is there and fails where the file ends,
// so a header that lies costs no more memory than the file holds.
std::string checkCounts(const Input& input, uint64_t vertices, uint64_t faces, size_t remaining, uint64_t vertexBytes,
                        uint64_t faceBytes)
{
    if (vertices > UINT32_MAX)
        fail(input, "header declares " + std::to_string(vertices) + " vertices (more than 2^32-1)");
    if (faces > UINT32_MAX) fail(input, "header declares " + std::to_string(faces) + " faces (more than 2^32-1)");
    // Both below 2^32 and the sizes below 2^7: the sum cannot overflow 64 bits.
    const uint64_t need = vertices * vertexBytes + faces * faceBytes;
    if (need <= remaining) return "";
    return " (the header's counts need at least " + std::to_string(need) + " bytes, " + std::to_string(remaining) +
        " follow the header)";
}

TriangleMesh readBinaryOff(const Input& input, size_t at, const OffKeyword& keyword)
{
    const std::span<const uint8_t> bytes = input.bytes;
    std::string declared = "the counts", note;  // for truncation messages
    auto readU32 = [&](const char* what) -> uint32_t {
        if (bytes.size() - at < 4)
            fail(input, "truncated binary OFF file: " + declared + ", it ends in " + std::string(what) + note);
        const uint32_t v =
            uint32_t(bytes[at]) << 24 | uint32_t(bytes[at + 1]) << 16 | uint32_t(bytes[at + 2]) << 8 | bytes[at + 3];
        at += 4;
        return v;
    };
    auto readFloat = [&](const char* what) {
        const uint32_t bits = readU32(what);
        float f;
        std::memcpy(&f, &bits, 4);
        return f;
    };
    const uint32_t vertexCount = readU32("the counts"), faceCount = readU32("the counts");
    readU32("the counts");  // edges, unused
    declared =
        "header declares " + std::to_string(vertexCount) + " vertices and " + std::to_string(faceCount) + " faces";
    const uint64_t floatsPerVertex =
        3 + (keyword.normal ? 3 : 0) + (keyword.colour ? 4 : 0) + (keyword.texture ? 2 : 0);
    note = checkCounts(input, vertexCount, faceCount, bytes.size() - at, 4 * floatsPerVertex, 4 * (1 + 3 + 1));
    TriangleMesh mesh;
    if (note.empty()) mesh.positions.reserve(vertexCount);
    for (uint32_t v = 0; v < vertexCount; ++v) {
        double xyz[3];
        for (double& c : xyz) c = readFloat("a vertex");
        for (uint64_t k = 3; k < floatsPerVertex; ++k) readFloat("a vertex");
        for (double c : xyz)
            if (!usableCoordinate(c)) fail(input, "vertex " + std::to_string(v) + " has a non-finite coordinate");
        mesh.positions.push_back({xyz[0], xyz[1], xyz[2]});
    }
    std::vector<uint32_t> polygon;
    PolygonTriangulator polygons;
    for (uint32_t f = 0; f < faceCount; ++f) {
        const uint32_t n = readU32("a face");
        if (n < 3)
            fail(input,
                 "face " + std::to_string(f) + " has " + std::to_string(int32_t(n)) +
                     " vertices (a face needs at least 3)");
        polygon.clear();
        for (uint32_t k = 0; k < n; ++k) {
            const uint32_t index = readU32("a face");
            if (index >= vertexCount)
                fail(input,
                     "face " + std::to_string(f) + " refers to vertex " + std::to_string(int32_t(index)) + " of " +
                         std::to_string(vertexCount));
            polygon.push_back(index);
        }
        const uint32_t colours = readU32("a face");
        if (colours > 4)
            fail(input,
                 "face " + std::to_string(f) + " declares " + std::to_string(colours) +
                     " colour components (at most 4)");
        for (uint32_t k = 0; k < colours; ++k) readFloat("a face colour");
        polygons.add(polygon, mesh);
    }
    polygons.finish(mesh);
    return mesh;
}

// The next line that holds more than a comment, without the comment; false at the end.
bool nextContentLine(LineReader& lines, std::string_view& line)
{
    while (lines.next(line)) {
        const size_t hash = line.find('#');
        if (hash != std::string_view::npos) line = line.substr(0, hash);
        if (line.find_first_not_of(" \t\r\f\v") != std::string_view::npos) return true;
    }
    return false;
}

}  // namespace

TriangleMesh readOff(const Input& input)
{
    if (input.bytes.empty()) fail(input, "the file is empty");
    // The header line decides ASCII or binary; it is found without LineReader, which refuses
    // the NUL bytes a binary body has.
    {
        const std::string_view text = input.text();
        size_t at = 0;
        while (at < text.size()) {
            size_t end = text.find('\n', at);
            if (end == std::string_view::npos) end = text.size();
            std::string_view line = text.substr(at, end - at);
            at = end + 1;
            if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
            std::string_view rest = line;
            const std::string_view keyword = nextToken(rest);
            if (keyword.empty()) continue;
            if (nextToken(rest) == "BINARY")
                return readBinaryOff(input, std::min(at, text.size()), parseKeyword(input, keyword));
            break;
        }
    }
    LineReader lines(input);
    std::string_view line;
    if (!nextContentLine(lines, line)) fail(input, "the file holds nothing but comments");
    std::string_view rest = line;
    parseKeyword(input, nextToken(rest));
    uint64_t counts[2];
    const char* names[2] = {"vertex", "face"};
    for (int got = 0; got < 2;) {  // the counts may follow the keyword on its line
        const std::string_view token = nextToken(rest);
        if (token.empty()) {
            if (!nextContentLine(lines, line))
                fail(input, "truncated OFF file: the vertex and face counts are missing");
            rest = line;
            continue;
        }
        if (!parseUnsigned(token, counts[got])) {
            long long value;
            const bool digits = token.find_first_not_of("+-0123456789") == std::string_view::npos;
            fail(input,
                 lines.where() + ": " + names[got] + " count '" + std::string(token.substr(0, 40)) + "' " +
                     (parseInteger(token, value) ? "is negative"
                          : digits               ? "is out of range"
                                                 : "is not a count"));
        }
        ++got;
    }
    // A vertex line is at least "0 0 0\n", a face line at least "3 0 0 0\n".
    const std::string note = checkCounts(input, counts[0], counts[1],
                                         input.bytes.size() - std::min(lines.offset(), input.bytes.size()), 6, 8);
    const size_t vertexCount = size_t(counts[0]), faceCount = size_t(counts[1]);
    TriangleMesh mesh;
    if (note.empty()) mesh.positions.reserve(vertexCount);
    for (size_t v = 0; v < vertexCount; ++v) {
        if (!nextContentLine(lines, line))
            fail(input,
                 "truncated OFF file: header declares " + std::to_string(vertexCount) +
                     " vertices, the file ends after " + std::to_string(v) + note);
        rest = line;
        double xyz[3];
        for (double& c : xyz) {
            const std::string_view token = nextToken(rest);
            if (token.empty())
                fail(input, lines.where() + ": vertex " + std::to_string(v) + " does not have three coordinates");
            if (!parseDouble(token, c))
                fail(input, lines.where() + ": vertex coordinate '" + std::string(token) + "' is not a number");
            if (!usableCoordinate(c)) fail(input, lines.where() + ": " + coordinateProblem(token, c));
        }
        mesh.positions.push_back({xyz[0], xyz[1], xyz[2]});
    }
    if (note.empty()) mesh.triangles.reserve(faceCount);
    std::vector<uint32_t> polygon;
    PolygonTriangulator polygons;
    for (size_t f = 0; f < faceCount; ++f) {
        if (!nextContentLine(lines, line))
            fail(input,
                 "truncated OFF file: header declares " + std::to_string(faceCount) + " faces, the file ends after " +
                     std::to_string(f) + note);
        rest = line;
        const std::string_view countToken = nextToken(rest);
        long long n = 0;
        if (!parseInteger(countToken, n))
            fail(input,
                 lines.where() + ": face " + std::to_string(f) + " has no vertex count ('" + std::string(countToken) +
                     "')");
        if (n < 3)
            fail(input,
                 lines.where() + ": face " + std::to_string(f) + " has " + std::to_string(n) +
                     " vertices (a face needs at least 3)");
        if (size_t(n) > line.size())
            fail(input,
                 lines.where() + ": face " + std::to_string(f) + " has fewer than " + std::to_string(n) + " indices");
        polygon.clear();
        for (long long k = 0; k < n; ++k) {
            const std::string_view token = nextToken(rest);
            long long index;
            if (token.empty())
                fail(input,
                     lines.where() + ": face " + std::to_string(f) + " has fewer than " + std::to_string(n) +
                         " indices");
            if (!parseInteger(token, index))
                fail(input,
                     lines.where() + ": face " + std::to_string(f) + " index '" + std::string(token) +
                         "' is not an integer");
            if (index < 0 || size_t(index) >= vertexCount)
                fail(input,
                     lines.where() + ": face " + std::to_string(f) + " refers to vertex " + std::string(token) +
                         " of " + std::to_string(vertexCount));
            polygon.push_back(uint32_t(index));
        }
        polygons.add(polygon, mesh);
    }
    polygons.finish(mesh);
    return mesh;
}

}  // namespace ngi::mesh_io
