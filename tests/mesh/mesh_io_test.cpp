// Mesh IO: round trips through every written format, glTF reading, and clear errors.
#include "ngi/asset.h"
#include "ngi/error.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/procedural_meshes.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace fs = std::filesystem;

namespace {

class MeshIo : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_mesh_io_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path file(const std::string& name) const { return dir_ / name; }
    void writeText(const fs::path& path, const std::string& text) const
    {
        std::ofstream(path, std::ios::binary) << text;
    }
    fs::path dir_;
};

std::string errorOf(const fs::path& path)
{
    try {
        ngi::readMesh(path);
    } catch (const ngi::Error& e) {
        return e.what();
    }
    return "";
}

TEST_F(MeshIo, RoundTripsEveryWrittenFormatExactly)
{
    ngi::TriangleMesh torus = ngi::makeTorus(12, 6);
    for (const char* ext : {".obj", ".off", ".ply"}) {
        fs::path path = file(std::string("torus") + ext);
        ngi::writeMesh(path, torus);
        ngi::TriangleMesh back = ngi::readMesh(path);
        ASSERT_EQ(back.triangles.size(), torus.triangles.size()) << ext;
        ASSERT_EQ(back.positions.size(), torus.positions.size()) << ext;
        EXPECT_EQ(back.triangles, torus.triangles) << ext;
        for (size_t i = 0; i < torus.positions.size(); ++i)
            EXPECT_NEAR(glm::distance(back.positions[i], torus.positions[i]), 0.0, 1e-6) << ext;
    }
}

