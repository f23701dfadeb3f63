// Mesh IO against hostile and odd inputs: every reader turns every bad file into
// one ngi::Error that starts with the file and names the problem, and valid-but-odd files
// (CRLF, no final newline, negative OBJ indices, binary PLY with extra elements, STL headers
// that start with "solid") still read. Every input is written by the test itself.
#include "ngi/error.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/procedural_meshes.h"

#include <draco/core/decoder_buffer.h>
#include <dlfcn.h>
#include <sys/resource.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

// AddressSanitizer reserves terabytes of shadow memory: no address-space cap under it.
#if defined(__SANITIZE_ADDRESS__)
#define NGI_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define NGI_TEST_ASAN 1
#endif
#endif

namespace {

class MeshIoHostile : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_mesh_io_hostile_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path write(const std::string& name, const std::string& bytes) const
    {
        const fs::path path = dir_ / name;
        fs::create_directories(path.parent_path());
        std::ofstream(path, std::ios::binary) << bytes;
        return path;
    }
    // The message of the ngi::Error reading `name` throws; it must start with the path.
    std::string error(const std::string& name) const
    {
        const fs::path path = dir_ / name;
        try {
            ngi::readMesh(path);
        } catch (const ngi::Error& e) {
            const std::string message = e.what();
            EXPECT_EQ(message.rfind(path.string() + ": ", 0), 0u) << "does not start with the file: " << message;
            return message;
        }
        ADD_FAILURE() << name << " was read without an error";
        return "";
    }
    fs::path dir_;
};

#define EXPECT_CONTAINS(text, part) EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

std::string base64(const std::string& bytes)
{
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const size_t n = std::min<size_t>(3, bytes.size() - i);  // bytes in this group
        uint32_t v = 0;
        for (size_t k = 0; k < 3; ++k) v = v << 8 | (k < n ? uint8_t(bytes[i + k]) : 0u);
        for (size_t k = 0; k < 4; ++k) out += k <= n ? table[(v >> (18 - 6 * k)) & 63] : '=';
    }
    return out;
}

std::string floats(std::initializer_list<float> values)
{
    std::string out;
    for (float f : values) out.append(reinterpret_cast<const char*>(&f), 4);
    return out;
}

std::string u32(uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

const std::string kTriangle = floats({0, 0, 0, 1, 0, 0, 0, 1, 0});

// A one-triangle glTF: `accessor` and `view` are the JSON of accessor 0 and buffer view 0,
// `buffer` the JSON of buffer 0.
std::string gltfJson(const std::string& accessor, const std::string& view, const std::string& buffer)
{
    return R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"accessors":[)" +
        accessor + R"(],"bufferViews":[)" + view + R"(],"buffers":[)" + buffer + "]}";
}

std::string dataUri(const std::string& bytes)
{
    return R"({"byteLength":)" + std::to_string(bytes.size()) + R"(,"uri":"data:application/octet-stream;base64,)" +
        base64(bytes) + "\"}";
}

std::string glb(std::string json, std::string bin)
{
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    return "glTF" + u32(2) + u32(uint32_t(12 + 8 + json.size() + 8 + bin.size())) + u32(uint32_t(json.size())) +
        "JSON" + json + u32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
}

const char* kTriangleAccessor =
    R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]})";

// ---------------------------------------------------------------- glTF / GLB

// Finding: count 2^60+1 with byteStride 16 wrapped (count - 1) * stride in the bounds check
// and ngi-bake read far past the buffer (SIGSEGV).
TEST_F(MeshIoHostile, GltfAccessorWhoseSizeWrapsIsRejectedNamingTheAccessor)
{
    const std::string buffer = floats({0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0});  // 48 bytes
    const std::string wrapping = R"({"bufferView":0,"componentType":5126,"count":1152921504606846977,"type":"VEC3"})";
    const std::string view = R"({"buffer":0,"byteLength":48,"byteStride":16})";
    write("wrap.gltf", gltfJson(wrapping, view, dataUri(buffer)));
    std::string message = error("wrap.gltf");
    EXPECT_CONTAINS(message, "accessor 0");
    EXPECT_CONTAINS(message, "count 1152921504606846977");
    EXPECT_CONTAINS(message, "reaches past the end");
    write("wrap.glb", glb(gltfJson(wrapping, view, R"({"byteLength":48})"), buffer));
    EXPECT_CONTAINS(error("wrap.glb"), "accessor 0");
    // The same stride with the count that fits reads: 3 elements of 16 bytes in 48.
    write("fits.gltf",
          gltfJson(R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]})", view,
                   dataUri(buffer)));
    EXPECT_EQ(ngi::readMesh(dir_ / "fits.gltf").positions[1], glm::dvec3(1, 0, 0));  // bytes 16..27
}

