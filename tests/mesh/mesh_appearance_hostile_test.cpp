// The appearance readers against hostile inputs: each gets one ngi::Error that starts with
// the mesh's path and names the problem (or, for what is common in the wild, a warning),
// never a crash or a silently grey result. Every input is made by the test.
#include "appearance_fixtures.h"

#include "ngi/mesh/mesh_io.h"

using namespace appearance_fixtures;

namespace {

class MeshAppearanceHostile : public ScratchDirectory {
protected:
    // The message reading `name` with appearance throws.
    std::string error(const std::string& name) const
    {
        const fs::path path = dir_ / name;
        return errorOf(path.string(), [&] {
            ngi::MeshAppearance look;
            ngi::readMesh(path, look);
        });
    }
    // An OBJ triangle whose material's map_Kd is `texture` (as the MTL writes it).
    std::string texturedObj(const std::string& texture) const
    {
        write("look.mtl", "newmtl m\nmap_Kd " + texture + "\n");
        write("m.obj", "mtllib look.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl m\nf 1/1 2/1 3/1\n");
        return error("m.obj");
    }
    // A glTF triangle whose material's base colour texture is image 0, `image` (JSON).
    std::string texturedGltf(const std::string& image, int material = 0) const
    {
        const std::string bin = raw<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
        write("m.gltf",
              R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
          "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":)" +
                  std::to_string(material) + R"(}]}],
          "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
          "bufferViews":[{"buffer":0,"byteLength":36}],
          "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)" +
                  base64(bin) + R"("}],
          "materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
          "textures":[{"source":0}],"images":[)" +
                  image + "]}");
        return error("m.gltf");
    }
    std::string dataUri(const std::string& mime, const std::string& bytes) const
    {
        return R"({"uri":"data:)" + mime + ";base64," + base64(bytes) + "\"}";
    }
};

TEST_F(MeshAppearanceHostile, MissingTextureIsAnErrorNamingIt)
{
    const std::string message = texturedObj("textures/missing.png");
    EXPECT_CONTAINS(message, "texture " + (dir_ / "textures/missing.png").string() + " does not exist");
    EXPECT_CONTAINS(texturedGltf(R"({"uri":"gone.jpg"})"), (dir_ / "gone.jpg").string() + " does not exist");
}

TEST_F(MeshAppearanceHostile, TexturesBeyondTheSizeLimitAreRefusedFromTheirHeader)
{
    write("huge.png", pngHeaderOnly(100000, 100000));
    EXPECT_CONTAINS(texturedObj("huge.png"), "is 100000 x 100000 pixels, beyond the limit of 16384 per side");
    write("huge.jpg", jpegClaiming(65000, 65000));
    EXPECT_CONTAINS(texturedObj("huge.jpg"), "is 65000 x 65000 pixels, beyond the limit");
    // Within each side's limit, beyond the pixel count: 16384 x 16385 is refused too.
    EXPECT_CONTAINS(texturedGltf(dataUri("image/png", pngHeaderOnly(16384, 16385))), "16384 x 16385 pixels");
}

TEST_F(MeshAppearanceHostile, CorruptAndTruncatedJpegAndPngAreErrors)
{
    const std::string jpeg = jpegBytes(16, 16, std::vector<uint8_t>(16 * 16 * 3, 90));
    write("cut.jpg", jpeg.substr(0, jpeg.size() / 2));
    EXPECT_CONTAINS(texturedObj("cut.jpg"), "texture " + (dir_ / "cut.jpg").string() + ": corrupt JPEG");
    write("garbage.jpg", std::string("\xFF\xD8\xFF", 3) + std::string(200, '\x17'));
    EXPECT_CONTAINS(texturedObj("garbage.jpg"), "corrupt JPEG");
    const std::string png = pngBytes(dir_ / "scratch.png", 16, 16, std::vector<uint8_t>(16 * 16 * 4, 200));
    write("cut.png", png.substr(0, png.size() - 20));
    EXPECT_CONTAINS(texturedObj("cut.png"), "corrupt PNG");
    std::string flipped = png;
    flipped[flipped.size() / 2] ^= 0x55;  // inside IDAT: its CRC fails
    EXPECT_CONTAINS(texturedGltf(dataUri("image/png", flipped)), "corrupt PNG");
    write("not-an-image.bmp", "BM" + std::string(60, '\0'));
    EXPECT_CONTAINS(texturedObj("not-an-image.bmp"), "unsupported image format (it looks like BMP)");
}

