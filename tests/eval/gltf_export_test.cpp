// The drawn mesh as a textured mesh (asset_appearance.h) and its glTF export (gltf_export.h):
// each vertex samples its chart's texel, and the file reads back through ngi's own reader with
// the same positions, texture coordinates, texels and materials.
#include "ngi/error.h"
#include "ngi/eval/asset_appearance.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/eval/gltf_export.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/surface_color.h"

#include "test_meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

namespace {

// The ripple asset with a base colour image at level 1 (33 x 33 texels) of a pattern that
// tells every texel from its neighbours.
ngi::Asset colouredRipple()
{
    ngi::Asset asset = ngi::test::rippleAsset();
    ngi::AssetChart& chart = asset.charts[0];
    chart.baseColorLevel = 1;
    const uint32_t size = chart.baseColorSize();
    for (uint32_t y = 0; y < size; ++y)
        for (uint32_t x = 0; x < size; ++x)
            chart.baseColor.insert(chart.baseColor.end(),
                                   {uint8_t(7 * x), uint8_t(5 * y + 3), uint8_t((x * y) % 251), 255});
    return asset;
}

const uint8_t* texel(const ngi::AssetChart& chart, uint32_t x, uint32_t y)
{
    return chart.baseColor.data() + (size_t(y) * chart.baseColorSize() + x) * 4;
}

ngi::AssetMesh drawnAt(const ngi::Asset& asset, float lod)
{
    ngi::AssetMeshOptions o;
    o.lod = lod;
    return ngi::assetMesh(asset, o);
}

// At LoD 1 the grid is the colour image's own (33 x 33), at LoD 0 every other vertex is on a
// texel: a glTF viewer's bilinear lookup at the exported texture coordinate reads that texel.
TEST(AssetAppearance, eachVertexOnATexelSamplesThatTexel)
{
    const ngi::Asset asset = colouredRipple();
    const ngi::AssetChart& chart = asset.charts[0];
    for (float lod : {0.0f, 1.0f}) {
        const ngi::AssetMesh drawn = drawnAt(asset, lod);
        const ngi::MeshAppearance appearance = ngi::assetMeshAppearance(asset, drawn);
        ASSERT_EQ(appearance.cornerUVs.size(), drawn.mesh.triangles.size() * 3);
        const ngi::SurfaceColor colour(drawn.mesh, appearance);
        const uint32_t last = chart.baseColorSize() - 1;
        size_t checked = 0;
        for (uint32_t t = 0; t < drawn.mesh.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) {
                const glm::dvec2 at = drawn.chartUVs[drawn.mesh.triangles[t][k]] * double(last);
                if (std::abs(at.x - std::round(at.x)) > 1e-9 || std::abs(at.y - std::round(at.y)) > 1e-9) continue;
                glm::dvec3 bary(0.0);
                bary[k] = 1.0;
                const glm::dvec4 c = colour.baseColor(t, bary, 1e-6);
                const uint8_t* expected = texel(chart, uint32_t(std::round(at.x)), uint32_t(std::round(at.y)));
                for (int channel = 0; channel < 3; ++channel)
                    ASSERT_EQ(std::lround(255.0 * ngi::linearToSrgb(c[channel])), expected[channel])
                        << "lod " << lod << " uv " << at.x << ", " << at.y << " channel " << channel;
                ++checked;
            }
        EXPECT_GT(checked, size_t(33 * 33)) << lod;
    }
}

TEST(AssetAppearance, chartsWithoutColourGetTheDefaultMaterialAndNoColourNoAppearance)
{
    ngi::Asset asset = colouredRipple();
    ngi::AssetChart plain = ngi::test::rippleAsset().charts[0];
    asset.charts.push_back(plain);
    const ngi::AssetMesh drawn = drawnAt(asset, 2.0f);
    const ngi::MeshAppearance appearance = ngi::assetMeshAppearance(asset, drawn);
    ASSERT_EQ(appearance.materials.size(), 2u);
    EXPECT_EQ(appearance.materials[0].name, "chart 0");
    EXPECT_EQ(appearance.materials[0].baseColorTexture.image, 0);
    EXPECT_EQ(appearance.materials[0].baseColorTexture.wrapU, ngi::TextureWrap::ClampToEdge);
    EXPECT_EQ(appearance.materials[0].metallicFactor, 0.0);
    EXPECT_EQ(appearance.materials[1].name, "default");
    EXPECT_FALSE(appearance.materials[1].baseColorTexture.present());
    ASSERT_EQ(appearance.images.size(), 1u);
    EXPECT_EQ(appearance.images[0].width, 33u);
    for (size_t t = 0; t < drawn.mesh.triangles.size(); ++t)
        ASSERT_EQ(appearance.triangleMaterial[t], drawn.triangleChart[t]);

    const ngi::Asset grey = ngi::test::rippleAsset();
    EXPECT_TRUE(ngi::assetMeshAppearance(grey, drawnAt(grey, 0.0f)).empty());
    ngi::AssetMesh incomplete = drawnAt(asset, 2.0f);
    incomplete.triangleChart.clear();
    EXPECT_THROW(ngi::assetMeshAppearance(asset, incomplete), ngi::Error);
}

TEST(AssetAppearance, theAlphaModeFollowsTheChartsAlpha)
{
    // Alpha all 255: opaque; only 0 and 255: a mask at 0.5; anything between: a blend.
    ngi::Asset asset = colouredRipple();
    const auto modeWith = [&](uint8_t first, uint8_t second) {
        std::vector<uint8_t>& rgba = asset.charts[0].baseColor;
        rgba[3] = first, rgba[7] = second;
        return ngi::assetMeshAppearance(asset, drawnAt(asset, 2.0f)).materials[0];
    };
    EXPECT_EQ(modeWith(255, 255).alphaMode, ngi::AlphaMode::Opaque);
    const ngi::Material mask = modeWith(0, 255);
    EXPECT_EQ(mask.alphaMode, ngi::AlphaMode::Mask);
    EXPECT_EQ(mask.alphaCutoff, 0.5);
    EXPECT_EQ(modeWith(0, 128).alphaMode, ngi::AlphaMode::Blend);
}

TEST(AssetAppearance, adaptiveMeshesCarryTheirTilesUvs)
{
    const ngi::Asset asset = colouredRipple();
    ngi::AssetMeshOptions o;
    ngi::AdaptiveView view;
    view.maxError = 0.01f;
    o.adaptive = view;
    const ngi::AssetMesh drawn = ngi::assetMesh(asset, o);
    ASSERT_EQ(drawn.chartUVs.size(), drawn.mesh.positions.size());
    ASSERT_EQ(drawn.normals.size(), drawn.mesh.positions.size());
    for (const glm::dvec2& uv : drawn.chartUVs) {
        ASSERT_GE(std::min(uv.x, uv.y), 0.0);
        ASSERT_LE(std::max(uv.x, uv.y), 1.0);
    }
    EXPECT_EQ(ngi::assetMeshAppearance(asset, drawn).cornerUVs.size(), drawn.mesh.triangles.size() * 3);
}

// Both containers read back through readMeshFromMemory: the same triangles in the same order,
// positions to float precision, texture coordinates to float precision, the texels exactly.
TEST(GltfExport, theDrawnMeshReadsBackWithItsUvsTexelsAndMaterials)
{
    ngi::Asset asset = colouredRipple();
    asset.charts.push_back(ngi::test::rippleAsset().charts[0]);  // a chart without colour
    const ngi::AssetMesh drawn = drawnAt(asset, 1.0f);
    const ngi::MeshAppearance appearance = ngi::assetMeshAppearance(asset, drawn);
    for (ngi::GltfContainer container : {ngi::GltfContainer::Binary, ngi::GltfContainer::Embedded}) {
        const std::vector<uint8_t> bytes = ngi::encodeGltf(drawn.mesh, appearance, drawn.normals, container);
        const bool binary = container == ngi::GltfContainer::Binary;
        ngi::MeshAppearance back;
        const ngi::TriangleMesh mesh = ngi::readMeshFromMemory(bytes, binary ? ".glb" : ".gltf", "drawn", back);
        ASSERT_EQ(mesh.triangles.size(), drawn.mesh.triangles.size());
        ASSERT_EQ(back.cornerUVs.size(), appearance.cornerUVs.size());
        for (size_t t = 0; t < mesh.triangles.size(); ++t)
            for (int k = 0; k < 3; ++k) {
                const glm::dvec3 p = mesh.positions[mesh.triangles[t][k]],
                                 q = drawn.mesh.positions[drawn.mesh.triangles[t][k]];
                ASSERT_LT(glm::length(p - q), 1e-5) << t;
                ASSERT_LT(glm::length(back.cornerUVs[t * 3 + k] - appearance.cornerUVs[t * 3 + k]), 1e-7) << t;
            }
        EXPECT_EQ(back.triangleMaterial, appearance.triangleMaterial);
        ASSERT_EQ(back.materials.size(), 2u);
        EXPECT_EQ(back.materials[0].name, "chart 0");
        EXPECT_EQ(back.materials[1].name, "default");
        EXPECT_EQ(back.materials[0].baseColorTexture.wrapU, ngi::TextureWrap::ClampToEdge);
        EXPECT_EQ(back.materials[0].baseColorTexture.wrapV, ngi::TextureWrap::ClampToEdge);
        EXPECT_EQ(back.materials[0].metallicFactor, 0.0);
        ASSERT_GE(back.materials[0].baseColorTexture.image, 0);
        const ngi::TextureImage& image = back.images[size_t(back.materials[0].baseColorTexture.image)];
        EXPECT_EQ(image.width, 33u);
        EXPECT_EQ(image.height, 33u);
        EXPECT_EQ(image.rgba, asset.charts[0].baseColor);
        EXPECT_TRUE(back.warnings.empty()) << back.warnings.front();
    }
}

TEST(GltfExport, glbContainerIsWellFormed)
{
    const ngi::Asset asset = colouredRipple();
    const ngi::AssetMesh drawn = drawnAt(asset, 3.0f);
    const std::vector<uint8_t> glb =
        ngi::encodeGltf(drawn.mesh, ngi::assetMeshAppearance(asset, drawn), drawn.normals, ngi::GltfContainer::Binary);
    auto u32 = [&](size_t at) {
        uint32_t v;
        std::memcpy(&v, glb.data() + at, 4);
        return v;
    };
    ASSERT_GE(glb.size(), 28u);
    EXPECT_EQ(u32(0), 0x46546C67u);
    EXPECT_EQ(u32(4), 2u);
    EXPECT_EQ(u32(8), glb.size());
    const uint32_t json = u32(12);
    EXPECT_EQ(json % 4, 0u);
    EXPECT_EQ(u32(16), 0x4E4F534Au);
    EXPECT_EQ(u32(20 + json + 4), 0x004E4942u);
    EXPECT_EQ(20 + json + 8 + u32(20 + json), glb.size());
}

TEST(GltfExport, rejectsWhatItCannotWrite)
{
    const ngi::Asset asset = colouredRipple();
    const ngi::AssetMesh drawn = drawnAt(asset, 4.0f);
    const ngi::MeshAppearance good = ngi::assetMeshAppearance(asset, drawn);
    const auto binary = ngi::GltfContainer::Binary;
    EXPECT_THROW(ngi::encodeGltf(ngi::TriangleMesh{}, {}, {}, binary), ngi::Error);
    ngi::MeshAppearance shortUVs = good;
    shortUVs.cornerUVs.pop_back();
    EXPECT_THROW(ngi::encodeGltf(drawn.mesh, shortUVs, {}, binary), ngi::Error);
    ngi::MeshAppearance badMaterial = good;
    badMaterial.triangleMaterial[0] = 7;
    EXPECT_THROW(ngi::encodeGltf(drawn.mesh, badMaterial, {}, binary), ngi::Error);
    ngi::MeshAppearance transformed = good;
    transformed.materials[0].baseColorTexture.transform[2][0] = 0.5;
    EXPECT_THROW(ngi::encodeGltf(drawn.mesh, transformed, {}, binary), ngi::Error);
    std::vector<glm::dvec3> normals = drawn.normals;
    normals.pop_back();
    EXPECT_THROW(ngi::encodeGltf(drawn.mesh, good, normals, binary), ngi::Error);
    EXPECT_TRUE(ngi::isGltfPath("a/B.GLB"));
    EXPECT_TRUE(ngi::isGltfPath("x.gltf"));
    EXPECT_FALSE(ngi::isGltfPath("x.obj"));
}

}  // namespace
