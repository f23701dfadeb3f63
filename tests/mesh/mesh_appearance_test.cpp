// The mesh readers' appearance (appearance.h): texture coordinates, vertex colours, materials
// and decoded textures from OBJ + MTL, PLY and glTF/GLB, each asserted by value. Every input
// is made by the test.
#include "appearance_fixtures.h"

#include "ngi/mesh/mesh_io.h"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include <sstream>

using namespace appearance_fixtures;

namespace {

class MeshAppearanceRead : public ScratchDirectory {};

constexpr double kColourTolerance = 1e-6;  // float storage of a converted colour

glm::dvec2 transformed(const ngi::TextureRef& ref, glm::dvec2 uv)
{
    return glm::dvec2(ref.transform * glm::dvec3(uv, 1.0));
}

// ---------------------------------------------------------------- OBJ + MTL

TEST_F(MeshAppearanceRead, ObjReadsUvsMaterialsAndTexturesFromItsMtl)
{
    write("materials/tex/albedo.png", pngBytes(dir_ / "scratch.png", 2, 1, {255, 0, 0, 255, 0, 0, 255, 128}));
    write("materials/tex/normal.png", pngBytes(dir_ / "scratch.png", 1, 1, {128, 128, 255, 255}));
    write("materials/look.mtl",
          "# two materials\nnewmtl red\nKd 0.8 0.1 0.1\nd 0.5\nKa 1 1 1\nillum 2\n"
          "newmtl textured\nKd 0.2 0.2 0.2\nmap_Kd -clamp on -s 2 2 1 tex/albedo.png\nmap_Bump -bm 0.5 tex/normal.png\n"
          "Ke 0.1 0.2 0.3\nPr 0.4\n");
    write("quad.obj",
          "mtllib materials/look.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\n"
          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.25 0.75\nvn 0 0 1\n"
          "usemtl red\nf 1/1 2/2 3/3 4/4\nusemtl textured\nf 2/2/1 5/5/1 3/3/1\nusemtl nosuch\nf 1 2 5\n");
    ngi::MeshAppearance look;
    const ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "quad.obj", look);
    ASSERT_EQ(mesh.triangles.size(), 4u);
    EXPECT_EQ(mesh.triangles[0], glm::uvec3(0, 1, 2));  // the quad's fan
    EXPECT_EQ(mesh.triangles[1], glm::uvec3(0, 2, 3));
    // (u, 1 - v) per corner; the face without vt gets (0, 0).
    const std::vector<glm::dvec2> uvs = {{0, 1}, {1, 1},       {1, 0}, {0, 1}, {1, 0}, {0, 0},
                                         {1, 1}, {0.25, 0.25}, {1, 0}, {0, 0}, {0, 0}, {0, 0}};
    ASSERT_EQ(look.cornerUVs.size(), 12u);
    for (size_t i = 0; i < uvs.size(); ++i) EXPECT_EQ(look.cornerUVs[i], uvs[i]) << "corner " << i;
    EXPECT_TRUE(look.cornerColors.empty());
    // Materials in order of first use; the unknown name gets the default one and a warning.
    EXPECT_EQ(look.triangleMaterial, (std::vector<uint32_t>{0, 0, 1, 2}));
    ASSERT_EQ(look.materials.size(), 3u);
    const ngi::Material& red = look.materials[0];
    EXPECT_EQ(red.name, "red");
    EXPECT_EQ(red.baseColorFactor, glm::dvec4(0.8, 0.1, 0.1, 0.5));
    EXPECT_EQ(red.alphaMode, ngi::AlphaMode::Blend);
    EXPECT_EQ(red.metallicFactor, 0.0);
    EXPECT_EQ(red.roughnessFactor, 1.0);
    EXPECT_FALSE(red.baseColorTexture.present());
    const ngi::Material& textured = look.materials[1];
    EXPECT_EQ(textured.baseColorFactor, glm::dvec4(1.0));  // map_Kd given: Kd is not a factor
    ASSERT_EQ(textured.baseColorTexture.image, 0);
    EXPECT_EQ(textured.baseColorTexture.wrapU, ngi::TextureWrap::ClampToEdge);
    EXPECT_EQ(textured.baseColorTexture.wrapV, ngi::TextureWrap::ClampToEdge);
    // -s 2 2: the OBJ lookup (0.25, 0.75) -> (0.5, 1.5), which is (0.5, -0.5) in glTF's uv.
    const glm::dvec2 lookedUp = transformed(textured.baseColorTexture, {0.25, 0.25});
    EXPECT_NEAR(lookedUp.x, 0.5, 1e-12);
    EXPECT_NEAR(lookedUp.y, -0.5, 1e-12);
    EXPECT_EQ(textured.normalTexture.image, 1);
    EXPECT_EQ(textured.normalScale, 0.5);
    EXPECT_EQ(textured.emissiveFactor, glm::dvec3(0.1, 0.2, 0.3));
    EXPECT_EQ(textured.roughnessFactor, 0.4);
    EXPECT_EQ(look.materials[2].name, "default");
    ASSERT_EQ(look.images.size(), 2u);
    EXPECT_EQ(look.images[0].width, 2u);
    EXPECT_EQ(look.images[0].height, 1u);
    EXPECT_EQ(look.images[0].rgba, (std::vector<uint8_t>{255, 0, 0, 255, 0, 0, 255, 128}));
    EXPECT_EQ(look.images[1].rgba, (std::vector<uint8_t>{128, 128, 255, 255}));
    ASSERT_EQ(look.warnings.size(), 1u);
    EXPECT_CONTAINS(look.warnings[0], (dir_ / "quad.obj").string() + ": usemtl 'nosuch'");
    // The geometry-only reader reads the same triangles.
    EXPECT_EQ(ngi::readMesh(dir_ / "quad.obj").triangles, mesh.triangles);
}

