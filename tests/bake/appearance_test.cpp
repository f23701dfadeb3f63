// The appearance stage of the bake: each chart's base colour image over its square is the
// input's colour where the chart's samples lie, from textures, vertex colours and materials.
#include "ngi/asset.h"
#include "ngi/bake/bake.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/mesh/surface_color.h"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace {

ngi::BakeOptions smallBake()
{
    ngi::BakeOptions options;
    options.resolution = 64;
    options.storeResolution = 16;
    options.remeshVertexCount = 800;
    options.sourceName = "coloured";
    return options;
}

// The colour every test surface should show at a point of the unit sphere: a linear function
// of the direction (continuous everywhere, so a texture wrapped around the sphere has no seam).
glm::dvec3 expectedSrgb(const glm::dvec3& direction) { return 0.5 + 0.4 * glm::normalize(direction); }

// A latitude-longitude texture of expectedSrgb: texel (x, y) at longitude 2 pi (x + 0.5) / W,
// colatitude pi (y + 0.5) / H.
ngi::TextureImage sphereTexture(uint32_t width, uint32_t height)
{
    ngi::TextureImage image{"sphere.png", width, height, std::vector<uint8_t>(size_t(width) * height * 4)};
    for (uint32_t y = 0; y < height; ++y)
        for (uint32_t x = 0; x < width; ++x) {
            const double phi = 2.0 * std::numbers::pi * (x + 0.5) / width,
                         theta = std::numbers::pi * (y + 0.5) / height;
            const glm::dvec3 c =
                expectedSrgb({std::cos(phi) * std::sin(theta), std::sin(phi) * std::sin(theta), std::cos(theta)});
            uint8_t* t = &image.rgba[(size_t(y) * width + x) * 4];
            for (int k = 0; k < 3; ++k) t[k] = uint8_t(std::lround(255.0 * c[k]));
            t[3] = 255;
        }
    return image;
}

// Spherical texture coordinates per corner; a triangle across the longitude wrap keeps its u
// continuous (some corners past 1, the sampler repeats).
std::vector<glm::dvec2> sphereUVs(const ngi::TriangleMesh& mesh)
{
    std::vector<glm::dvec2> uvs;
    for (const glm::uvec3& t : mesh.triangles) {
        glm::dvec2 uv[3];
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 p = glm::normalize(mesh.positions[t[k]]);
            double phi = std::atan2(p.y, p.x);
            if (phi < 0.0) phi += 2.0 * std::numbers::pi;
            uv[k] = {phi / (2.0 * std::numbers::pi), std::acos(std::clamp(p.z, -1.0, 1.0)) / std::numbers::pi};
        }
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                if (uv[j].x - uv[k].x > 0.5) uv[k].x += 1.0;
        for (const glm::dvec2& u : uv) uvs.push_back(u);
    }
    return uvs;
}

// Mean and largest difference (in 1/255 of sRGB) between a baked chart's colour image and
// expectedSrgb at the chart's samples of that level, skipping the poles (u is singular there).
std::pair<double, double> colourError(const ngi::BakeResult& result, size_t c,
                                      const glm::dvec3& centre = glm::dvec3(0.0))
{
    const ngi::AssetChart& chart = result.asset.charts[c];
    const uint32_t n = chart.baseColorSize(), step = 1u << chart.baseColorLevel;
    const ngi::GeometryImage& full = result.charts[c].fullPositions;
    double sum = 0.0, largest = 0.0;
    size_t count = 0;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const glm::dvec3 p = glm::dvec3(result.asset.offset) +
                glm::dvec3(result.asset.scale) * glm::dvec3(full.at(x * step, y * step)) - centre;
            if (std::abs(glm::normalize(p).z) > 0.95) continue;
            const glm::dvec3 want = 255.0 * expectedSrgb(p);
            const uint8_t* t = &chart.baseColor[(size_t(y) * n + x) * 4];
            for (int k = 0; k < 3; ++k) {
                const double d = std::abs(double(t[k]) - want[k]);
                sum += d, largest = std::max(largest, d), ++count;
            }
        }
    return {sum / double(count), largest};
}

}  // namespace