TEST_F(MeshIoHostile, GltfOffsetsStridesAndViewsOutsideTheBufferAreRejected)
{
    const std::string buffer = dataUri(kTriangle);
    struct Case {
        const char* name;
        std::string accessor, view, expected;
    } cases[] = {
        {"view_offset", kTriangleAccessor, R"({"buffer":0,"byteOffset":18446744073709551600,"byteLength":36})",
         "reaches past the end of its buffer"},
        {"view_length", kTriangleAccessor, R"({"buffer":0,"byteLength":18446744073709551615})",
         "reaches past the end of its buffer"},
        {"accessor_offset",
         R"({"bufferView":0,"byteOffset":18446744073709551612,"componentType":5126,"count":3,"type":"VEC3"})",
         R"({"buffer":0,"byteLength":36})", "past the end of buffer view 0"},
        {"small_stride", kTriangleAccessor, R"({"buffer":0,"byteLength":36,"byteStride":4})",
         "less than its element size"},
        {"count", R"({"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"})", R"({"buffer":0,"byteLength":36})",
         "reaches past the end"},
        {"no_view", R"({"bufferView":7,"componentType":5126,"count":3,"type":"VEC3"})",
         R"({"buffer":0,"byteLength":36})", "no buffer view"},
        {"no_buffer", kTriangleAccessor, R"({"buffer":3,"byteLength":36})", "buffer 3 does not exist"},
    };
    for (const Case& c : cases) {
        write(std::string(c.name) + ".gltf", gltfJson(c.accessor, c.view, buffer));
        const std::string message = error(std::string(c.name) + ".gltf");
        EXPECT_CONTAINS(message, c.expected);
        EXPECT_CONTAINS(message, "accessor 0");
    }
}

TEST_F(MeshIoHostile, GltfIndicesOutOfRangeCyclesAndSharedNodesAreRejected)
{
    const std::string indices = std::string("\0\0\1\0\7\0\0\0", 8);  // u16 0, 1, 7 (+ pad)
    std::string json = R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
      "accessors":[)" +
        std::string(kTriangleAccessor) + R"(,{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],
      "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],"buffers":[{"byteLength":44}]})";
    write("index.glb", glb(json, kTriangle + indices));
    EXPECT_CONTAINS(error("index.glb"), "refers to vertex 7 of 3");
    // Node 0 -> 1 -> 0 (a cycle) and node 0 -> 1, 1 twice (a shared child: a small file could
    // instance a mesh 2^depth times).
    const std::string accessor = kTriangleAccessor, view = R"({"buffer":0,"byteLength":36})",
                      buffer = dataUri(kTriangle);
    std::string cycle = gltfJson(accessor, view, buffer);
    cycle.replace(cycle.find(R"("nodes":[{"mesh":0}])"), std::strlen(R"("nodes":[{"mesh":0}])"),
                  R"("nodes":[{"mesh":0,"children":[1]},{"children":[0]}])");
    write("cycle.gltf", cycle);
    EXPECT_CONTAINS(error("cycle.gltf"), "reached twice");
    std::string shared = gltfJson(accessor, view, buffer);
    shared.replace(shared.find(R"("nodes":[{"mesh":0}])"), std::strlen(R"("nodes":[{"mesh":0}])"),
                   R"("nodes":[{"children":[1,1]},{"mesh":0}])");
    write("shared.gltf", shared);
    EXPECT_CONTAINS(error("shared.gltf"), "reached twice");
}