TEST_F(MeshAppearanceRead, ObjPolygonTrianglesTakeTheirCornersUvsThroughTheOutlineTriangulation)
{
    // An L-shaped hexagon started at a corner whose fan folds over: CGAL triangulates it. The
    // vt of each corner is its position / 2, listed in reverse, so a corner given the wrong
    // polygon corner's vt shows.
    const glm::dvec2 corners[6] = {{2, 1}, {1, 1}, {1, 2}, {0, 2}, {0, 0}, {2, 0}};
    std::ostringstream obj;
    for (const glm::dvec2& c : corners) obj << "v " << c.x << " " << c.y << " 0\n";
    for (int i = 5; i >= 0; --i) obj << "vt " << corners[i].x / 2 << " " << corners[i].y / 2 << "\n";
    obj << "f";
    for (int i = 0; i < 6; ++i) obj << " " << i + 1 << "/" << 6 - i;
    obj << "\n";
    write("l.obj", obj.str());
    ngi::MeshAppearance look;
    const ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "l.obj", look);
    ASSERT_EQ(mesh.triangles.size(), 4u);
    EXPECT_NE(mesh.triangles[0], glm::uvec3(0, 1, 2))
        << "the fan was kept: the test no longer exercises the outline path";
    ASSERT_EQ(look.cornerUVs.size(), 12u);
    for (size_t t = 0; t < 4; ++t)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 p = mesh.positions[mesh.triangles[t][k]];
            EXPECT_NEAR(look.cornerUVs[t * 3 + k].x, p.x / 2, 1e-6) << t << "," << k;
            EXPECT_NEAR(look.cornerUVs[t * 3 + k].y, 1.0 - p.y / 2, 1e-6) << t << "," << k;
        }
}

