// ngi offline: what the per-format mesh readers share (private to ngi_mesh).
//
// Every reader parses bytes already in memory (readMesh reads the file first), so a reader
// never sees a file change under it, can compare every count a header declares against the
// bytes that are really there BEFORE allocating, and can be fed a buffer by the fuzz
// targets. Every problem is one ngi::Error whose message starts with the input's name.
#pragma once

#include "ngi/mesh/appearance.h"
#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ngi::mesh_io {

// One input to parse: its bytes, the name messages start with, and the directory its
// relative references (glTF buffer and image URIs, OBJ material libraries and textures)
// resolve against; none for a memory buffer, and then only embedded data is read.
struct Input {
    std::span<const uint8_t> bytes;
    std::string name;
    std::optional<std::filesystem::path> directory;

    std::string_view text() const { return {reinterpret_cast<const char*>(bytes.data()), bytes.size()}; }
};

// Throws ngi::Error "<name>: <problem>".
[[noreturn]] void fail(const Input& input, const std::string& problem);

// Per format: parse the whole input or throw. Polygons become triangles by
// PolygonTriangulator (polygon_triangulation.h); positions are
// not yet checked for being finite (readMesh does that for every format once, as a backstop
// to the readers' own per-line messages). With `appearance` (not null, empty on entry) the
// readers that know appearance fill it as appearance.h defines (textures decoded); without
// it they read geometry only and open no other file than glTF buffers.
TriangleMesh readObj(const Input& input, MeshAppearance* appearance);
TriangleMesh readOff(const Input& input);
TriangleMesh readPly(const Input& input, MeshAppearance* appearance);
TriangleMesh readStl(const Input& input);
TriangleMesh readGltf(const Input& input, bool binary, MeshAppearance* appearance);

// ---------------------------------------------------------------- files a mesh refers to

// True when `path` (absolute, or relative to the working directory) lies in `directory`
// (absolute, normalized) or below it. Lexical: "..", absolute paths and other roots leave it.
bool insideDirectory(const std::filesystem::path& directory, const std::filesystem::path& path);

// The input's directory, absolute and normalized without a trailing separator; throws naming
// the input if it cannot be resolved. Only for an input with a directory.
std::filesystem::path meshDirectory(const Input& input);

// A file the mesh refers to: `reference` as the mesh (or its MTL file) writes it (relative;
// '/' or '\' separates directories), resolved against `base` (the mesh's directory or one
// below it). Throws one ngi::Error naming the input, `what` ("material library", "texture")
// and the reference when the mesh was read from memory or the file lies outside the mesh's
// directory.
std::filesystem::path referencedFile(const Input& input, const std::filesystem::path& base, std::string_view reference,
                                     const std::string& what);

// The bytes of a referenced file (referencedFile's path); one ngi::Error naming the input,
// `what` and the file when it is missing or cannot be read.
std::vector<uint8_t> readReferencedFile(const Input& input, const std::filesystem::path& path, const std::string& what);

// ---------------------------------------------------------------- text helpers

// Reads a text input line by line (LF or CRLF; the last line may lack its newline) and
// counts lines from 1 for messages. A NUL byte is refused: no text mesh format has one, and
// it is the cheap sign that a binary file was given a text format's extension.
class LineReader {
public:
    explicit LineReader(const Input& input, size_t offset = 0);
    // Next line without its line ending; false at the end of the input.
    bool next(std::string_view& line);
    size_t lineNumber() const { return line_; }
    size_t offset() const { return at_; }  // byte offset of the next line
    std::string where() const { return "line " + std::to_string(line_); }

private:
    const Input& input_;
    std::string_view text_;
    size_t at_ = 0;
    size_t line_ = 0;
};

// Splits off the next whitespace-separated token of `rest` (empty when none is left).
std::string_view nextToken(std::string_view& rest);

// Parses a whole token as a number; false if the token is not one (or out of range for
// integers). Doubles accept a leading '+' and "nan"/"inf" (callers reject non-finite values
// with their own message).
bool parseDouble(std::string_view token, double& value);
bool parseInteger(std::string_view token, long long& value);
bool parseUnsigned(std::string_view token, uint64_t& value);

// A coordinate every later stage can use: finite, and within single precision (geometry
// images store floats; 1e39 would become infinity there).
bool usableCoordinate(double value);
// "non-finite coordinate 'nan'", "... '1e39' (beyond single precision)": for an unusable one.
std::string coordinateProblem(std::string_view token, double value);

}  // namespace ngi::mesh_io