// Finding: a buffer URI of ../../../../etc/passwd (or an absolute path) was opened outside the
// directory of the mesh. Files beside the mesh and below it still read.
TEST_F(MeshIoHostile, GltfBufferUrisMayNotLeaveTheMeshDirectory)
{
    write("outside.bin", kTriangle);  // a valid buffer, one level above the mesh
    write("mesh/sub/inside.bin", kTriangle);
    const std::string accessor = kTriangleAccessor, view = R"({"buffer":0,"byteLength":36})";
    auto withUri = [&](const std::string& uri) {
        return gltfJson(accessor, view, R"({"byteLength":36,"uri":")" + uri + "\"}");
    };
    write("mesh/inside.gltf", withUri("sub/inside.bin"));
    EXPECT_EQ(ngi::readMesh(dir_ / "mesh/inside.gltf").triangles.size(), 1u);
    write("mesh/dotdot.gltf", withUri("../outside.bin"));
    EXPECT_CONTAINS(error("mesh/dotdot.gltf"), "directory of the mesh");
    write("mesh/encoded.gltf", withUri("%2e%2e/outside.bin"));
    EXPECT_CONTAINS(error("mesh/encoded.gltf"), "directory of the mesh");
    write("mesh/passwd.gltf", withUri("../../../../../../../../etc/passwd"));
    EXPECT_CONTAINS(error("mesh/passwd.gltf"), "refusing to read");
    write("mesh/absolute.gltf", withUri((dir_ / "outside.bin").string()));
    EXPECT_CONTAINS(error("mesh/absolute.gltf"), "relative path");
    write("mesh/sub/back.gltf", withUri("../sub/inside.bin"));  // leaves and comes back: inside
    EXPECT_EQ(ngi::readMesh(dir_ / "mesh/sub/back.gltf").triangles.size(), 1u);
    // From memory there is no directory: only embedded buffers.
    const std::string json = withUri("sub/inside.bin");
    try {
        ngi::readMeshFromMemory({reinterpret_cast<const uint8_t*>(json.data()), json.size()}, ".gltf", "memory.gltf");
        ADD_FAILURE() << "an external buffer was read from memory";
    } catch (const ngi::Error& e) {
        EXPECT_CONTAINS(e.what(), "memory.gltf: ");
        EXPECT_CONTAINS(e.what(), "embedded");
    }
}

// Finding: ngi-eval could read no glTF ("FS callback not set"): libdraco.so, which ngi-eval
// links, exports its own build of tinygltf::TinyGLTF, and the dynamic linker bound our calls
// to it. This test executable links draco the same way (the DecoderBuffer below makes the
// link real) and reads a glTF with an external buffer and a GLB.
TEST_F(MeshIoHostile, GltfReadsWithDracoLinkedIntoTheProgram)
{
    draco::DecoderBuffer dracoInUse;
    (void)dracoInUse;
    if (!dlsym(RTLD_DEFAULT,
               "_ZN8tinygltf8TinyGLTF17LoadASCIIFromFileEPNS_5ModelEPNSt7__cxx1112basic_stringIcSt11char_"
               "traitsIcESaIcEEES9_RKS8_j"))
        std::printf("note: this libdraco exports no tinygltf; the test still reads both files\n");
    write("tri.bin", kTriangle);
    write("tri.gltf",
          gltfJson(kTriangleAccessor, R"({"buffer":0,"byteLength":36})", R"({"byteLength":36,"uri":"tri.bin"})"));
    EXPECT_EQ(ngi::readMesh(dir_ / "tri.gltf").triangles.size(), 1u);
    write("tri.glb",
          glb(gltfJson(kTriangleAccessor, R"({"buffer":0,"byteLength":36})", R"({"byteLength":36})"), kTriangle));
    EXPECT_EQ(ngi::readMesh(dir_ / "tri.glb").triangles.size(), 1u);
}

TEST_F(MeshIoHostile, GltfAndGlbGarbageIsRejected)
{
    write("garbage.glb", "glTF" + u32(2) + u32(0xffffffffu) + u32(0xfffffff0u) + "JSON" + std::string(64, '\xff'));
    EXPECT_CONTAINS(error("garbage.glb"), "glTF");
    write("empty.glb", "");
    EXPECT_CONTAINS(error("empty.glb"), "empty");
    // A BIN chunk whose length counts its 8-byte header too (what tinygltf checks): the data
    // would end 8 bytes past the file. One clear error, no read past the end (ASan, fuzzing).
    const std::string json = gltfJson(kTriangleAccessor, R"({"buffer":0,"byteLength":36})", R"({"byteLength":36})");
    std::string overrun = glb(json, kTriangle);
    const size_t binHeader = overrun.size() - 36 - 8;
    const std::string longer = u32(36 + 8);
    overrun.replace(binHeader, 4, longer);
    write("overrun.glb", overrun);
    EXPECT_CONTAINS(error("overrun.glb"), "BIN chunk holds 44 bytes but the file has 36");
    write("cut.glb", glb(json, kTriangle).substr(0, binHeader + 4));
    EXPECT_CONTAINS(error("cut.glb"), "BIN chunk's header is cut off");
    write("deep.gltf", std::string(100000, '[') + std::string(100000, ']'));  // no stack overflow
    EXPECT_CONTAINS(error("deep.gltf"), "cannot parse glTF");
    write("points.gltf", R"({"asset":{"version":"2.0"}})");
    EXPECT_CONTAINS(error("points.gltf"), "no triangles");
}

