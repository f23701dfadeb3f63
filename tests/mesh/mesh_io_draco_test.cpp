// glTF primitives compressed with KHR_draco_mesh_compression: a sphere encoded here with
// libdraco reads back as the sphere (binary and JSON containers, node transform and TEXCOORD_0
// applied), and a broken extension is one error naming the file.
#include "ngi/error.h"
#include "ngi/mesh/appearance.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/procedural_meshes.h"

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace {

struct Encoded {
    std::string bitstream;
    int positionId = -1, uvId = -1;
};

// The sphere as a Draco bitstream: POSITION (14 bits) and TEX_COORD = (x, y) / 2 + 0.5 (12 bits).
Encoded encodeSphere(const ngi::TriangleMesh& sphere)
{
    draco::Mesh mesh;
    mesh.set_num_points(uint32_t(sphere.positions.size()));
    draco::GeometryAttribute position, uv;
    position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, sizeof(float) * 3, 0);
    uv.Init(draco::GeometryAttribute::TEX_COORD, nullptr, 2, draco::DT_FLOAT32, false, sizeof(float) * 2, 0);
    const int p = mesh.AddAttribute(position, true, uint32_t(sphere.positions.size()));
    const int t = mesh.AddAttribute(uv, true, uint32_t(sphere.positions.size()));
    for (size_t i = 0; i < sphere.positions.size(); ++i) {
        const glm::dvec3 q = sphere.positions[i];
        const float xyz[3] = {float(q.x), float(q.y), float(q.z)}, st[2] = {float(q.x / 2 + 0.5), float(q.y / 2 + 0.5)};
        mesh.attribute(p)->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), xyz);
        mesh.attribute(t)->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), st);
    }
    for (const auto& f : sphere.triangles)
        mesh.AddFace({draco::PointIndex(f[0]), draco::PointIndex(f[1]), draco::PointIndex(f[2])});
    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
    encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 12);
    draco::EncoderBuffer buffer;
    EXPECT_TRUE(encoder.EncodeMeshToBuffer(mesh, &buffer).ok());
    return {std::string(buffer.data(), buffer.size()), int(mesh.attribute(p)->unique_id()),
            int(mesh.attribute(t)->unique_id())};
}

// The glTF JSON of one node (translated by (1, 2, 3)) drawing the Draco primitive; its
// accessors have no buffer view, as the extension prescribes.
std::string gltfJson(const Encoded& e, size_t points, size_t corners, const std::string& buffer, int view = 0,
                     int positionId = -2)
{
    const std::string n = std::to_string(e.bitstream.size());
    return R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],)"
           R"("extensionsRequired":["KHR_draco_mesh_compression"],"scenes":[{"nodes":[0]}],)"
           R"("nodes":[{"mesh":0,"translation":[1,2,3]}],"meshes":[{"primitives":[{"attributes":{"POSITION":0,)"
           R"("TEXCOORD_0":1},"indices":2,"mode":4,"extensions":{"KHR_draco_mesh_compression":{"bufferView":)" +
        std::to_string(view) + R"(,"attributes":{"POSITION":)" +
        std::to_string(positionId == -2 ? e.positionId : positionId) + R"(,"TEXCOORD_0":)" + std::to_string(e.uvId) +
        R"(}}}}]}],"accessors":[)" + R"({"componentType":5126,"count":)" + std::to_string(points) +
        R"(,"type":"VEC3","min":[-1,-1,-1],"max":[1,1,1]},)" + R"({"componentType":5126,"count":)" +
        std::to_string(points) + R"(,"type":"VEC2"},)" + R"({"componentType":5125,"count":)" + std::to_string(corners) +
        R"(,"type":"SCALAR"}],)" + R"("bufferViews":[{"buffer":0,"byteLength":)" + n +
        R"(}],"buffers":[{"byteLength":)" + n + buffer + "}]}";
}

std::string u32(uint32_t v) { return std::string(reinterpret_cast<const char*>(&v), 4); }

std::string glb(std::string json, std::string bin)
{
    while (json.size() % 4) json += ' ';
    while (bin.size() % 4) bin += '\0';
    return "glTF" + u32(2) + u32(uint32_t(12 + 8 + json.size() + 8 + bin.size())) + u32(uint32_t(json.size())) +
        "JSON" + json + u32(uint32_t(bin.size())) + std::string("BIN\0", 4) + bin;
}

