// ngi offline: the STL reader (ASCII and binary).
//
// STL stores every triangle with its own three corners; corners at exactly the same
// position are merged into one vertex (in the order they first appear), so the cleaning
// stage sees the connectivity. Binary or ASCII: a file whose size is exactly 84 + 50 n for
// the n at offset 80 is binary (binary headers may start with "solid" too); otherwise one
// that starts with "solid" and holds no NUL byte is ASCII; anything else is binary, and a
// size that does not match its triangle count is an error saying so.
#include "mesh_io_internal.h"

#include <bit>
#include <cstring>
#include <string>
#include <unordered_map>

namespace ngi::mesh_io {
namespace {

struct PositionHash {
    size_t operator()(const glm::dvec3& p) const
    {
        uint64_t h = 1469598103934665603ull;
        for (int c = 0; c < 3; ++c) {
            const double v = p[c] == 0.0 ? 0.0 : p[c];  // -0 and +0 are one position
            uint64_t bits;
            std::memcpy(&bits, &v, 8);
            h = (h ^ bits) * 1099511628211ull;
        }
        return size_t(h ^ (h >> 29));
    }
};

// Merges exactly equal corners into vertices.
class Welder {
public:
    explicit Welder(TriangleMesh& mesh) : mesh_(mesh) {}
    uint32_t vertex(const glm::dvec3& p)
    {
        const auto [it, inserted] = index_.try_emplace(p, uint32_t(mesh_.positions.size()));
        if (inserted) mesh_.positions.push_back(p);
        return it->second;
    }

private:
    TriangleMesh& mesh_;
    std::unordered_map<glm::dvec3, uint32_t, PositionHash> index_;
};

TriangleMesh readBinaryStl(const Input& input)
{
    const std::span<const uint8_t> bytes = input.bytes;
    if (bytes.size() < 84)
        fail(input,
             "truncated binary STL file: " + std::to_string(bytes.size()) + " bytes, less than the 84-byte header");
    uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
    // Trailing bytes after the triangles are tolerated (some exporters pad); too few are not.
    if (uint64_t(count) * 50 > bytes.size() - 84)
        fail(input,
             "truncated binary STL file: header declares " + std::to_string(count) + " triangles (" +
                 std::to_string(84 + uint64_t(count) * 50) + " bytes), the file has " + std::to_string(bytes.size()) +
                 " bytes (" + std::to_string((bytes.size() - 84) / 50) + " triangles)");
    if (count == 0) fail(input, "binary STL file declares 0 triangles: the mesh has no triangles");
    TriangleMesh mesh;
    mesh.triangles.reserve(count);
    Welder welder(mesh);
    for (uint32_t t = 0; t < count; ++t) {
        const uint8_t* record = bytes.data() + 84 + size_t(t) * 50;
        uint32_t corners[3];
        for (int k = 0; k < 3; ++k) {
            glm::dvec3 p;
            for (int c = 0; c < 3; ++c) {
                uint32_t bits;
                std::memcpy(&bits, record + 12 + 12 * k + 4 * c, 4);
                if constexpr (std::endian::native == std::endian::big) bits = __builtin_bswap32(bits);
                float f;
                std::memcpy(&f, &bits, 4);
                if (!usableCoordinate(f))
                    fail(input, "triangle " + std::to_string(t) + " has a non-finite (NaN or infinite) coordinate");
                p[c] = f;
            }
            corners[k] = welder.vertex(p);
        }
        mesh.triangles.push_back({corners[0], corners[1], corners[2]});
    }
    return mesh;
}

TriangleMesh readAsciiStl(const Input& input)
{
    LineReader lines(input);
    std::string_view line, rest;
    // The next token, across lines; empty at the end of the input.
    auto token = [&]() -> std::string_view {
        for (;;) {
            const std::string_view t = nextToken(rest);
            if (!t.empty()) return t;
            if (!lines.next(line)) return {};
            rest = line;
        }
    };
    auto where = [&] { return lines.where() + ": "; };
    TriangleMesh mesh;
    Welder welder(mesh);
    size_t facets = 0;
    std::string solid;  // the open solid's name, for messages
    bool inSolid = false;
    auto expect = [&](std::string_view keyword, const char* context) {
        const std::string_view t = token();
        if (t.empty())
            fail(input,
                 "truncated ASCII STL file: it ends " + std::string(context) + " of facet " +
                     std::to_string(facets + 1) + " (" +
                     (keyword[0] == '<' ? "" : "expected '" + std::string(keyword) + "'; ") + std::to_string(facets) +
                     " complete facets)");
        if (t != keyword)
            fail(input,
                 where() + "expected '" + std::string(keyword) + "', found '" + std::string(t.substr(0, 40)) + "'");
    };
    for (;;) {
        const std::string_view t = token();
        if (t.empty()) break;
        if (!inSolid) {
            if (t != "solid") fail(input, where() + "expected 'solid', found '" + std::string(t.substr(0, 40)) + "'");
            solid = std::string(nextToken(rest).substr(0, 60));  // the name's first word, for messages
            rest = {};
            inSolid = true;
            continue;
        }
        if (t == "endsolid") {
            rest = {};  // an optional name follows
            inSolid = false;
            continue;
        }
        if (t != "facet")
            fail(input, where() + "expected 'facet' or 'endsolid', found '" + std::string(t.substr(0, 40)) + "'");
        expect("normal", "inside the header");
        for (int c = 0; c < 3; ++c) {
            const std::string_view n = token();
            double unused;
            if (n.empty()) expect("<number>", "inside the normal");
            if (!parseDouble(n, unused))
                fail(input, where() + "facet normal '" + std::string(n.substr(0, 40)) + "' is not a number");
        }
        expect("outer", "before the loop");
        expect("loop", "before the loop");
        uint32_t corners[3];
        for (int k = 0; k < 3; ++k) {
            expect("vertex", "inside the loop");
            glm::dvec3 p;
            for (int c = 0; c < 3; ++c) {
                const std::string_view v = token();
                if (v.empty()) expect("<number>", "inside a vertex");
                if (!parseDouble(v, p[c]))
                    fail(input, where() + "vertex coordinate '" + std::string(v.substr(0, 40)) + "' is not a number");
                if (!usableCoordinate(p[c])) fail(input, where() + coordinateProblem(v, p[c]));
            }
            corners[k] = welder.vertex(p);
        }
        expect("endloop", "inside the loop");
        expect("endfacet", "at the end");
        mesh.triangles.push_back({corners[0], corners[1], corners[2]});
        ++facets;
    }
    if (inSolid)
        fail(input,
             "truncated ASCII STL file: solid '" + solid + "' has no endsolid (the file ends after " +
                 std::to_string(facets) + " facets)");
    if (facets == 0) fail(input, "ASCII STL file without facets: the mesh has no triangles");
    return mesh;
}

}  // namespace

TriangleMesh readStl(const Input& input)
{
    const std::span<const uint8_t> bytes = input.bytes;
    if (bytes.empty()) fail(input, "the file is empty");
    if (bytes.size() >= 84) {
        uint32_t count;
        std::memcpy(&count, bytes.data() + 80, 4);
        if constexpr (std::endian::native == std::endian::big) count = __builtin_bswap32(count);
        if (84 + uint64_t(count) * 50 == bytes.size()) return readBinaryStl(input);
    }
    const std::string_view text = input.text();
    const size_t first = text.find_first_not_of(" \t\r\n");
    const bool solid = first != std::string_view::npos && text.substr(first, 5) == "solid";
    if (solid && std::memchr(bytes.data(), 0, bytes.size()) == nullptr) return readAsciiStl(input);
    return readBinaryStl(input);
}

}  // namespace ngi::mesh_io