TEST(BakeAppearance, TextureColoursLandWhereTheSamplesLie)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(3);
    ngi::MeshAppearance appearance;
    appearance.cornerUVs = sphereUVs(sphere);
    appearance.images.push_back(sphereTexture(256, 128));
    ngi::Material material;
    material.baseColorTexture.image = 0;
    appearance.materials.push_back(material);
    ngi::BakeOptions options = smallBake();
    options.appearance = &appearance;
    const ngi::BakeResult result = ngi::bakeMesh(sphere, options);
    ASSERT_EQ(result.asset.charts.size(), 1u);
    const ngi::AssetChart& chart = result.asset.charts[0];
    ASSERT_FALSE(chart.baseColor.empty());
    // 256 x 128 texels over the sphere need about 181 samples per side: the full 65^2 grid.
    EXPECT_EQ(chart.baseColorLevel, 0u);
    EXPECT_EQ(result.report.charts[0].colorLevel, 0);
    const auto [mean, largest] = colourError(result, 0);
    // Measured 0.27 mean, 1.35 largest: texture coordinates interpolate linearly over the
    // icosphere's flat facets, so the colour found differs from the direction's slightly.
    EXPECT_LT(mean, 1.0);
    EXPECT_LT(largest, 4.0);
    // Written and read back (WebP at the default quality): still the colour of the surface.
    const ngi::Asset read = ngi::parseAsset(ngi::serializeAsset(result.asset), "coloured.ngi");
    ASSERT_EQ(read.charts[0].baseColor.size(), chart.baseColor.size());
    double coded = 0.0;
    for (size_t i = 0; i < chart.baseColor.size(); ++i)
        coded += std::abs(int(read.charts[0].baseColor[i]) - int(chart.baseColor[i]));
    EXPECT_LT(coded / double(chart.baseColor.size()), 3.0);
}

TEST(BakeAppearance, ColoursLandOnTheSurfaceFarFromTheOrigin)
{
    // The bake works relative to the input's centre; the colours are located there too.
    ngi::TriangleMesh sphere = ngi::makeSphere(3);
    ngi::MeshAppearance appearance;
    appearance.cornerUVs = sphereUVs(sphere);
    appearance.images.push_back(sphereTexture(256, 128));
    ngi::Material material;
    material.baseColorTexture.image = 0;
    appearance.materials.push_back(material);
    const glm::dvec3 centre(3000.0, -2000.0, 500.0);
    for (glm::dvec3& p : sphere.positions) p += centre;
    ngi::BakeOptions options = smallBake();
    options.appearance = &appearance;
    const ngi::BakeResult result = ngi::bakeMesh(sphere, options);
    const auto [mean, largest] = colourError(result, 0, centre);
    EXPECT_LT(mean, 1.0);  // as at the origin (0.27, 1.35), up to the float offset's rounding
    EXPECT_LT(largest, 4.0);
}

TEST(BakeAppearance, VertexColoursAndAMaterialFactorMultiply)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(3);
    ngi::MeshAppearance appearance;
    for (const glm::uvec3& t : sphere.triangles)
        for (int k = 0; k < 3; ++k) {
            const glm::dvec3 s = expectedSrgb(sphere.positions[t[k]]);
            appearance.cornerColors.push_back(glm::vec4(float(ngi::srgbToLinear(s.x)), float(ngi::srgbToLinear(s.y)),
                                                        float(ngi::srgbToLinear(s.z)), 1.0f));
        }
    ngi::BakeOptions options = smallBake();
    options.appearance = &appearance;
    const ngi::BakeResult result = ngi::bakeMesh(sphere, options);
    const auto [mean, largest] = colourError(result, 0);
    EXPECT_LT(mean, 1.0);  // measured 0.31, 1.05: interpolated in linear light over facets
    EXPECT_LT(largest, 4.0);
    // A material factor of one half in linear light scales every texel (sRGB-encoded).
    ngi::Material half;
    half.baseColorFactor = {0.5, 0.5, 0.5, 1.0};
    appearance.materials.push_back(half);
    const ngi::BakeResult halved = ngi::bakeMesh(sphere, options);
    const std::vector<uint8_t>& a = result.asset.charts[0].baseColor;
    const std::vector<uint8_t>& b = halved.asset.charts[0].baseColor;
    ASSERT_EQ(a.size(), b.size());
    double worst = 0.0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (i % 4 == 3) continue;
        const double want = 255.0 * ngi::linearToSrgb(0.5 * ngi::srgbToLinear(a[i] / 255.0));
        worst = std::max(worst, std::abs(want - b[i]));
    }
    EXPECT_LE(worst, 1.01) << "rounding only";
}