std::string base64(const std::string& bytes)
{
    static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = uint32_t(uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= uint32_t(uint8_t(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= uint8_t(bytes[i + 2]);
        out += digits[(v >> 18) & 63];
        out += digits[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? digits[v & 63] : '=';
    }
    return out;
}

ngi::TriangleMesh read(const std::string& bytes, const char* format, const char* name,
                       ngi::MeshAppearance* appearance = nullptr)
{
    const std::span<const uint8_t> span(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
    return appearance ? ngi::readMeshFromMemory(span, format, name, *appearance)
                      : ngi::readMeshFromMemory(span, format, name);
}

std::string errorOf(const std::string& bytes, const char* format, const char* name)
{
    try {
        read(bytes, format, name);
    } catch (const ngi::Error& e) {
        return e.what();
    }
    return "(no error)";
}

// Every read vertex lies on the unit sphere moved by (1, 2, 3), within Draco's 14-bit steps.
void expectTranslatedSphere(const ngi::TriangleMesh& mesh, size_t triangles)
{
    EXPECT_EQ(mesh.triangles.size(), triangles);
    double worst = 0.0;
    for (const glm::dvec3& p : mesh.positions)
        worst = std::max(worst, std::abs(glm::length(p - glm::dvec3(1, 2, 3)) - 1.0));
    EXPECT_LT(worst, 1e-3);  // 2 / 2^14 = 1.2e-4 per axis
}

TEST(MeshIoDraco, ADracoPrimitiveReadsAsItsMeshInGlbAndGltf)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(2);
    const Encoded e = encodeSphere(sphere);
    const size_t points = sphere.positions.size(), corners = 3 * sphere.triangles.size();
    ngi::MeshAppearance appearance;
    const ngi::TriangleMesh fromGlb =
        read(glb(gltfJson(e, points, corners, ""), e.bitstream), ".glb", "sphere.glb", &appearance);
    expectTranslatedSphere(fromGlb, sphere.triangles.size());
    ASSERT_EQ(appearance.cornerUVs.size(), 3 * fromGlb.triangles.size());
    double uvError = 0.0;
    for (size_t t = 0; t < fromGlb.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 q = fromGlb.positions[fromGlb.triangles[t][k]] - glm::dvec3(1, 2, 3);
            uvError = std::max(uvError, glm::length(appearance.cornerUVs[3 * t + k] - (glm::dvec2(q) / 2.0 + 0.5)));
        }
    EXPECT_LT(uvError, 2e-3);  // 12-bit uv and 14-bit position steps
    const std::string uri = R"(,"uri":"data:application/octet-stream;base64,)" + base64(e.bitstream) + "\"";
    expectTranslatedSphere(read(gltfJson(e, points, corners, uri), ".gltf", "sphere.gltf"), sphere.triangles.size());
}

TEST(MeshIoDraco, ABrokenDracoPrimitiveIsOneErrorNamingTheFile)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(1);
    const Encoded e = encodeSphere(sphere);
    const size_t points = sphere.positions.size(), corners = 3 * sphere.triangles.size();
    const std::string noView = errorOf(glb(gltfJson(e, points, corners, "", 7), e.bitstream), ".glb", "view.glb");
    EXPECT_EQ(noView.rfind("view.glb: ", 0), 0u) << noView;
    EXPECT_NE(noView.find("buffer view"), std::string::npos) << noView;
    const std::string garbage =
        errorOf(glb(gltfJson(e, points, corners, ""), std::string(e.bitstream.size(), 'Z')), ".glb", "garbage.glb");
    EXPECT_EQ(garbage.rfind("garbage.glb: ", 0), 0u) << garbage;
    EXPECT_NE(garbage.find("Draco"), std::string::npos) << garbage;
    const std::string truncated = errorOf(
        glb(gltfJson(e, points, corners, ""), e.bitstream.substr(0, e.bitstream.size() / 2)), ".glb", "half.glb");
    EXPECT_EQ(truncated.rfind("half.glb: ", 0), 0u) << truncated;
    const std::string missing =
        errorOf(glb(gltfJson(e, points, corners, "", 0, 99), e.bitstream), ".glb", "missing.glb");
    EXPECT_EQ(missing.rfind("missing.glb: ", 0), 0u) << missing;
    EXPECT_NE(missing.find("not in the bitstream"), std::string::npos) << missing;
}

}  // namespace