TEST_F(MeshAppearanceHostile, NanAndInfiniteTextureCoordinatesAreErrors)
{
    write("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt nan 0\nf 1/1 2/2 3/1\n");
    EXPECT_CONTAINS(error("nan.obj"), "line 5: texture coordinate 'nan' is NaN or infinite");
    write("inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 1e999\nf 1/1 2/1 3/1\n");
    EXPECT_CONTAINS(error("inf.obj"), "is NaN or infinite");
    const std::string bin = raw<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}) + raw<float>({0, 0, 1, 0, std::nanf(""), 1});
    write("nan.gltf",
          R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1}}]}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},
                   {"bufferView":1,"componentType":5126,"count":3,"type":"VEC2"}],
      "bufferViews":[{"buffer":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":24}],
      "buffers":[{"byteLength":60,"uri":"data:application/octet-stream;base64,)" +
              base64(bin) + R"("}]})");
    EXPECT_CONTAINS(error("nan.gltf"), "accessor 1 (TEXCOORD_0) element 2 is NaN or infinite");
}

TEST_F(MeshAppearanceHostile, Gltf1IsRefusedAsSuch)
{
    write("old.gltf", R"({"asset":{"version":"1.0"},"scene":"s","scenes":{"s":{"nodes":[]}}})");
    EXPECT_CONTAINS(error("old.gltf"), "glTF 1.0 is not supported");
    // Files tinygltf cannot even parse: a 1.0 JSON without an asset (its meshes a dictionary),
    // and a binary container of version 1 (KHR_binary_glTF).
    write("noasset.gltf", R"({"meshes":{"m":{"primitives":[]}},"scene":"s","scenes":{"s":{"nodes":[]}}})");
    EXPECT_CONTAINS(error("noasset.gltf"), "glTF 1.0 is not supported");
    write("number.gltf", R"({"asset":{"version":1},"meshes":{"m":{"primitives":[]}}})");
    EXPECT_CONTAINS(error("number.gltf"), "glTF 1.0 is not supported");
    std::string glb("glTF\x01\0\0\0\x14\0\0\0\0\0\0\0\0\0\0\0", 20);
    write("old.glb", glb);
    EXPECT_CONTAINS(error("old.glb"), "glTF 1.0 is not supported");
    // A 1.0 container with its scene and body (as assimp's BoxTextured.glb): its body's first
    // word is no chunk length, which 2.0's chunk check would read as one.
    std::string scene = R"({"a":1})";
    std::string body("\0\0\x01\0\0\0\0\0", 8);
    std::string full("glTF\x01\0\0\0", 8);
    const uint32_t sizes[3] = {uint32_t(20 + scene.size() + body.size()), uint32_t(scene.size()), 0};
    full.append(reinterpret_cast<const char*>(sizes), sizeof sizes);
    write("old-body.glb", full + scene + body);
    EXPECT_CONTAINS(error("old-body.glb"), "glTF 1.0 is not supported");
    // A 2.0 file that fails to parse keeps the parser's message.
    write("broken.gltf", R"({"asset":{"version":"2.0"},"accessors":[{"bufferView":7}]})");
    EXPECT_EQ(error("broken.gltf").find("glTF 1.0"), std::string::npos);
}

TEST_F(MeshAppearanceHostile, GltfIndicesOutOfRangeAreErrors)
{
    const std::string png = dataUri("image/png", pngBytes(dir_ / "scratch.png", 1, 1, {1, 2, 3, 4}));
    EXPECT_CONTAINS(texturedGltf(png, 3), "glTF material 3 does not exist (the file has 1 materials)");
    // Texture 0 names image 0 of none.
    EXPECT_CONTAINS(texturedGltf(""), "refers to image 0, which does not exist (the file has 0 images)");
}

TEST_F(MeshAppearanceHostile, UnknownUsemtlIsAWarningAndGetsTheDefaultMaterial)
{
    write("look.mtl", "newmtl known\nKd 0 1 0\n");
    write("m.obj",
          "mtllib look.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nusemtl known\nf 1 2 3\nusemtl unknown\nf 2 4 3\n");
    ngi::MeshAppearance look;
    ngi::readMesh(dir_ / "m.obj", look);
    EXPECT_EQ(look.triangleMaterial, (std::vector<uint32_t>{0, 1}));
    EXPECT_EQ(look.materials[1].name, "default");
    ASSERT_EQ(look.warnings.size(), 1u);
    EXPECT_EQ(look.warnings[0].rfind((dir_ / "m.obj").string() + ": usemtl 'unknown'", 0), 0u) << look.warnings[0];
}