TEST_F(MeshAppearanceRead, ObjVertexColoursAreSrgbAndExponentNumbersParse)
{
    write("c.obj", "v 0 0 0 0.5 0.25 1\nv 3.1e+2 0 0\nv 0 1E+1 0 0 0 0\nf 1 2 3\n");
    ngi::MeshAppearance look;
    const ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "c.obj", look);
    EXPECT_EQ(mesh.positions[1].x, 310.0);
    EXPECT_EQ(mesh.positions[2].y, 10.0);
    ASSERT_EQ(look.cornerColors.size(), 3u);
    EXPECT_NEAR(look.cornerColors[0].r, srgbToLinear(0.5), kColourTolerance);  // 0.2140
    EXPECT_NEAR(look.cornerColors[0].g, srgbToLinear(0.25), kColourTolerance);
    EXPECT_EQ(look.cornerColors[0].b, 1.0f);
    EXPECT_EQ(look.cornerColors[1], glm::vec4(1.0f));  // a vertex without a colour is white
    EXPECT_EQ(look.cornerColors[2], glm::vec4(0, 0, 0, 1));
    EXPECT_TRUE(look.materials.empty());
    EXPECT_TRUE(look.cornerUVs.empty());
}

TEST_F(MeshAppearanceRead, GeometryOnlyReadOpensNoMaterialLibraryAndDecodesNoTexture)
{
    write("broken.png", "\x89PNG\r\n\x1a\n garbage");
    write("look.mtl", "newmtl m\nmap_Kd broken.png\n");
    write("m.obj",
          "mtllib look.mtl\nmtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt nan 0\nusemtl m\nf 1/1 2/1 3/1\n");
    EXPECT_EQ(ngi::readMesh(dir_ / "m.obj").triangles.size(), 1u);
}

// ---------------------------------------------------------------- PLY

TEST_F(MeshAppearanceRead, PlyUcharColoursAreSrgbPerCornerFromTheirVertex)
{
    write("c.ply",
          "ply\nformat ascii 1.0\nCreated by a tool that forgot 'comment'\ncomment x\nelement vertex 4\nproperty float "
          "x\n"
          "property float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nproperty "
          "uchar alpha\n"
          "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
          "0 0 0 255 128 0 255\n1 0 0 0 0 0 128\n1 1 0 10 20 30 255\n0 1 0 255 255 255 0\n4 0 1 2 3\n");
    ngi::MeshAppearance look;
    const ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "c.ply", look);
    ASSERT_EQ(mesh.triangles.size(), 2u);
    ASSERT_EQ(look.cornerColors.size(), 6u);
    const glm::vec4 v0(1.0f, float(srgbToLinear(128 / 255.0)), 0.0f, 1.0f);
    const glm::vec4 v2(float(srgbToLinear(10 / 255.0)), float(srgbToLinear(20 / 255.0)),
                       float(srgbToLinear(30 / 255.0)), 1.0f);
    for (int c = 0; c < 4; ++c) {
        EXPECT_NEAR(look.cornerColors[0][c], v0[c], kColourTolerance);  // triangle 0 = (0, 1, 2)
        EXPECT_NEAR(look.cornerColors[2][c], v2[c], kColourTolerance);
        EXPECT_NEAR(look.cornerColors[4][c], v2[c], kColourTolerance);  // triangle 1 = (0, 2, 3)
    }
    EXPECT_NEAR(look.cornerColors[1].a, 128 / 255.0, kColourTolerance);  // alpha stays linear
    EXPECT_EQ(look.cornerColors[5], glm::vec4(1, 1, 1, 0));
    ASSERT_EQ(look.warnings.size(), 1u);
    EXPECT_CONTAINS(look.warnings[0], "unknown keyword 'Created' skipped");
    EXPECT_EQ(ngi::readMesh(dir_ / "c.ply").triangles, mesh.triangles);  // and without appearance
}

TEST_F(MeshAppearanceRead, PlyFloatDiffuseColoursAreSrgbInBinary)
{
    std::string body;
    const float vertices[3][6] = {{0, 0, 0, 0.5f, 0.0f, 1.0f}, {1, 0, 0, 0.25f, 0.75f, 2.0f}, {0, 1, 0, 0, 0, 0}};
    for (const auto& v : vertices) body.append(reinterpret_cast<const char*>(v), sizeof v);
    body += std::string("\x03", 1) + raw<int32_t>({0, 1, 2});
    write(
        "f.ply",
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "property float diffuse_red\nproperty float diffuse_green\nproperty float diffuse_blue\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
            body);
    ngi::MeshAppearance look;
    ngi::readMesh(dir_ / "f.ply", look);
    ASSERT_EQ(look.cornerColors.size(), 3u);
    EXPECT_NEAR(look.cornerColors[0].r, srgbToLinear(0.5), kColourTolerance);
    EXPECT_NEAR(look.cornerColors[1].g, srgbToLinear(0.75), kColourTolerance);
    EXPECT_EQ(look.cornerColors[1].b, 1.0f);  // 2.0 clamped
    EXPECT_EQ(look.cornerColors[0].a, 1.0f);  // no alpha property
}

