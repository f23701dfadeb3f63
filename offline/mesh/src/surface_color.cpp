// ngi offline: the input surface's base colour at a point (surface_color.h).
#include "ngi/mesh/surface_color.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace ngi {
namespace {

const Material kDefaultMaterial{};
// Samples a triangle of vertex colours (or one material among several) needs: its colour
// varies linearly inside and jumps at its edges, which the image resolves with about 6 x 6.
constexpr double kSamplesPerTriangle = 32.0;

// A texture coordinate wrapped into [0, 1] by the sampler's mode.
double wrap(double t, TextureWrap mode)
{
    if (!std::isfinite(t)) return 0.0;
    switch (mode) {
    case TextureWrap::ClampToEdge: return std::clamp(t, 0.0, 1.0);
    case TextureWrap::MirroredRepeat: {
        const double f = t - 2.0 * std::floor(t * 0.5);  // [0, 2)
        return f <= 1.0 ? f : 2.0 - f;
    }
    case TextureWrap::Repeat:
    default: return t - std::floor(t);
    }
}

// Texel (x, y) of a level with the sampler's wrap applied to integer coordinates.
int wrapIndex(long i, uint32_t n, TextureWrap mode)
{
    const long size = long(n);
    if (mode == TextureWrap::Repeat) return int(((i % size) + size) % size);
    if (mode == TextureWrap::MirroredRepeat) {
        long m = ((i % (2 * size)) + 2 * size) % (2 * size);
        return int(m < size ? m : 2 * size - 1 - m);
    }
    return int(std::clamp(i, 0L, size - 1));
}

}  // namespace

SurfaceColor::SurfaceColor(const TriangleMesh& mesh, const MeshAppearance& appearance)
    : mesh_(mesh), appearance_(appearance)
{
    const size_t triangles = mesh.triangles.size();
    const MeshAppearance& a = appearance;
    if (!a.cornerUVs.empty() && a.cornerUVs.size() != triangles * 3)
        throw Error("appearance: " + std::to_string(a.cornerUVs.size()) + " texture coordinates for " +
                    std::to_string(triangles) + " triangles");
    if (!a.cornerColors.empty() && a.cornerColors.size() != triangles * 3)
        throw Error("appearance: " + std::to_string(a.cornerColors.size()) + " vertex colours for " +
                    std::to_string(triangles) + " triangles");
    if (!a.triangleMaterial.empty() && a.triangleMaterial.size() != triangles)
        throw Error("appearance: " + std::to_string(a.triangleMaterial.size()) + " material indices for " +
                    std::to_string(triangles) + " triangles");
    for (uint32_t m : a.triangleMaterial)
        if (m >= a.materials.size())
            throw Error("appearance: material index " + std::to_string(m) + " of " +
                        std::to_string(a.materials.size()) + " materials");
    for (const Material& m : a.materials)
        if (m.baseColorTexture.image >= int32_t(a.images.size()))
            throw Error("appearance: material '" + m.name + "' uses image " + std::to_string(m.baseColorTexture.image) +
                        " of " + std::to_string(a.images.size()));

    // Mip pyramids of the base colour textures in use, box-filtered in linear light.
    pyramids_.resize(a.images.size());
    const bool textured = !a.cornerUVs.empty();
    for (const Material& m : a.materials) {
        if (!textured || !m.baseColorTexture.present()) continue;
        Pyramid& p = pyramids_[size_t(m.baseColorTexture.image)];
        if (!p.levels.empty()) continue;
        const TextureImage& image = a.images[size_t(m.baseColorTexture.image)];
        if (image.width == 0 || image.height == 0 || image.rgba.size() != size_t(image.width) * image.height * 4)
            throw Error("appearance: image '" + image.name + "' has no texels or the wrong number of them");
        std::vector<glm::vec4> base(size_t(image.width) * image.height);
        const std::array<float, 256>& table = srgb8ToLinear();
        for (size_t i = 0; i < base.size(); ++i)
            base[i] = {table[image.rgba[i * 4]], table[image.rgba[i * 4 + 1]], table[image.rgba[i * 4 + 2]],
                       image.rgba[i * 4 + 3] / 255.0f};
        p.widths.push_back(image.width), p.heights.push_back(image.height), p.levels.push_back(std::move(base));
        while (p.widths.back() > 1 || p.heights.back() > 1) {
            const uint32_t w = p.widths.back(), h = p.heights.back();
            const uint32_t nw = std::max(1u, w / 2), nh = std::max(1u, h / 2);
            const std::vector<glm::vec4>& fine = p.levels.back();
            std::vector<glm::vec4> coarse(size_t(nw) * nh);
            for (uint32_t y = 0; y < nh; ++y)
                for (uint32_t x = 0; x < nw; ++x) {
                    const uint32_t x0 = std::min(2 * x, w - 1), x1 = std::min(2 * x + 1, w - 1);
                    const uint32_t y0 = std::min(2 * y, h - 1), y1 = std::min(2 * y + 1, h - 1);
                    coarse[size_t(y) * nw + x] = 0.25f *
                        (fine[size_t(y0) * w + x0] + fine[size_t(y0) * w + x1] + fine[size_t(y1) * w + x0] +
                         fine[size_t(y1) * w + x1]);
                }
            p.widths.push_back(nw), p.heights.push_back(nh), p.levels.push_back(std::move(coarse));
        }
    }

    // Per triangle: texels per unit area; the density the colour needs.
    texelsPerArea_.assign(triangles, 0.0);
    double area = 0.0, weighted = 0.0;
    for (size_t t = 0; t < triangles; ++t) {
        const glm::uvec3 tri = mesh.triangles[t];
        const double a3 = 0.5 *
            glm::length(glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x],
                                   mesh.positions[tri.z] - mesh.positions[tri.x]));
        if (!(a3 > 0.0)) continue;
        const Material& m = a.triangleMaterial.empty() ? (a.materials.empty() ? kDefaultMaterial : a.materials[0])
                                                       : a.materials[a.triangleMaterial[t]];
        const bool mapped = textured && m.baseColorTexture.present();
        double need = a.cornerColors.empty() && a.materials.size() <= 1 && !mapped ? 0.0 : kSamplesPerTriangle / a3;
        if (mapped) {
            const TextureImage& image = a.images[size_t(m.baseColorTexture.image)];
            const glm::dvec2 u0 = a.cornerUVs[t * 3], u1 = a.cornerUVs[t * 3 + 1], u2 = a.cornerUVs[t * 3 + 2];
            const glm::dvec2 e1 = (u1 - u0) * glm::dvec2(image.width, image.height),
                             e2 = (u2 - u0) * glm::dvec2(image.width, image.height);
            // The texture transform (KHR_texture_transform) scales the texels a triangle covers.
            const glm::dmat3& transform = m.baseColorTexture.transform;
            const double scale = std::abs(transform[0][0] * transform[1][1] - transform[0][1] * transform[1][0]);
            const double texels = 0.5 * std::abs(e1.x * e2.y - e1.y * e2.x) * scale;
            if (std::isfinite(texels)) texelsPerArea_[t] = texels / a3, need = std::max(need, texelsPerArea_[t]);
        }
        area += a3;
        weighted += need * a3;
    }
    samplesPerArea_ = area > 0.0 ? weighted / area : 0.0;
    uniform_ = samplesPerArea_ == 0.0;
}