TEST_F(MeshIo, PolygonsAreFanTriangulated)
{
    writeText(file("quad.off"), "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 2 0\n4 0 1 2 3\n3 3 2 4\n");
    ngi::TriangleMesh mesh = ngi::readMesh(file("quad.off"));
    ASSERT_EQ(mesh.triangles.size(), 3u);
    // A convex quad keeps its fan, and the faces keep the file's order.
    EXPECT_EQ(mesh.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(mesh.triangles[1], glm::uvec3(0, 2, 3));
    EXPECT_EQ(mesh.triangles[2], glm::uvec3(3, 2, 4));
}

// CGAL's corner_poly.off: L-shaped hexagons, whose fan from the first corner folds outside the
// polygon (the remesher then tore the surface: "boundary loops 0 -> 2").
TEST_F(MeshIo, NonConvexPolygonsAreTriangulatedInsideTheirOutline)
{
    // The L (the square [0,2]^2 without [0,1)^2, area 3) counter-clockwise from (0,1): the fan
    // from there has a triangle (0,1)-(1,0)-(2,0) outside it. As a hexagon, then a quad with a
    // reflex corner (fan from corner 0 folds), in OFF, OBJ and PLY.
    const std::string corners = "0 1 0\n1 1 0\n1 0 0\n2 0 0\n2 2 0\n0 2 0\n";
    writeText(file("l.off"), "OFF\n6 1 0\n" + corners + "6 0 1 2 3 4 5\n");
    writeText(file("l.obj"), "v 0 1 0\nv 1 1 0\nv 1 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\nf 1 2 3 4 5 6\n");
    writeText(file("l.ply"),
              "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
              "element vertex 6\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
              "6 0 1 2 3 4 5\n" +
                  corners);
    // A dart (area 2): corner 1 is reflex, so the fan's diagonal 0-2 lies outside it.
    writeText(file("dart.off"), "OFF\n4 1 0\n0 0 0\n1 1 0\n2 0 0\n1 3 0\n4 0 1 2 3\n");
    for (const auto& [name, area] : {std::pair{"l.off", 3.0}, {"l.obj", 3.0}, {"l.ply", 3.0}, {"dart.off", 2.0}}) {
        ngi::TriangleMesh mesh = ngi::readMesh(file(name));
        const size_t corners = mesh.positions.size();
        ASSERT_EQ(mesh.triangles.size(), corners - 2) << name;
        double unsignedArea = 0.0;
        for (const glm::uvec3& t : mesh.triangles) {
            const glm::dvec3 n =
                glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
            EXPECT_GT(n.z, 1e-9) << name << ": a triangle is folded or degenerate";  // the outline is counter-clockwise
            unsignedArea += 0.5 * glm::length(n);
        }
        // A fan would cover area outside the outline twice (L: 3.5 instead of 3).
        EXPECT_NEAR(unsignedArea, area, 1e-9) << name;
    }
}

TEST_F(MeshIo, ReadsOffWithCommentsColoursAndCountsOnTheHeaderLine)
{
    writeText(file("commented.off"),
              "# Output of a CGAL tool\n#CBP\nCOFF\n# counts\n4 2 0\n\n0 0 0 1 0 0 1 # red\n1 0 0 0 1 0 1\n"
              "1 1 0 0 0 1 1\n0 1 0 1 1 1 1\n# faces\n3 0 1 2 255 0 0\n3 0 2 3\n");
    ngi::TriangleMesh mesh = ngi::readMesh(file("commented.off"));
    ASSERT_EQ(mesh.positions.size(), 4u);
    EXPECT_EQ(mesh.positions[2], glm::dvec3(1, 1, 0));
    EXPECT_EQ(mesh.triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}}));
    writeText(file("inline.off"), "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_EQ(ngi::readMesh(file("inline.off")).triangles.size(), 1u);
    writeText(file("truncated.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n");
    EXPECT_NE(errorOf(file("truncated.off")).find("truncated"), std::string::npos);
    writeText(file("badindex.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    EXPECT_NE(errorOf(file("badindex.off")).find("refers to vertex 7"), std::string::npos);
}

TEST_F(MeshIo, ReadsGltfWithNodeTransformsAndMergedPrimitives)
{
    // Two nodes instancing one triangle: one translated by +10 in x, one mirrored in x.
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    std::string bytes(reinterpret_cast<const char*>(positions), sizeof positions);
    std::string base64;
    {
        static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        size_t i = 0;
        for (; i + 2 < bytes.size(); i += 3) {
            uint32_t v = (uint8_t(bytes[i]) << 16) | (uint8_t(bytes[i + 1]) << 8) | uint8_t(bytes[i + 2]);
            for (int k = 3; k >= 0; --k) base64 += table[(v >> (6 * k)) & 63];
        }
        ASSERT_EQ(i, bytes.size());  // 36 bytes: no padding needed
    }
    writeText(file("two.gltf"),
              R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0,1]}],
      "nodes":[{"mesh":0,"translation":[10,0,0]},{"mesh":0,"scale":[-1,1,1]}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
      "bufferViews":[{"buffer":0,"byteLength":36}],
      "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)" +
                  base64 + R"("}]})");
    ngi::TriangleMesh mesh = ngi::readMesh(file("two.gltf"));
    ASSERT_EQ(mesh.positions.size(), 6u);
    ASSERT_EQ(mesh.triangles.size(), 2u);
    EXPECT_DOUBLE_EQ(mesh.positions[1].x, 11.0);
    EXPECT_DOUBLE_EQ(mesh.positions[4].x, -1.0);
    // Both triangles face +z after the transform (the mirrored one had its winding swapped).
    for (const glm::uvec3& t : mesh.triangles) {
        glm::dvec3 n = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
        EXPECT_GT(n.z, 0.0);
    }
}

TEST_F(MeshIo, ReadsGlbWithIndexedTriangles)
{
    // A minimal binary glTF: JSON chunk + BIN chunk (3 float positions, 3 u16 indices + pad).
    std::string bin;
    const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const uint16_t indices[4] = {0, 1, 2, 0};
    bin.append(reinterpret_cast<const char*>(positions), sizeof positions);
    bin.append(reinterpret_cast<const char*>(indices), sizeof indices);
    std::string json =
        R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"matrix":[2,0,0,0,0,2,0,0,0,0,2,0,1,1,1,1]}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                   {"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],
      "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],
      "buffers":[{"byteLength":44}]})";
    while (json.size() % 4) json += ' ';
    auto u32 = [](uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); };
    std::string glb = "glTF" + u32(2) + u32(uint32_t(12 + 8 + json.size() + 8 + bin.size())) +
        u32(uint32_t(json.size())) + "JSON" + json + u32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
    writeText(file("tri.glb"), glb);
    ngi::TriangleMesh mesh = ngi::readMesh(file("tri.glb"));
    ASSERT_EQ(mesh.triangles.size(), 1u);
    EXPECT_EQ(mesh.positions[1], glm::dvec3(3, 1, 1));  // scaled by 2, translated by (1,1,1)
    writeText(file("truncated.glb"), glb.substr(0, glb.size() - 10));
    EXPECT_NE(errorOf(file("truncated.glb")).find("truncated.glb"), std::string::npos);
}