// ---------------------------------------------------------------- glTF / GLB

// A quad (primitive 0: material 0, TEXCOORD_0 as normalized u16, COLOR_0 as normalized u8)
// and a triangle (primitive 1: no material, no attributes but POSITION).
std::string texturedQuadGltf(const std::string& pngDataUri)
{
    const std::string bin = raw<float>({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}) +             // 0: 48 bytes
        raw<uint16_t>({0, 0, 65535, 0, 65535, 65535, 0, 32768}) +                          // 48: 16 bytes
        raw<uint8_t>({51, 102, 153, 255, 255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 0}) +  // 64: 16 bytes
        raw<uint8_t>({0, 1, 2, 0, 2, 3, 0, 1});                                            // 80: 6 indices + pad
    return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1,"COLOR_0":2},"indices":3,"material":0},
                               {"attributes":{"POSITION":0},"indices":4}]}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                   {"bufferView":1,"componentType":5123,"normalized":true,"count":4,"type":"VEC2"},
                   {"bufferView":2,"componentType":5121,"normalized":true,"count":4,"type":"VEC4"},
                   {"bufferView":3,"componentType":5121,"count":6,"type":"SCALAR"},
                   {"bufferView":3,"componentType":5121,"count":3,"type":"SCALAR"}],
      "bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":16},
                     {"buffer":0,"byteOffset":64,"byteLength":16},{"buffer":0,"byteOffset":80,"byteLength":6}],
      "buffers":[{"byteLength":88,"uri":"data:application/octet-stream;base64,)" +
        base64(bin) + R"("}],
      "materials":[{"name":"painted","pbrMetallicRoughness":{"baseColorFactor":[0.5,0.6,0.7,0.8],
          "baseColorTexture":{"index":0,"extensions":{"KHR_texture_transform":{"offset":[0.5,0],"rotation":1.5707963267948966,"scale":[2,3]}}},
          "metallicFactor":0.25,"roughnessFactor":0.75,"metallicRoughnessTexture":{"index":1}},
        "normalTexture":{"index":1,"scale":0.3},"occlusionTexture":{"index":1,"strength":0.6},
        "emissiveFactor":[1,0.5,0],"emissiveTexture":{"index":0,"texCoord":1},
        "alphaMode":"MASK","alphaCutoff":0.3,"doubleSided":true},
        {"name":"unused","pbrMetallicRoughness":{"baseColorTexture":{"index":2}}}],
      "textures":[{"source":0,"sampler":0},{"source":1},{"source":2}],
      "samplers":[{"wrapS":33071,"wrapT":33648}],
      "images":[{"uri":")" +
        pngDataUri + R"("},{"uri":"tex/metal%20rough.png"},{"uri":"never-read.png"}]})";
}