TEST(BakeAppearance, OneColourNeedsOnlyTheCoarsestLevelAndNoAppearanceNone)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(2);
    ngi::MeshAppearance appearance;
    ngi::Material red;
    red.baseColorFactor = {1.0, 0.0, 0.0, 1.0};
    appearance.materials.push_back(red);
    ngi::BakeOptions options = smallBake();
    options.appearance = &appearance;
    const ngi::BakeResult result = ngi::bakeMesh(sphere, options);
    const ngi::AssetChart& chart = result.asset.charts[0];
    EXPECT_EQ(chart.baseColorSize(), 2u);
    for (size_t i = 0; i < chart.baseColor.size(); i += 4) {
        EXPECT_EQ(chart.baseColor[i], 255);
        EXPECT_EQ(chart.baseColor[i + 1], 0);
    }
    options.appearance = nullptr;
    EXPECT_TRUE(ngi::bakeMesh(sphere, options).asset.charts[0].baseColor.empty());
}

TEST(BakeAppearance, TheAlphaIsTheCoverageTheMaterialsAlphaModeDraws)
{
    // The sphere's texture: alpha 0.8 on the upper half (z > 0), 0.3 on the lower.
    const ngi::TriangleMesh sphere = ngi::makeSphere(3);
    ngi::MeshAppearance appearance;
    appearance.cornerUVs = sphereUVs(sphere);
    appearance.images.push_back(sphereTexture(64, 32));
    ngi::TextureImage& image = appearance.images[0];
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x)
            image.rgba[(size_t(y) * image.width + x) * 4 + 3] = y < image.height / 2 ? 204 : 77;
    ngi::Material material;
    material.baseColorTexture.image = 0;
    appearance.materials.push_back(material);
    // Away from the equator (|z| > 0.3, where the texture's two halves do not blend): opaque
    // draws everything, a mask at 0.5 the upper half only, a blend the texture's alpha.
    auto alphaAt = [&](ngi::AlphaMode mode, const glm::dvec3& direction) {
        appearance.materials[0].alphaMode = mode;
        const ngi::SurfaceColor colour(sphere, appearance);
        double best = -1.0, alpha = 0.0;
        for (uint32_t t = 0; t < sphere.triangles.size(); ++t) {
            const glm::uvec3& tri = sphere.triangles[t];
            const glm::dvec3 centre =
                (sphere.positions[tri.x] + sphere.positions[tri.y] + sphere.positions[tri.z]) / 3.0;
            const double along = glm::dot(glm::normalize(centre), direction);
            if (along > best) best = along, alpha = colour.baseColor(t, glm::dvec3(1.0 / 3.0), 1e-3).a;
        }
        return alpha;
    };
    const glm::dvec3 up = glm::normalize(glm::dvec3(0.3, 0.2, 0.8)), down = glm::normalize(glm::dvec3(0.2, -0.4, -0.7));
    EXPECT_EQ(alphaAt(ngi::AlphaMode::Opaque, up), 1.0);
    EXPECT_EQ(alphaAt(ngi::AlphaMode::Opaque, down), 1.0);
    EXPECT_EQ(alphaAt(ngi::AlphaMode::Mask, up), 1.0);
    EXPECT_EQ(alphaAt(ngi::AlphaMode::Mask, down), 0.0);
    EXPECT_NEAR(alphaAt(ngi::AlphaMode::Blend, up), 0.8, 0.01);
    EXPECT_NEAR(alphaAt(ngi::AlphaMode::Blend, down), 0.3, 0.01);

    // Baked with the mask: every texel is 0 or 255, both occur, and a texel's alpha follows the
    // side of the sphere its sample lies on.
    appearance.materials[0].alphaMode = ngi::AlphaMode::Mask;
    ngi::BakeOptions options = smallBake();
    options.appearance = &appearance;
    const ngi::BakeResult result = ngi::bakeMesh(sphere, options);
    const ngi::AssetChart& chart = result.asset.charts[0];
    const uint32_t n = chart.baseColorSize(), step = 1u << chart.baseColorLevel;
    size_t covered = 0, uncovered = 0;
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            const uint8_t alpha = chart.baseColor[(size_t(y) * n + x) * 4 + 3];
            ASSERT_TRUE(alpha == 0 || alpha == 255) << int(alpha);
            const double z = result.asset.offset[2] +
                result.asset.scale[2] * double(result.charts[0].fullPositions.at(x * step, y * step).z);
            if (std::abs(z) < 0.2) continue;
            EXPECT_EQ(alpha, z > 0.0 ? 255 : 0) << "z " << z;
            ++(alpha ? covered : uncovered);
        }
    EXPECT_GT(covered, n * n / 5);
    EXPECT_GT(uncovered, n * n / 5);
}
