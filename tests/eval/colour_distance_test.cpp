// The colour metric (colour_distance.h) on procedural textured squares: identical surfaces,
// a known constant shift of one channel, a candidate tessellated and offset differently, a
// texture transform, and its errors.
#include "ngi/error.h"
#include "ngi/eval/colour_distance.h"
#include "ngi/mesh/surface_color.h"

#include <gtest/gtest.h>

#include <cmath>

namespace {

// The unit square z = height in the xy plane, n x n quads, split along `mainDiagonal` or the
// other one, with texture coordinates (x, y) * uvScale per corner.
struct TexturedSquare {
    ngi::TriangleMesh mesh;
    ngi::MeshAppearance appearance;
};

TexturedSquare square(int n, bool mainDiagonal, double height = 0.0, double uvScale = 1.0)
{
    TexturedSquare s;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) s.mesh.positions.push_back({double(i) / n, double(j) / n, height});
    auto at = [n](int i, int j) { return uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            if (mainDiagonal)
                s.mesh.triangles.push_back({a, b, c}), s.mesh.triangles.push_back({a, c, d});
            else
                s.mesh.triangles.push_back({a, b, d}), s.mesh.triangles.push_back({b, c, d});
        }
    for (const glm::uvec3& t : s.mesh.triangles)
        for (int k = 0; k < 3; ++k) s.appearance.cornerUVs.push_back(glm::dvec2(s.mesh.positions[t[k]]) * uvScale);
    return s;
}

// A 16 x 16 texture whose red and blue vary (a gradient and a checker) and whose green is `green`.
ngi::TextureImage texture(uint8_t green)
{
    ngi::TextureImage image;
    image.name = "procedural";
    image.width = image.height = 16;
    for (uint32_t y = 0; y < 16; ++y)
        for (uint32_t x = 0; x < 16; ++x)
            image.rgba.insert(image.rgba.end(),
                              {uint8_t(16 * x + 8), green, uint8_t((x / 4 + y / 4) % 2 ? 220 : 30), 255});
    return image;
}

void addTexture(TexturedSquare& s, uint8_t green, glm::dmat3 transform = glm::dmat3(1.0))
{
    s.appearance.images.push_back(texture(green));
    ngi::Material& m = s.appearance.materials.emplace_back();
    m.baseColorTexture.image = 0;
    m.baseColorTexture.transform = transform;
    s.appearance.triangleMaterial.assign(s.mesh.triangles.size(), 0);
}

ngi::ColourDistanceOptions fewSamples()
{
    ngi::ColourDistanceOptions o;
    o.sampleCount = 20000;
    return o;
}

// Expected PSNR of a constant difference d (8-bit units) in every sample.
double psnrOf(double d) { return 20.0 * std::log10(255.0 / std::abs(d)); }

TEST(ColourDistance, identicalTexturedSurfacesHaveInfinitePsnr)
{
    TexturedSquare s = square(8, true);
    addTexture(s, 100);
    const ngi::ColourDistance d = ngi::colourDistance(s.mesh, s.appearance, s.mesh, s.appearance, fewSamples());
    EXPECT_TRUE(std::isinf(d.psnrY) && d.psnrY > 0.0);
    EXPECT_TRUE(std::isinf(d.psnrCb) && std::isinf(d.psnrCr));
    EXPECT_EQ(d.mseY, 0.0);
    EXPECT_EQ(d.sampleCount, 20000u);
    EXPECT_NEAR(d.footprint, std::sqrt(1.0 / 20000.0), 1e-12);  // unit area
}

// sRGB (100, 150, 200) against (110, 150, 200): every sample differs by 10 in red, so
// dY = 2.126, dCb = -2.126 / 1.8556, dCr = (10 - 2.126) / 1.5748 = 5, exactly (the colours are
// rounded to 8 bits before the conversion). Tolerance 1e-9 dB: only floating-point rounding.
TEST(ColourDistance, aConstantRedShiftGivesItsPsnrOnEveryChannel)
{
    auto uniform = [](const ngi::TriangleMesh& mesh, double red) {
        ngi::MeshAppearance a;
        ngi::Material& m = a.materials.emplace_back();
        m.baseColorFactor = {ngi::srgbToLinear(red / 255.0), ngi::srgbToLinear(150 / 255.0),
                             ngi::srgbToLinear(200 / 255.0), 1.0};
        a.triangleMaterial.assign(mesh.triangles.size(), 0);
        return a;
    };
    const TexturedSquare reference = square(4, true), candidate = square(3, false, 0.01);
    const ngi::ColourDistance d = ngi::colourDistance(reference.mesh, uniform(reference.mesh, 100), candidate.mesh,
                                                      uniform(candidate.mesh, 110), fewSamples());
    EXPECT_NEAR(d.psnrY, psnrOf(2.126), 1e-9);
    EXPECT_NEAR(d.psnrCb, psnrOf(2.126 / 1.8556), 1e-9);
    EXPECT_NEAR(d.psnrCr, psnrOf(5.0), 1e-9);
    EXPECT_NEAR(d.mseCr, 25.0, 1e-9);
}