// ---------------------------------------------------------------- PLY

// Finding: a truncated ASCII PLY baked 64 of its 320 triangles with exit 0.
TEST_F(MeshIoHostile, TruncatedPlyNamesWhatTheHeaderDeclaredAndWhereTheFileEnds)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(2);
    ASSERT_EQ(sphere.triangles.size(), 320u);
    ngi::writeMesh(dir_ / "sphere.ply", sphere);
    std::ifstream in(dir_ / "sphere.ply", std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    size_t at = text.find("end_header\n") + 11;
    for (size_t line = 0; line < sphere.positions.size() + 64; ++line) at = text.find('\n', at) + 1;
    write("cut.ply", text.substr(0, at));
    EXPECT_CONTAINS(error("cut.ply"), "header declares 320 faces, the file ends after 64");
    write("cut_mid_face.ply", text.substr(0, at + 3));  // "3 1" of face 64
    EXPECT_CONTAINS(error("cut_mid_face.ply"), "header declares 320 faces, the file ends after 64");
    const size_t body = text.find("end_header\n") + 11;
    write("cut_in_vertices.ply", text.substr(0, text.find('\n', text.find('\n', body) + 1) + 1));  // 2 vertices
    EXPECT_CONTAINS(error("cut_in_vertices.ply"), "header declares 162 vertices, the file ends after 2");
    write("no_end_header.ply", text.substr(0, text.find("end_header")));
    EXPECT_CONTAINS(error("no_end_header.ply"), "no end_header");
    // The whole file still reads.
    EXPECT_EQ(ngi::readMesh(dir_ / "sphere.ply").triangles, sphere.triangles);
}

// Finding: a header claiming 2e9 vertices died with std::bad_alloc; it is now compared with
// the bytes after the header before anything is allocated.
TEST_F(MeshIoHostile, PlyHeaderCountsBeyondTheFileSizeAreRejectedBeforeAllocating)
{
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n";
    write("huge.ply", header);
    const std::string message = error("huge.ply");
    EXPECT_CONTAINS(message, "header declares 2000000000 vertices, the file ends after 1");
    EXPECT_CONTAINS(message, "need at least 6 bytes each, 6 bytes follow the header");
    write(
        "huge_binary.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 4294967295\nproperty list uchar int vertex_indices\nend_header\n" +
            kTriangle + "\3");
    EXPECT_CONTAINS(error("huge_binary.ply"), "header declares 4294967295 faces");
    write(
        "huge_list.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uint int vertex_indices\nend_header\n" +
            kTriangle + u32(0xfffffff0u) + u32(0));
    EXPECT_CONTAINS(error("huge_list.ply"), "header declares 1 faces, the file ends after 0");
}

