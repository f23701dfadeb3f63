// ngi offline eval: the drawn mesh's appearance, each chart's base colour image as a glTF
// texture addressed by the chart uv (asset_appearance.h).
#include "ngi/eval/asset_appearance.h"

#include "ngi/error.h"

#include <algorithm>
#include <string>

namespace ngi {

glm::dvec2 chartTextureCoordinate(glm::dvec2 gridUV, uint32_t size)
{
    const double s = double(size);
    return (gridUV * (s - 1.0) + 0.5) / s;
}

MeshAppearance assetMeshAppearance(const Asset& asset, const AssetMesh& drawn)
{
    const TriangleMesh& mesh = drawn.mesh;
    if (drawn.chartUVs.size() != mesh.positions.size() || drawn.triangleChart.size() != mesh.triangles.size())
        throw Error("the drawn mesh has no chart uv per vertex or no chart per triangle");
    MeshAppearance appearance;
    if (!asset.hasBaseColors()) return appearance;

    // One material per coloured chart, then the default material if a chart has no colour.
    std::vector<uint32_t> chartMaterial(asset.charts.size(), UINT32_MAX);
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        const AssetChart& chart = asset.charts[c];
        if (chart.baseColor.empty()) continue;
        const uint32_t size = chart.baseColorSize();
        if (chart.baseColor.size() != size_t(size) * size * 4)
            throw Error("chart " + std::to_string(c) + ": its base colour has " +
                        std::to_string(chart.baseColor.size()) + " bytes, not " + std::to_string(size) + "^2 x 4");
        TextureImage& image = appearance.images.emplace_back();
        image.name = "chart " + std::to_string(c) + " base colour";
        image.width = image.height = size;
        image.rgba = chart.baseColor;
        Material& material = appearance.materials.emplace_back();
        material.name = "chart " + std::to_string(c);
        material.baseColorTexture.image = int32_t(appearance.images.size() - 1);
        material.baseColorTexture.wrapU = material.baseColorTexture.wrapV = TextureWrap::ClampToEdge;
        material.metallicFactor = 0.0;
        // The baked alpha is coverage (ngi/mesh/surface_color.h): all 255 for an opaque
        // surface, 0 or 255 for a masked one, anything for a blended one.
        bool translucent = false, partial = false;
        for (size_t i = 3; i < image.rgba.size(); i += 4) {
            translucent = translucent || image.rgba[i] < 255;
            partial = partial || (image.rgba[i] > 0 && image.rgba[i] < 255);
        }
        material.alphaMode = partial ? AlphaMode::Blend : translucent ? AlphaMode::Mask : AlphaMode::Opaque;
        chartMaterial[c] = uint32_t(appearance.materials.size() - 1);
    }
    uint32_t defaultMaterial = UINT32_MAX;
    for (size_t c = 0; c < asset.charts.size(); ++c) {
        if (chartMaterial[c] != UINT32_MAX) continue;
        if (defaultMaterial == UINT32_MAX) {
            Material& material = appearance.materials.emplace_back();
            material.name = "default";
            material.metallicFactor = 0.0;
            defaultMaterial = uint32_t(appearance.materials.size() - 1);
        }
        chartMaterial[c] = defaultMaterial;
    }

    appearance.cornerUVs.reserve(mesh.triangles.size() * 3);
    appearance.triangleMaterial.reserve(mesh.triangles.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const uint32_t c = drawn.triangleChart[t];
        if (c >= asset.charts.size())
            throw Error("triangle " + std::to_string(t) + " names chart " + std::to_string(c) + " of " +
                        std::to_string(asset.charts.size()));
        const uint32_t size = asset.charts[c].baseColor.empty() ? 2u : asset.charts[c].baseColorSize();
        for (int k = 0; k < 3; ++k)
            appearance.cornerUVs.push_back(chartTextureCoordinate(drawn.chartUVs[mesh.triangles[t][k]], size));
        appearance.triangleMaterial.push_back(chartMaterial[c]);
    }
    return appearance;
}

}  // namespace ngi