TEST_F(MeshAppearanceRead, GltfReadsTexcoordsColoursAndEveryPbrMaterialField)
{
    const std::string albedo = pngBytes(dir_ / "scratch.png", 1, 2, {10, 20, 30, 40, 50, 60, 70, 80});
    write("tex/metal rough.png", png16Bytes(dir_ / "scratch.png", 1, 1, {65535, 32896, 257}));
    write("quad.gltf", texturedQuadGltf("data:image/png;base64," + base64(albedo)));
    ngi::MeshAppearance look;
    const ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "quad.gltf", look);
    ASSERT_EQ(mesh.triangles.size(), 3u);
    ASSERT_EQ(look.cornerUVs.size(), 9u);
    EXPECT_EQ(look.cornerUVs[1], glm::dvec2(1, 0));  // triangle 0 = (0, 1, 2)
    EXPECT_EQ(look.cornerUVs[2], glm::dvec2(1, 1));
    EXPECT_NEAR(look.cornerUVs[5].y, 32768 / 65535.0, 1e-12);  // triangle 1 = (0, 2, 3)
    EXPECT_EQ(look.cornerUVs[6], glm::dvec2(0, 0));            // primitive 1 has no TEXCOORD_0
    ASSERT_EQ(look.cornerColors.size(), 9u);
    EXPECT_NEAR(look.cornerColors[0].r, 0.2, kColourTolerance);  // COLOR_0 is linear: 51 / 255
    EXPECT_NEAR(look.cornerColors[0].b, 0.6, kColourTolerance);
    EXPECT_EQ(look.cornerColors[5], glm::vec4(0, 0, 1, 0));
    EXPECT_EQ(look.cornerColors[8], glm::vec4(1.0f));  // primitive 1: white
    EXPECT_EQ(look.triangleMaterial, (std::vector<uint32_t>{0, 0, 1}));
    ASSERT_EQ(look.materials.size(), 2u);  // "painted" and the default; "unused" is not converted
    const ngi::Material& m = look.materials[0];
    EXPECT_EQ(m.name, "painted");
    EXPECT_EQ(m.baseColorFactor, glm::dvec4(0.5, 0.6, 0.7, 0.8));
    EXPECT_EQ(m.metallicFactor, 0.25);
    EXPECT_EQ(m.roughnessFactor, 0.75);
    EXPECT_EQ(m.normalScale, 0.3);
    EXPECT_EQ(m.occlusionStrength, 0.6);
    EXPECT_EQ(m.emissiveFactor, glm::dvec3(1, 0.5, 0));
    EXPECT_EQ(m.alphaMode, ngi::AlphaMode::Mask);
    EXPECT_EQ(m.alphaCutoff, 0.3);
    EXPECT_TRUE(m.doubleSided);
    EXPECT_EQ(m.baseColorTexture.image, 0);
    EXPECT_EQ(m.emissiveTexture.image, 0);  // one image, decoded once
    EXPECT_EQ(m.metallicRoughnessTexture.image, 1);
    EXPECT_EQ(m.normalTexture.image, 1);
    EXPECT_EQ(m.occlusionTexture.image, 1);
    EXPECT_EQ(m.baseColorTexture.wrapU, ngi::TextureWrap::ClampToEdge);
    EXPECT_EQ(m.baseColorTexture.wrapV, ngi::TextureWrap::MirroredRepeat);
    EXPECT_EQ(m.metallicRoughnessTexture.wrapU, ngi::TextureWrap::Repeat);
    // KHR_texture_transform: translation * rotation * scale, rotated as viewers do
    // (u' = u cos r + v sin r, v' = v cos r - u sin r); (1, 0) -> (2, 0) -> (0, -2) -> (0.5, -2).
    const glm::dvec2 t = transformed(m.baseColorTexture, {1, 0});
    EXPECT_NEAR(t.x, 0.5, 1e-12);
    EXPECT_NEAR(t.y, -2.0, 1e-12);
    EXPECT_EQ(m.emissiveTexture.transform, glm::dmat3(1.0));
    ASSERT_EQ(look.images.size(), 2u);
    EXPECT_EQ(look.images[0].width, 1u);
    EXPECT_EQ(look.images[0].height, 2u);
    EXPECT_EQ(look.images[0].rgba, (std::vector<uint8_t>{10, 20, 30, 40, 50, 60, 70, 80}));
    EXPECT_EQ(look.images[1].rgba, (std::vector<uint8_t>{255, 128, 1, 255}));  // 16-bit rounded to 8
    ASSERT_EQ(look.warnings.size(), 1u);
    EXPECT_CONTAINS(look.warnings[0], "uses TEXCOORD_1; only TEXCOORD_0 is read");
}