glm::dvec4 SurfaceColor::sampleTexture(const Pyramid& p, const TextureRef& ref, glm::dvec2 uv, double lod) const
{
    const glm::dvec3 t = ref.transform * glm::dvec3(uv, 1.0);
    const double u = wrap(t.x, ref.wrapU), v = wrap(t.y, ref.wrapV);
    const double maxLevel = double(p.levels.size() - 1);
    lod = std::clamp(std::isfinite(lod) ? lod : 0.0, 0.0, maxLevel);
    const size_t l0 = size_t(std::floor(lod));
    const size_t l1 = std::min(l0 + 1, p.levels.size() - 1);
    auto bilinear = [&](size_t l) {
        const uint32_t w = p.widths[l], h = p.heights[l];
        const double x = u * w - 0.5, y = v * h - 0.5;
        const double fx = std::floor(x), fy = std::floor(y);
        const double ax = x - fx, ay = y - fy;
        const int x0 = wrapIndex(long(fx), w, ref.wrapU), x1 = wrapIndex(long(fx) + 1, w, ref.wrapU);
        const int y0 = wrapIndex(long(fy), h, ref.wrapV), y1 = wrapIndex(long(fy) + 1, h, ref.wrapV);
        const std::vector<glm::vec4>& level = p.levels[l];
        const glm::dvec4 a = glm::dvec4(level[size_t(y0) * w + size_t(x0)]),
                         b = glm::dvec4(level[size_t(y0) * w + size_t(x1)]);
        const glm::dvec4 c = glm::dvec4(level[size_t(y1) * w + size_t(x0)]),
                         d = glm::dvec4(level[size_t(y1) * w + size_t(x1)]);
        return (a * (1.0 - ax) + b * ax) * (1.0 - ay) + (c * (1.0 - ax) + d * ax) * ay;
    };
    const glm::dvec4 fine = bilinear(l0);
    if (l1 == l0) return fine;
    const double f = lod - double(l0);
    return fine * (1.0 - f) + bilinear(l1) * f;
}

glm::dvec4 SurfaceColor::baseColor(uint32_t triangle, const glm::dvec3& bary, double footprint) const
{
    const MeshAppearance& a = appearance_;
    const Material& m = a.triangleMaterial.empty() ? (a.materials.empty() ? kDefaultMaterial : a.materials[0])
                                                   : a.materials[a.triangleMaterial[triangle]];
    glm::dvec4 colour = m.baseColorFactor;
    if (!a.cornerColors.empty()) {
        const size_t c = size_t(triangle) * 3;
        colour *= bary.x * glm::dvec4(a.cornerColors[c]) + bary.y * glm::dvec4(a.cornerColors[c + 1]) +
            bary.z * glm::dvec4(a.cornerColors[c + 2]);
    }
    if (!a.cornerUVs.empty() && m.baseColorTexture.present()) {
        const Pyramid& p = pyramids_[size_t(m.baseColorTexture.image)];
        const size_t c = size_t(triangle) * 3;
        const glm::dvec2 uv = bary.x * a.cornerUVs[c] + bary.y * a.cornerUVs[c + 1] + bary.z * a.cornerUVs[c + 2];
        // Texels under the footprint: density x area; the level where one texel covers it.
        const double texels = texelsPerArea_[triangle] * footprint * footprint;
        const double lod = texels > 1.0 ? 0.5 * std::log2(texels) : 0.0;
        colour *= sampleTexture(p, m.baseColorTexture, uv, lod);
    }
    colour = glm::clamp(colour, glm::dvec4(0.0), glm::dvec4(1.0));
    // The alpha a viewer draws (glTF 2.0, "alpha coverage"): none for an opaque material, all
    // or nothing at the cutoff for a masked one, as it is for a blended one.
    if (m.alphaMode == AlphaMode::Opaque)
        colour.a = 1.0;
    else if (m.alphaMode == AlphaMode::Mask)
        colour.a = colour.a >= m.alphaCutoff ? 1.0 : 0.0;
    return colour;
}

}  // namespace ngi