TEST_F(MeshAppearanceHostile, MaterialLibrariesAndTexturesOutsideTheMeshDirectoryAreRefused)
{
    write("outside.mtl", "newmtl m\n");
    write("mesh/m.obj", "mtllib ../outside.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const std::string message = error("mesh/m.obj");
    EXPECT_CONTAINS(message,
                    "refusing to read the material library '../outside.mtl' (" + (dir_ / "outside.mtl").string() + ")");
    EXPECT_CONTAINS(message, "directory of the mesh (" + (dir_ / "mesh").string() + ")");
    write("mesh/abs.obj", "mtllib /etc/passwd\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_CONTAINS(error("mesh/abs.obj"), "refusing to read the material library '/etc/passwd'");
    EXPECT_CONTAINS(texturedObj("../../secret.png"), "refusing to read the texture '../../secret.png'");
    EXPECT_CONTAINS(texturedGltf(R"({"uri":"../x.png"})"), "refusing to read");
}

TEST_F(MeshAppearanceHostile, MissingMaterialLibraryIsAWarning)
{
    write("m.obj", "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl x\nf 1 2 3\n");
    ngi::MeshAppearance look;
    ngi::readMesh(dir_ / "m.obj", look);
    EXPECT_TRUE(look.materials.empty());
    ASSERT_EQ(look.warnings.size(), 2u);
    EXPECT_CONTAINS(look.warnings[0],
                    "line 1: the material library " + (dir_ / "nowhere.mtl").string() + " does not exist");
    EXPECT_CONTAINS(look.warnings[1], "usemtl 'x' names no material");
}

TEST_F(MeshAppearanceHostile, MemoryReadsUseOnlyEmbeddedImages)
{
    texturedGltf(R"({"uri":"beside.png"})");
    const std::string file = readBytes(dir_ / "m.gltf");
    const std::span bytes(reinterpret_cast<const uint8_t*>(file.data()), file.size());
    const std::string message = errorOf("buffer", [&] {
        ngi::MeshAppearance look;
        ngi::readMeshFromMemory(bytes, ".gltf", "buffer", look);
    });
    EXPECT_CONTAINS(message, "a mesh read from memory may only use embedded data");
    EXPECT_EQ(ngi::readMeshFromMemory(bytes, ".gltf", "buffer").triangles.size(), 1u);  // geometry only: no image read
    const std::string obj = "mtllib look.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    ngi::MeshAppearance look;
    ngi::readMeshFromMemory(std::span(reinterpret_cast<const uint8_t*>(obj.data()), obj.size()), "obj", "buffer", look);
    ASSERT_EQ(look.warnings.size(), 1u);
    EXPECT_CONTAINS(look.warnings[0], "buffer: line 1: mtllib not read");
}

TEST_F(MeshAppearanceHostile, AnImageNoUsedMaterialNamesIsNotDecoded)
{
    const std::string bin = raw<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
    write("m.gltf",
          R"({"asset":{"version":"2.0"},"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],
      "meshes":[{"primitives":[{"attributes":{"POSITION":0},"material":0}]}],
      "accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],
      "bufferViews":[{"buffer":0,"byteLength":36}],
      "buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)" +
              base64(bin) + R"("}],
      "materials":[{"pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1]}},{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],
      "textures":[{"source":0}],"images":[{"uri":"data:image/png;base64,AAAA"}]})");
    ngi::MeshAppearance look;
    ngi::readMesh(dir_ / "m.gltf", look);
    ASSERT_EQ(look.materials.size(), 1u);
    EXPECT_EQ(look.materials[0].baseColorFactor, glm::dvec4(1, 0, 0, 1));
    EXPECT_TRUE(look.images.empty());
}

TEST_F(MeshAppearanceHostile, Utf16ObjIsRefusedWithAClearMessage)
{
    write("wide.obj",
          std::string("\xFF\xFEv\0 \0"
                      "0\0",
                      8));
    EXPECT_CONTAINS(error("wide.obj"), "is UTF-16 text; save it as UTF-8");
    EXPECT_CONTAINS(errorOf((dir_ / "wide.obj").string(), [&] { ngi::readMesh(dir_ / "wide.obj"); }), "UTF-16");
    write("marked.obj", "\xEF\xBB\xBFv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");  // a UTF-8 mark is skipped
    EXPECT_EQ(ngi::readMesh(dir_ / "marked.obj").positions.size(), 3u);
}

TEST_F(MeshAppearanceHostile, NonFiniteVertexColoursAreErrors)
{
    write("c.obj", "v 0 0 0 nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_CONTAINS(error("c.obj"), "line 1: vertex colour 'nan' is not a finite number");
    write("c.ply",
          "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "property float red\nproperty float green\nproperty float blue\nelement face 1\n"
          "property list uchar int vertex_indices\nend_header\n0 0 0 inf 0 0\n1 0 0 0 0 0\n0 1 0 0 0 0\n3 0 1 2\n");
    EXPECT_CONTAINS(error("c.ply"), "vertex 0 has a NaN or infinite colour");
}

}  // namespace