TEST_F(MeshAppearanceRead, GlbReadsAJpegFromABufferViewAndFromMemory)
{
    const std::string jpeg =
        jpegBytes(2, 2, std::vector<uint8_t>{200, 100, 50, 200, 100, 50, 200, 100, 50, 200, 100, 50});
    const std::string bin = raw<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}) + raw<float>({0, 0, 1, 0, 0, 1}) + jpeg;
    const std::string json = R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"material":0}]}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                   {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}],
      "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24},
                     {"buffer":0,"byteOffset":60,"byteLength":)" +
        std::to_string(jpeg.size()) + R"(}],
      "buffers":[{"byteLength":)" +
        std::to_string(60 + jpeg.size()) + R"(}],
      "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
      "textures":[{"source":0}],"images":[{"bufferView":2,"mimeType":"image/jpeg"}]})";
    const std::string file = glb(json, bin);
    write("t.glb", file);
    ngi::MeshAppearance fromFile, fromMemory;
    ngi::readMesh(dir_ / "t.glb", fromFile);
    ngi::readMeshFromMemory(std::span(reinterpret_cast<const uint8_t*>(file.data()), file.size()), "glb", "buffer",
                            fromMemory);
    for (const ngi::MeshAppearance* look : {&fromFile, &fromMemory}) {
        EXPECT_EQ(look->cornerUVs, (std::vector<glm::dvec2>{{0, 0}, {1, 0}, {0, 1}}));
        ASSERT_EQ(look->images.size(), 1u);
        ASSERT_EQ(look->images[0].rgba.size(), 16u);
        const int expected[4] = {200, 100, 50, 255};
        for (int c = 0; c < 4; ++c)
            EXPECT_NEAR(look->images[0].rgba[size_t(c)], expected[c], 3) << c;  // JPEG at quality 100
        EXPECT_EQ(look->materials[0].baseColorTexture.image, 0);
    }
}

TEST_F(MeshAppearanceRead, GltfTriangleFansAndStripsBecomeTheirTriangles)
{
    const std::string bin = raw<float>({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, -1, 0.5f, 0});
    auto primitive = [&](int mode) {
        return R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
          "meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":)" +
            std::to_string(mode) + R"(}]}],
          "accessors":[{"bufferView":0,"componentType":5126,"count":5,"type":"VEC3","min":[-1,0,0],"max":[1,1,0]}],
          "bufferViews":[{"buffer":0,"byteLength":60}],
          "buffers":[{"byteLength":60,"uri":"data:application/octet-stream;base64,)" +
            base64(bin) + R"("}]})";
    };
    write("fan.gltf", primitive(6));
    write("strip.gltf", primitive(5));
    EXPECT_EQ(ngi::readMesh(dir_ / "fan.gltf").triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}, {0, 3, 4}}));
    EXPECT_EQ(ngi::readMesh(dir_ / "strip.gltf").triangles, (std::vector<glm::uvec3>{{0, 1, 2}, {2, 1, 3}, {2, 3, 4}}));
}

TEST_F(MeshAppearanceRead, GltfWithoutScenesAndNodesReadsEveryMesh)
{
    const std::string bin = raw<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
    write("loose.gltf",
          R"({"asset":{"version":"2.0"},
      "meshes":[{"primitives":[{"attributes":{"POSITION":0}}]},{"primitives":[{"attributes":{"POSITION":0}}]}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
      "bufferViews":[{"buffer":0,"byteLength":36}],
      "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)" +
              base64(bin) + R"("}]})");
    const ngi::TriangleMesh mesh = ngi::readMesh(dir_ / "loose.gltf");
    EXPECT_EQ(mesh.triangles.size(), 2u);
    EXPECT_EQ(mesh.positions.size(), 6u);
}

TEST_F(MeshAppearanceRead, AMeshWithoutAppearanceGivesAnEmptyOne)
{
    write("t.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    ngi::MeshAppearance look;
    look.warnings.push_back("left over from an earlier read");
    ngi::readMesh(dir_ / "t.off", look);
    EXPECT_TRUE(look.empty());
    EXPECT_TRUE(look.warnings.empty());
}

}  // namespace
