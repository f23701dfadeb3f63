// ngi offline: the PLY reader (ASCII, binary little- and big-endian).
//
// Any elements and properties (scalar or list, every PLY type and its sized alias); the
// vertex element's x, y, z and the face element's vertex_indices (or vertex_index) list are
// kept, and with appearance the vertex colours (red, green, blue and alpha, or diffuse_red
// ...: 8- and 16-bit integers scaled to [0, 1], floats clamped to it; sRGB, alpha linear);
// everything else is read past. A header line with an unknown keyword (some exporters write
// "Created by ...") is skipped: only element, property and format lines describe the body. Before anything is allocated, the header's element
// counts are compared with the bytes that follow it (every element needs at least one byte
// per binary scalar or two per ASCII value), so a header that lies about its size is an
// error naming the file, not an allocation of gigabytes.
#include "mesh_io_internal.h"
#include "ngi/srgb.h"
#include "polygon_triangulation.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

namespace ngi::mesh_io {
namespace {

enum class Type { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

bool parseType(std::string_view name, Type& type)
{
    static const struct {
        const char* name;
        Type type;
    } names[] = {
        {"char", Type::Int8},     {"int8", Type::Int8},       {"uchar", Type::UInt8},    {"uint8", Type::UInt8},
        {"short", Type::Int16},   {"int16", Type::Int16},     {"ushort", Type::UInt16},  {"uint16", Type::UInt16},
        {"int", Type::Int32},     {"int32", Type::Int32},     {"uint", Type::UInt32},    {"uint32", Type::UInt32},
        {"float", Type::Float32}, {"float32", Type::Float32}, {"double", Type::Float64}, {"float64", Type::Float64}};
    for (const auto& n : names)
        if (name == n.name) {
            type = n.type;
            return true;
        }
    return false;
}

size_t sizeOf(Type type)
{
    switch (type) {
    case Type::Int8:
    case Type::UInt8: return 1;
    case Type::Int16:
    case Type::UInt16: return 2;
    case Type::Int32:
    case Type::UInt32:
    case Type::Float32: return 4;
    case Type::Float64: return 8;
    }
    return 1;
}

bool isInteger(Type type) { return type != Type::Float32 && type != Type::Float64; }

// A colour channel as stored to [0, 1]: 16-bit integers over 65535, other integers over 255
// (8-bit, and the 32-bit ints some writers use for 0..255), floats as they are; clamped.
double colourUnit(Type type, double value)
{
    const double unit = !isInteger(type)                ? value
        : (type == Type::Int16 || type == Type::UInt16) ? value / 65535.0
                                                        : value / 255.0;
    return std::clamp(unit, 0.0, 1.0);
}

struct Property {
    std::string name;
    bool list = false;
    Type countType = Type::UInt8;
    Type type = Type::Float32;
};

struct Element {
    std::string name;
    uint64_t count = 0;
    std::vector<Property> properties;
};

// "vertices", "faces", "edge elements": for messages.
std::string plural(const std::string& element)
{
    return element == "vertex" ? "vertices" : element == "face" ? "faces" : element + " elements";
}

enum class Format { Ascii, LittleEndian, BigEndian };

// Reads the body's values one at a time, in ASCII or binary, tracking where it is.
class BodyReader {
public:
    // `line`: the line number the body starts on (for ASCII messages).
    BodyReader(const Input& input, size_t begin, Format format, size_t line)
        : input_(input), at_(begin), format_(format), line_(line)
    {}
    size_t remaining() const { return input_.bytes.size() - at_; }
    // One value of `type`; false at the end of the input. ASCII tokens that are not
    // numbers (or not integers for an integer type) are errors naming the line.
    bool read(Type type, double& value)
    {
        if (format_ == Format::Ascii) return readAscii(type, value);
        const size_t n = sizeOf(type);
        if (remaining() < n) return false;
        uint8_t raw[8];
        std::memcpy(raw, input_.bytes.data() + at_, n);
        at_ += n;
        const bool bigEndianHost = std::endian::native == std::endian::big;
        if ((format_ == Format::BigEndian) != bigEndianHost) std::reverse(raw, raw + n);
        switch (type) {
        case Type::Int8: {
            int8_t v;
            std::memcpy(&v, raw, 1);
            value = v;
            break;
        }
        case Type::UInt8: value = raw[0]; break;
        case Type::Int16: {
            int16_t v;
            std::memcpy(&v, raw, 2);
            value = v;
            break;
        }
        case Type::UInt16: {
            uint16_t v;
            std::memcpy(&v, raw, 2);
            value = v;
            break;
        }
        case Type::Int32: {
            int32_t v;
            std::memcpy(&v, raw, 4);
            value = v;
            break;
        }
        case Type::UInt32: {
            uint32_t v;
            std::memcpy(&v, raw, 4);
            value = v;
            break;
        }
        case Type::Float32: {
            float v;
            std::memcpy(&v, raw, 4);
            value = v;
            break;
        }
        case Type::Float64: std::memcpy(&value, raw, 8); break;
        }
        return true;
    }
    std::string where() const { return format_ == Format::Ascii ? "line " + std::to_string(line_) + ": " : ""; }

private:
    bool readAscii(Type type, double& value)
    {
        const std::string_view text = input_.text();
        while (at_ < text.size() && (text[at_] == ' ' || text[at_] == '\t' || text[at_] == '\r' || text[at_] == '\n')) {
            if (text[at_] == '\n') ++line_;
            ++at_;
        }
        if (at_ >= text.size()) return false;
        size_t end = at_;
        while (end < text.size() && text[end] != ' ' && text[end] != '\t' && text[end] != '\r' && text[end] != '\n')
            ++end;
        const std::string_view token = text.substr(at_, end - at_);
        at_ = end;
        long long integer;
        if (isInteger(type)) {
            if (!parseInteger(token, integer))
                fail(input_, where() + "'" + std::string(token.substr(0, 40)) + "' is not an integer");
            value = double(integer);
        } else if (!parseDouble(token, value)) {
            fail(input_, where() + "'" + std::string(token.substr(0, 40)) + "' is not a number");
        }
        return true;
    }