// A textured reference against the same texture with green 10 higher on a candidate of another
// tessellation, lifted off the plane: the closest point and its barycentrics find the same uv,
// so every sample differs by 10 in green. Tolerance 0.05 dB: red and blue are rounded to 8 bits
// from uvs computed through two triangulations, which may round a rare sample differently.
TEST(ColourDistance, aTextureShiftIsFoundThroughTheClosestPoint)
{
    TexturedSquare reference = square(8, true), candidate = square(5, false, 0.02);
    addTexture(reference, 100);
    addTexture(candidate, 110);
    const ngi::ColourDistance d =
        ngi::colourDistance(reference.mesh, reference.appearance, candidate.mesh, candidate.appearance, fewSamples());
    EXPECT_NEAR(d.psnrY, psnrOf(7.152), 0.05);
    EXPECT_NEAR(d.psnrCb, psnrOf(7.152 / 1.8556), 0.05);
    EXPECT_NEAR(d.psnrCr, psnrOf(7.152 / 1.5748), 0.05);
}

// A candidate whose uvs are stored x64 with a texture transform of 1/64 (as a dequantizing
// glTF writer leaves them) is the same surface: the transform is applied before the texel
// density picks the mip level, so the colours match (no blur from a level 6 too coarse).
TEST(ColourDistance, appliesTheTextureTransformBeforeChoosingTheMipLevel)
{
    TexturedSquare reference = square(8, true), candidate = square(8, true, 0.0, 64.0);
    addTexture(reference, 100);
    glm::dmat3 shrink(1.0);
    shrink[0][0] = shrink[1][1] = 1.0 / 64.0;
    addTexture(candidate, 100, shrink);
    const ngi::ColourDistance d =
        ngi::colourDistance(reference.mesh, reference.appearance, candidate.mesh, candidate.appearance, fewSamples());
    EXPECT_GT(d.psnrY, 60.0);
}

TEST(ColourDistance, doesNotDependOnTheThreadCount)
{
    TexturedSquare reference = square(8, true), candidate = square(5, false, 0.02);
    addTexture(reference, 100);
    addTexture(candidate, 90);
    ngi::ColourDistanceOptions one = fewSamples(), three = fewSamples();
    one.threadCount = 1, three.threadCount = 3;
    const ngi::ColourDistance a =
        ngi::colourDistance(reference.mesh, reference.appearance, candidate.mesh, candidate.appearance, one);
    const ngi::ColourDistance b =
        ngi::colourDistance(reference.mesh, reference.appearance, candidate.mesh, candidate.appearance, three);
    EXPECT_EQ(a.mseY, b.mseY);
    EXPECT_EQ(a.mseCb, b.mseCb);
    EXPECT_EQ(a.mseCr, b.mseCr);
}

TEST(ColourDistance, rejectsAnAppearanceThatDoesNotMatchItsMeshAndNoSamples)
{
    TexturedSquare good = square(2, true), bad = square(2, true);
    addTexture(good, 100);
    addTexture(bad, 100);
    bad.appearance.cornerUVs.pop_back();
    try {
        ngi::colourDistance(good.mesh, good.appearance, bad.mesh, bad.appearance, fewSamples());
        FAIL() << "a short uv array was accepted";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("candidate mesh"), std::string::npos) << e.what();
    }
    ngi::ColourDistanceOptions none;
    none.sampleCount = 0;
    EXPECT_THROW(ngi::colourDistance(good.mesh, good.appearance, good.mesh, good.appearance, none), ngi::Error);
    EXPECT_THROW(ngi::colourDistance(good.mesh, good.appearance, ngi::TriangleMesh{}, {}, fewSamples()), ngi::Error);
}

TEST(ColourDistance, ycbcrIsBt709FullRange)
{
    const glm::dvec3 white = ngi::ycbcrBt709({255, 255, 255}), red = ngi::ycbcrBt709({255, 0, 0});
    EXPECT_NEAR(white.x, 255.0, 1e-9);
    EXPECT_NEAR(white.y, 128.0, 1e-9);
    EXPECT_NEAR(white.z, 128.0, 1e-9);
    EXPECT_NEAR(red.x, 0.2126 * 255.0, 1e-9);
    EXPECT_NEAR(red.z, 255.0 + 0.5, 1e-9);  // Cr of pure red: 0.5 * 255 + 128
    EXPECT_TRUE(std::isinf(ngi::psnr8(0.0)));
    EXPECT_NEAR(ngi::psnr8(1.0), 48.1308036, 1e-6);
}

}  // namespace