TEST_F(MeshIoHostile, PlyNanIndicesAndTypesAreNamed)
{
    const std::string header =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    write("nan.ply", header + "0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_CONTAINS(error("nan.ply"), "vertex 1 has a non-finite coordinate");
    write("negative.ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n");
    EXPECT_CONTAINS(error("negative.ply"), "refers to vertex -1 of 3");
    write("range.ply", header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n");
    EXPECT_CONTAINS(error("range.ply"), "refers to vertex 3 of 3");
    write("two.ply", header + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n");
    EXPECT_CONTAINS(error("two.ply"), "face 0 has 2 vertices");
    write("word.ply", header + "0 0 0\n1 zero 0\n0 1 0\n3 0 1 2\n");
    EXPECT_CONTAINS(error("word.ply"), "line 11: 'zero' is not a number");
    write("type.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty quad x\nend_header\n");
    EXPECT_CONTAINS(error("type.ply"), "header line 4: unknown property type 'quad'");
    write("zero.ply",
          "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\n"
          "element face 0\nproperty list uchar int vertex_indices\nend_header\n");
    EXPECT_CONTAINS(error("zero.ply"), "no triangles");
    write("garbage.ply", std::string("ply\n\0\1\2\3", 8));
    EXPECT_CONTAINS(error("garbage.ply"), "NUL byte");
}

// Valid but odd: CRLF header, big-endian, extra vertex properties and an extra element after
// the faces (OpenMesh refused these), and an ASCII file without its final newline.
TEST_F(MeshIoHostile, PlyVariantsStillRead)
{
    auto be = [](std::string bytes, size_t width) {
        for (size_t i = 0; i + width <= bytes.size(); i += width)
            std::reverse(bytes.begin() + long(i), bytes.begin() + long(i + width));
        return bytes;
    };
    std::string body;
    for (int v = 0; v < 3; ++v) body += be(kTriangle.substr(size_t(v) * 12, 12), 4) + "\x07";
    body += std::string("\x03", 1) + be(u32(0) + u32(1) + u32(2), 4) + be(u32(0) + u32(1), 4);
    write("big.ply",
          "ply\r\nformat binary_big_endian 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty "
          "float z\r\n"
          "property uchar red\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nelement edge 1\r\n"
          "property int vertex1\r\nproperty int vertex2\r\nend_header\r\n" +
              body);
    ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "big.ply");
    ASSERT_EQ(mesh.triangles.size(), 1u);
    EXPECT_EQ(mesh.positions[1], glm::dvec3(1, 0, 0));
    write("nonewline.ply",
          "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
          "element face 1\nproperty list uchar int vertex_index\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3");
    EXPECT_EQ(ngi::readMesh(dir_ / "nonewline.ply").triangles.size(), 2u);
}

// ---------------------------------------------------------------- STL

// Finding: a truncated ASCII STL baked what it had (only a components warning).
TEST_F(MeshIoHostile, TruncatedAsciiStlIsAnError)
{
    const std::string facet =
        " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n";
    write("ok.stl", "solid t\r\n" + facet + facet + "endsolid t");   // CRLF and no final newline
    EXPECT_EQ(ngi::readMesh(dir_ / "ok.stl").positions.size(), 3u);  // corners merged
    write("noend.stl", "solid t\n" + facet + facet);
    EXPECT_CONTAINS(error("noend.stl"), "solid 't' has no endsolid (the file ends after 2 facets)");
    const std::string cut = "solid t\n" + facet + facet.substr(0, facet.find("   vertex 1"));
    write("cut.stl", cut);
    EXPECT_CONTAINS(error("cut.stl"), "truncated ASCII STL file");
    EXPECT_CONTAINS(error("cut.stl"), "1 complete facets");
    std::string noEndloop = facet;
    noEndloop.erase(noEndloop.find("  endloop\n"), 10);
    write("noendloop.stl", "solid t\n" + noEndloop + "endsolid t\n");
    EXPECT_CONTAINS(error("noendloop.stl"), "line 7: expected 'endloop', found 'endfacet'");
    std::string nan = facet;
    nan.replace(nan.find("vertex 1 0 0"), 12, "vertex nan 0 0");
    write("nan.stl", "solid t\n" + nan + "endsolid t\n");
    EXPECT_CONTAINS(error("nan.stl"), "line 5: non-finite coordinate 'nan'");
}

// Finding: a truncated binary STL and one with NaN said "the mesh has no triangles".
TEST_F(MeshIoHostile, BinaryStlTruncationAndNanAreNamed)
{
    std::string stl = std::string(80, ' ') + u32(2);
    for (int t = 0; t < 2; ++t) stl += floats({0, 0, 1}) + kTriangle + std::string(2, '\0');
    write("ok.stl", stl);
    EXPECT_EQ(ngi::readMesh(dir_ / "ok.stl").triangles.size(), 2u);
    write("solid_header.stl", "solid but binary" + stl.substr(16));  // "solid" header, binary size
    EXPECT_EQ(ngi::readMesh(dir_ / "solid_header.stl").triangles.size(), 2u);
    write("cut.stl", stl.substr(0, stl.size() - 20));
    EXPECT_CONTAINS(error("cut.stl"),
                    "truncated binary STL file: header declares 2 triangles (184 bytes), the file has 164 bytes");
    write("cut_solid.stl", "solid but binary" + stl.substr(16, stl.size() - 36));  // NUL bytes: not ASCII
    EXPECT_CONTAINS(error("cut_solid.stl"), "truncated binary STL file");
    write("short.stl", std::string(40, '\1'));
    EXPECT_CONTAINS(error("short.stl"), "less than the 84-byte header");
    std::string nan = stl;
    const float value = std::nanf("");
    std::memcpy(nan.data() + 84 + 12 + 4, &value, 4);
    write("nan.stl", nan);
    EXPECT_CONTAINS(error("nan.stl"), "triangle 0 has a non-finite");
    write("zero.stl", std::string(80, ' ') + u32(0));
    EXPECT_CONTAINS(error("zero.stl"), "declares 0 triangles");
}

// ---------------------------------------------------------------- OBJ

// Finding: nan/inf/1e39 coordinates said "a face refers to a vertex that does not exist".
TEST_F(MeshIoHostile, ObjNonFiniteCoordinatesNameTheLine)
{
    for (const char* value : {"nan", "inf", "-inf", "1e39", "1e400"}) {
        write("bad.obj", std::string("v 0 0 0\nv ") + value + " 0 0\nv 0 1 0\nf 1 2 3\n");
        EXPECT_CONTAINS(error("bad.obj"), std::string("line 2: non-finite coordinate '") + value + "'");
    }
}

TEST_F(MeshIoHostile, ObjIndicesAreCheckedAndOddFilesRead)
{
    write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    EXPECT_CONTAINS(error("range.obj"), "line 4: face refers to vertex 4, but the file has only 3 vertices");
    write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    EXPECT_CONTAINS(error("zero.obj"), "line 4: face refers to vertex 0");
    write("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
    EXPECT_CONTAINS(error("negative.obj"), "line 4: face refers to vertex -4, but only 3 vertices precede it");
    write("huge.obj", "v 0 0 0\nf 1 99999999999999999999999 1\n");
    EXPECT_CONTAINS(error("huge.obj"), "line 2: face vertex '99999999999999999999999' is not an index");
    write("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
    EXPECT_CONTAINS(error("two.obj"), "line 3: face with 2 vertices");
    write("nofaces.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    EXPECT_CONTAINS(error("nofaces.obj"), "no triangles");
    write("binary.obj", std::string("v 0 0 0\n\0\xff\xfe", 11));
    EXPECT_CONTAINS(error("binary.obj"), "not a text file");
    write("empty.obj", "");
    EXPECT_CONTAINS(error("empty.obj"), "no vertices and no faces");
    // Valid but odd: CRLF, relative indices, v/vt/vn, a continued line, a comment after a
    // vertex, a w coordinate, no final newline.
    write("odd.obj",
          "# odd\r\nv 0 0 0 1\r\nv 1 0 0 # right\r\nv 1 1 0\r\nv +0 1 0\r\nvt 0 0\r\nvn 0 0 1\r\n"
          "f -4/1/1 -3/1/1 \\\r\n -2/1/1 -1//1");
    ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "odd.obj");
    EXPECT_EQ(mesh.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}));
    // A face with a high degree (fan-triangulated in linear time).
    std::string wheel = "v 0 0 0\n";
    std::string face = "f 1";
    for (int k = 0; k < 20000; ++k) {
        char line[64];
        std::snprintf(line, sizeof line, "v %.9g %.9g 0\n", std::cos(k * 1e-4), std::sin(k * 1e-4));
        wheel += line;
        std::snprintf(line, sizeof line, " %d", k + 2);
        face += line;
    }
    write("wheel.obj", wheel + face + "\n");
    EXPECT_EQ(ngi::readMesh(dir_ / "wheel.obj").triangles.size(), 19999u);
}

// ---------------------------------------------------------------- OFF

// Finding: a count of 99999999999999999999 said "the mesh has no triangles" (the counts were
// read from the vertex lines instead).
TEST_F(MeshIoHostile, OffCountsAreParsedStrictlyAndCheckedAgainstTheFileSize)
{
    write("overflow.off", "OFF\n99999999999999999999 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_CONTAINS(error("overflow.off"), "line 2: vertex count '99999999999999999999' is out of range");
    write("negative.off", "OFF\n-3 1 0\n0 0 0\n");
    EXPECT_CONTAINS(error("negative.off"), "vertex count '-3' is negative");
    write("huge.off", "OFF\n4000000000 4000000000 0\n0 0 0\n");
    const std::string huge = error("huge.off");
    EXPECT_CONTAINS(huge, "header declares 4000000000 vertices, the file ends after 1");
    EXPECT_CONTAINS(huge, "need at least 56000000000 bytes, 6 follow the header");
    write("big.off", "OFF\n3 200000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_CONTAINS(error("big.off"),
                    "header declares 200000000 faces, the file ends after 1 (the header's counts need at least");
    write("faces_cut.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_CONTAINS(error("faces_cut.off"), "header declares 2 faces, the file ends after 1");
    write("degree.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n");
    EXPECT_CONTAINS(error("degree.off"), "fewer than 1000000000 indices");
    write("negative_index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n");
    EXPECT_CONTAINS(error("negative_index.off"), "refers to vertex -1 of 3");
    write("nan.off", "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n");
    EXPECT_CONTAINS(error("nan.off"), "line 4: non-finite coordinate 'inf'");
    write("binary.off", std::string("\x01\x02\0\0garbage", 11));
    EXPECT_CONTAINS(error("binary.off"), "not a text file");
    write("empty.off", "");
    EXPECT_CONTAINS(error("empty.off"), "empty");
    // Valid but odd: CRLF, no final newline.
    write("crlf.off", "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2");
    EXPECT_EQ(ngi::readMesh(dir_ / "crlf.off").triangles.size(), 1u);
}

TEST_F(MeshIoHostile, BinaryOffReadsAndTruncationIsNamed)
{
    auto be32 = [](uint32_t v) {
        const char b[4] = {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
        return std::string(b, 4);
    };
    auto bef = [&](float f) {
        uint32_t bits;
        std::memcpy(&bits, &f, 4);
        return be32(bits);
    };
    std::string off = "OFF BINARY\n" + be32(3) + be32(1) + be32(0);
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) off += bef(f);
    off += be32(3) + be32(0) + be32(1) + be32(2) + be32(0);
    write("binary.off", off);
    ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "binary.off");
    ASSERT_EQ(mesh.triangles.size(), 1u);
    EXPECT_EQ(mesh.positions[2], glm::dvec3(0, 1, 0));
    write("cut.off", off.substr(0, off.size() - 8));
    EXPECT_CONTAINS(error("cut.off"), "truncated binary OFF file");
    write("huge.off", "OFF BINARY\n" + be32(0xffffffffu) + be32(1) + be32(0));
    EXPECT_CONTAINS(error("huge.off"), "header declares 4294967295 vertices");
}

#if !defined(NGI_TEST_ASAN)
// In a death-test child: caps the address space at what is mapped now plus `slack`, reads
// `off` from memory and exits 0 if that failed with the out-of-memory ngi::Error.
[[noreturn]] void readUnderAddressSpaceCap(const std::string& off, size_t slack)
{
    std::ifstream statm("/proc/self/statm");
    size_t pages = 0;
    statm >> pages;
    const rlim_t cap = rlim_t(pages) * rlim_t(::sysconf(_SC_PAGESIZE)) + rlim_t(slack);
    const rlimit limit{cap, cap};
    if (::setrlimit(RLIMIT_AS, &limit) != 0) std::_Exit(2);
    try {
        ngi::readMeshFromMemory({reinterpret_cast<const uint8_t*>(off.data()), off.size()}, ".off", "big.off");
    } catch (const ngi::Error& e) {
        std::fprintf(stderr, "%s\n", e.what());
        std::_Exit(std::string(e.what()).rfind("big.off: out of memory reading the mesh", 0) == 0 ? 0 : 1);
    }
    std::_Exit(3);
}
#endif

// Finding: out-of-memory cases said only "std::bad_alloc". A child process whose address
// space is capped reads a valid OFF whose vertices do not fit: one ngi::Error naming it.
TEST_F(MeshIoHostile, OutOfMemoryIsAnErrorNamingTheFile)
{
#if defined(NGI_TEST_ASAN)
    GTEST_SKIP() << "an address-space limit breaks AddressSanitizer's shadow memory";
#else
    const size_t vertices = 4'000'000;  // 96 MB of positions from 24 MB of text
    std::string off = "OFF\n" + std::to_string(vertices) + " 1 0\n";
    off.reserve(off.size() + vertices * 6 + 16);
    for (size_t v = 0; v < vertices; ++v) off += "0 0 0\n";
    off += "3 0 1 2\n";
    EXPECT_EXIT(readUnderAddressSpaceCap(off, 32u << 20), ::testing::ExitedWithCode(0), "big.off: out of memory");
#endif
}

TEST_F(MeshIoHostile, ReadFromMemoryNamesTheBuffer)
{
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    EXPECT_EQ(ngi::readMeshFromMemory({reinterpret_cast<const uint8_t*>(obj.data()), obj.size()}, "obj", "buffer")
                  .triangles.size(),
              1u);
    try {
        ngi::readMeshFromMemory({reinterpret_cast<const uint8_t*>(obj.data()), 20}, ".OBJ", "buffer");
        ADD_FAILURE() << "a cut OBJ was read";
    } catch (const ngi::Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("buffer: ", 0), 0u) << e.what();
    }
}

// Polygons the outline triangulation must not trip over (CGAL checks its preconditions only in
// debug builds): corners at one point, a self-intersecting star, a non-planar zigzag of 600
// corners (past the cubic search's limit) and one of 5000 (past the outline limit: fanned).
// Each still reads as n - 2 triangles of its own corners.
TEST_F(MeshIoHostile, DegenerateAndHugePolygonsStillReadAsTheirCorners)
{
    auto polygonFile = [](const std::vector<glm::dvec3>& corners) {
        std::ostringstream text;  // not a + chain of strings: GCC 12 warns (-Wrestrict) on those
        text << "OFF\n" << corners.size() << " 1 0\n";
        for (const glm::dvec3& c : corners) text << c.x << ' ' << c.y << ' ' << c.z << '\n';
        text << corners.size();
        for (size_t i = 0; i < corners.size(); ++i) text << ' ' << i;
        text << '\n';
        return text.str();
    };
    std::vector<std::pair<std::string, std::vector<glm::dvec3>>> cases;
    // A reflex L whose reflex corner appears twice.
    cases.push_back({"coincident.off", {{0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {2, 0, 0}, {2, 2, 0}, {1, 1, 0}, {0, 2, 0}}});
    std::vector<glm::dvec3> star;  // pentagram: its outline crosses itself
    for (int k = 0; k < 5; ++k) star.push_back({std::cos(4.0 * M_PI * k / 5), std::sin(4.0 * M_PI * k / 5), 0.0});
    cases.push_back({"star.off", star});
    for (const size_t n : {size_t(600), size_t(5000)}) {
        std::vector<glm::dvec3> zigzag;
        for (size_t k = 0; k < n; ++k) {
            const double a = 2.0 * M_PI * double(k) / double(n), r = k % 2 ? 1.0 : 0.3;
            zigzag.push_back({r * std::cos(a), r * std::sin(a), k % 3 ? 0.0 : 0.5});
        }
        cases.push_back({"zigzag" + std::to_string(n) + ".off", zigzag});
    }
    for (const auto& [name, corners] : cases) {
        SCOPED_TRACE(name);
        ngi::TriangleMesh mesh;
        ASSERT_NO_THROW(mesh = ngi::readMesh(write(name, polygonFile(corners))));
        ASSERT_EQ(mesh.triangles.size(), corners.size() - 2);
        for (const glm::uvec3& t : mesh.triangles)
            for (int k = 0; k < 3; ++k) ASSERT_LT(t[k], corners.size());
    }
}

// An element without properties that declares 2^64-1 instances holds no bytes: the reader
// skips it at once (mesh_ply_fuzzer found the reader counting through 2^32-1 of them for 25
// s; through these it would not finish before ctest's timeout).
TEST_F(MeshIoHostile, PlyElementWithoutPropertiesButBillionsOfInstancesIsSkipped)
{
    const std::string header =
        "ply\nformat ascii 1.0\nelement junk 18446744073709551615\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\n"
        "end_header\n";
    const std::string body = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    ngi::TriangleMesh mesh;
    ASSERT_NO_THROW(mesh = ngi::readMesh(write("junk.ply", header + body)));
    EXPECT_EQ(mesh.positions.size(), 4u);
    EXPECT_EQ(mesh.triangles.size(), 4u);
}

}  // namespace