    const Input& input_;
    size_t at_;
    Format format_;
    size_t line_;
};

}  // namespace

TriangleMesh readPly(const Input& input, MeshAppearance* appearance)
{
    const std::string_view text = input.text();
    if (text.empty()) fail(input, "the file is empty");
    // ---- header (text, even in binary files; found line by line up to end_header)
    size_t at = 0, lineNumber = 0;
    auto nextHeaderLine = [&](std::string_view& line) {
        if (at >= text.size()) return false;
        size_t end = text.find('\n', at);
        if (end == std::string_view::npos) end = text.size();
        line = text.substr(at, end - at);
        if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
        at = end + 1;
        ++lineNumber;
        return true;
    };
    auto headerFail = [&](const std::string& problem) {
        fail(input, "PLY header line " + std::to_string(lineNumber) + ": " + problem);
    };
    std::string_view line;
    if (!nextHeaderLine(line) || line != "ply") fail(input, "not a PLY file (it does not start with 'ply')");
    std::optional<Format> format;
    std::vector<Element> elements;
    bool ended = false;
    while (!ended && nextHeaderLine(line)) {
        if (line.find('\0') != std::string_view::npos)
            headerFail("NUL byte in the header (binary data before end_header?)");
        std::string_view rest = line;
        const std::string_view keyword = nextToken(rest);
        if (keyword == "format") {
            const std::string_view name = nextToken(rest), version = nextToken(rest);
            if (name == "ascii")
                format = Format::Ascii;
            else if (name == "binary_little_endian")
                format = Format::LittleEndian;
            else if (name == "binary_big_endian")
                format = Format::BigEndian;
            else
                headerFail("unknown format '" + std::string(name) + "'");
            if (version != "1.0") headerFail("unsupported PLY version '" + std::string(version) + "'");
        } else if (keyword == "element") {
            Element element;
            element.name = std::string(nextToken(rest));
            const std::string_view count = nextToken(rest);
            if (element.name.empty() || !parseUnsigned(count, element.count))
                headerFail("element '" + element.name + "' has no valid count ('" + std::string(count.substr(0, 40)) +
                           "')");
            elements.push_back(std::move(element));
        } else if (keyword == "property") {
            if (elements.empty()) headerFail("property before any element");
            Property property;
            std::string_view type = nextToken(rest);
            if (type == "list") {
                property.list = true;
                const std::string_view countType = nextToken(rest);
                if (!parseType(countType, property.countType) || !isInteger(property.countType))
                    headerFail("list count type '" + std::string(countType) + "' is not an integer type");
                type = nextToken(rest);
            }
            if (!parseType(type, property.type)) headerFail("unknown property type '" + std::string(type) + "'");
            property.name = std::string(nextToken(rest));
            if (property.name.empty()) headerFail("property without a name");
            elements.back().properties.push_back(std::move(property));
        } else if (keyword == "end_header") {
            ended = true;
        } else if (keyword != "comment" && keyword != "obj_info" && !keyword.empty() && appearance) {
            appearance->warnings.push_back(input.name + ": PLY header line " + std::to_string(lineNumber) +
                                           ": unknown keyword '" + std::string(keyword.substr(0, 40)) + "' skipped");
        }
    }
    if (!ended) fail(input, "truncated PLY file: the header has no end_header");
    if (!format) fail(input, "PLY header has no format line");
    const size_t bodyBegin = std::min(at, text.size());

    // ---- the declared sizes against the bytes there, before allocating: if they cannot fit,
    // nothing is reserved, the body is read as far as it goes and the truncation message
    // carries this note (a header that lies costs no more memory than the file holds).
    const Element* vertexElement = nullptr;
    const Element* faceElement = nullptr;
    int x = -1, y = -1, z = -1, indices = -1;
    int colour[4] = {-1, -1, -1, -1};  // red, green, blue, alpha properties of the vertex element
    const size_t body = text.size() - bodyBegin;
    uint64_t need = 0;
    std::string note;
    for (const Element& element : elements) {
        uint64_t least = 0;
        for (const Property& p : element.properties)
            least += *format == Format::Ascii ? 2 : sizeOf(p.list ? p.countType : p.type);
        if (note.empty() && least && element.count > (body - std::min<uint64_t>(need, body)) / least)
            note = " (the header's " + std::to_string(element.count) + " " + plural(element.name) + " need at least " +
                std::to_string(least) + " bytes each, " + std::to_string(body) + " bytes follow the header)";
        if (note.empty()) need += element.count * least;
        if (element.name == "vertex") {
            if (vertexElement) fail(input, "PLY header declares two vertex elements");
            vertexElement = &element;
            for (size_t k = 0; k < element.properties.size(); ++k) {
                const Property& p = element.properties[k];
                if (p.list) continue;
                if (p.name == "x") x = int(k);
                if (p.name == "y") y = int(k);
                if (p.name == "z") z = int(k);
                static const char* channels[4] = {"red", "green", "blue", "alpha"};
                for (int c = 0; c < 4; ++c)
                    if (p.name == channels[c] || p.name == std::string("diffuse_") + channels[c]) colour[c] = int(k);
            }
        } else if (element.name == "face") {
            if (faceElement) fail(input, "PLY header declares two face elements");
            faceElement = &element;
            for (size_t k = 0; k < element.properties.size(); ++k)
                if (element.properties[k].list &&
                    (element.properties[k].name == "vertex_indices" || element.properties[k].name == "vertex_index")) {
                    indices = int(k);
                    break;
                }
        }
    }
    if (!vertexElement) fail(input, "PLY header declares no vertex element");
    if (x < 0 || y < 0 || z < 0) fail(input, "PLY vertex element lacks an x, y or z property");
    if (!faceElement || faceElement->count == 0) fail(input, "PLY header declares no faces: the mesh has no triangles");
    if (indices < 0) fail(input, "PLY face element has no vertex_indices list");
    if (vertexElement->count > UINT32_MAX) fail(input, "PLY header declares more than 2^32-1 vertices");
    bool colours = appearance && (colour[0] >= 0 || colour[1] >= 0 || colour[2] >= 0);
    if (colours && (colour[0] < 0 || colour[1] < 0 || colour[2] < 0)) {
        appearance->warnings.push_back(
            input.name + ": PLY vertex colours ignored: the vertex element lacks a red, green or blue property");
        colours = false;
    }
    std::vector<glm::vec4> vertexColours;  // per vertex, linear

    // ---- body
    TriangleMesh mesh;
    if (note.empty()) {
        mesh.positions.reserve(size_t(vertexElement->count));
        mesh.triangles.reserve(size_t(faceElement->count));
        if (colours) vertexColours.reserve(size_t(vertexElement->count));
    }
    BodyReader reader(input, bodyBegin, *format, lineNumber + 1);
    std::vector<uint32_t> polygon;
    PolygonTriangulator polygons;  // the vertex element may follow the faces
    for (const Element& element : elements) {
        const bool isVertex = &element == vertexElement, isFace = &element == faceElement;
        // An element without properties holds no bytes, however many it declares: counting
        // through 2^32 of them read nothing and hung the reader (found by mesh_ply_fuzzer).
        if (element.properties.empty()) continue;
        for (uint64_t e = 0; e < element.count; ++e) {
            auto truncated = [&] {
                fail(input,
                     "truncated PLY file: header declares " + std::to_string(element.count) + " " +
                         plural(element.name) + ", the file ends after " + std::to_string(e) + note);
            };
            glm::dvec3 position(0.0);
            glm::vec4 rgba(1.0f);
            for (size_t k = 0; k < element.properties.size(); ++k) {
                const Property& p = element.properties[k];
                double value;
                if (!reader.read(p.list ? p.countType : p.type, value)) truncated();
                if (!p.list) {
                    if (isVertex && (int(k) == x || int(k) == y || int(k) == z)) {
                        if (!usableCoordinate(value))
                            fail(input,
                                 reader.where() + "vertex " + std::to_string(e) + " has a " +
                                     coordinateProblem(std::to_string(value), value));
                        position[int(k) == x ? 0 : int(k) == y ? 1 : 2] = value;
                    } else if (isVertex && colours) {
                        for (int c = 0; c < 4; ++c)
                            if (int(k) == colour[c]) {
                                if (!std::isfinite(value))
                                    fail(input,
                                         reader.where() + "vertex " + std::to_string(e) +
                                             " has a NaN or infinite colour");
                                const double unit = colourUnit(p.type, value);
                                rgba[c] = c < 3 ? float(srgbToLinear(unit)) : float(unit);
                            }
                    }
                    continue;
                }
                const double n = value;
                if (n < 0)
                    fail(input,
                         reader.where() + element.name + " " + std::to_string(e) + " declares a list of " +
                             std::to_string((long long)n) + " values");
                const bool keep = isFace && int(k) == indices;
                if (keep) {
                    if (n < 3)
                        fail(input,
                             reader.where() + "face " + std::to_string(e) + " has " + std::to_string((long long)n) +
                                 " vertices (a face needs at least 3)");
                    polygon.clear();
                }
                for (size_t i = 0; i < size_t(n); ++i) {
                    double item;
                    if (!reader.read(p.type, item)) truncated();
                    if (!keep) continue;
                    if (!(item >= 0 && item < double(vertexElement->count)) || item != double(uint32_t(item)))
                        fail(input,
                             reader.where() + "face " + std::to_string(e) + " refers to vertex " +
                                 std::to_string((long long)item) + " of " + std::to_string(vertexElement->count));
                    polygon.push_back(uint32_t(item));
                }
                if (keep) polygons.add(polygon, mesh);
            }
            if (isVertex) mesh.positions.push_back(position);
            if (isVertex && colours) vertexColours.push_back(rgba);
        }
    }
    polygons.finish(mesh);
    if (colours) {  // per corner from its vertex
        appearance->cornerColors.reserve(mesh.triangles.size() * 3);
        for (const glm::uvec3& t : mesh.triangles)
            for (int k = 0; k < 3; ++k) appearance->cornerColors.push_back(vertexColours[t[k]]);
    }
    return mesh;
}

}  // namespace ngi::mesh_io