TEST_F(MeshIo, RejectsMissingUnknownCorruptEmptyAndNonFinite)
{
    EXPECT_NE(errorOf(file("missing.obj")).find("no such file"), std::string::npos);
    writeText(file("mesh.xyz"), "1 2 3\n");
    EXPECT_NE(errorOf(file("mesh.xyz")).find("unknown mesh format"), std::string::npos);
    writeText(file("corrupt.off"), "this is not an OFF file\n");
    EXPECT_NE(errorOf(file("corrupt.off")).find("corrupt.off"), std::string::npos);
    writeText(file("empty.off"), "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
    EXPECT_NE(errorOf(file("empty.off")).find("no triangles"), std::string::npos);
    writeText(file("nan.obj"), "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    std::string nanError = errorOf(file("nan.obj"));
    EXPECT_TRUE(nanError.find("NaN") != std::string::npos || nanError.find("nan.obj") != std::string::npos) << nanError;
    writeText(file("broken.gltf"), "{ not json");
    EXPECT_NE(errorOf(file("broken.gltf")).find("broken.gltf"), std::string::npos);
}

TEST_F(MeshIo, WriterRejectsUnknownFormatAndLeavesNoFile)
{
    EXPECT_THROW(ngi::writeMesh(file("out.xyz"), ngi::makeSphere(0)), ngi::Error);
    EXPECT_FALSE(fs::exists(file("out.xyz")));
}

// A tool checks its mesh output path before the work; the message names the path given.
TEST_F(MeshIo, OutputFormatCheckNamesThePathAndTheMissingOrUnknownExtension)
{
    auto message = [](const fs::path& path) {
        try {
            ngi::checkMeshOutputFormat(path);
        } catch (const ngi::Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(message(file("out")),
              file("out").string() + ": the output path has no extension (expected .obj, .off or .ply)");
    EXPECT_EQ(message(file("out.xyz")),
              file("out.xyz").string() + ": cannot write mesh format '.xyz' (expected .obj, .off or .ply)");
    EXPECT_EQ(message(file("out.OBJ")), "");
    EXPECT_EQ(message(file("out.ply")), "");
}

// Thousands of nodes, each instancing one small mesh (a scene exported from a game engine),
// read in time linear in the node count: the vertex array grows geometrically, not by one
// exact reserve per primitive.
TEST_F(MeshIo, GltfWithThousandsOfNodesReadsEveryInstance)
{
    const size_t nodes = 5000;
    std::string nodeList, sceneNodes;
    for (size_t n = 0; n < nodes; ++n) {
        nodeList += (n ? "," : "") + std::string(R"({"mesh":0,"translation":[)") + std::to_string(2 * (n % 100)) +
            ",0," + std::to_string(2 * (n / 100)) + "]}";
        sceneNodes += (n ? "," : "") + std::to_string(n);
    }
    // One triangle (0,0,0) (1,0,0) (0,1,0) as 9 little-endian floats.
    const std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[)" + sceneNodes +
        R"(]}],"nodes":[)" + nodeList + R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
      "bufferViews":[{"buffer":0,"byteLength":36}],
      "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA"}]})";
    const ngi::TriangleMesh mesh =
        ngi::readMeshFromMemory({reinterpret_cast<const uint8_t*>(json.data()), json.size()}, ".gltf", "nodes.gltf");
    ASSERT_EQ(mesh.triangles.size(), nodes);
    ASSERT_EQ(mesh.positions.size(), 3 * nodes);
    EXPECT_DOUBLE_EQ(mesh.positions[3 * (nodes - 1) + 1].x, 2.0 * 99 + 1.0);  // the last instance, translated
    EXPECT_DOUBLE_EQ(mesh.positions[3 * (nodes - 1)].z, 2.0 * 49);
}

}  // namespace
