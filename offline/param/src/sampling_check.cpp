// ngi offline: refuse a chart whose map undersamples a large part of its surface (see
// sampling_check.h). The measure is the bake's undersampling warning (uv area share against 3D
// area share per triangle, Sander et al. 2001 "Texture mapping progressive meshes" use the same
// ratio as the signal-stretch argument); only the threshold turns it into an error.
#include "ngi/param/sampling_check.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdio>

namespace ngi {

double mapUndersampledAreaFraction(const TriangleMesh& mesh, const std::vector<glm::dvec2>& uv, double factor)
{
    double total3d = 0.0, totalUv = 0.0;
    std::vector<double> a3(mesh.triangles.size()), a2(mesh.triangles.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 f = mesh.triangles[t];
        a3[t] = 0.5 *
            glm::length(
                    glm::cross(mesh.positions[f.y] - mesh.positions[f.x], mesh.positions[f.z] - mesh.positions[f.x]));
        const glm::dvec2 e1 = uv[f.y] - uv[f.x], e2 = uv[f.z] - uv[f.x];
        a2[t] = std::abs(0.5 * (e1.x * e2.y - e1.y * e2.x));
        total3d += a3[t], totalUv += a2[t];
    }
    if (!(total3d > 0.0) || !(totalUv > 0.0)) return 0.0;
    double squeezed = 0.0;
    for (size_t t = 0; t < a3.size(); ++t)
        if (a2[t] / totalUv * factor < a3[t] / total3d) squeezed += a3[t];
    return squeezed / total3d;
}

void checkChartSampling(double undersampledFraction, const ChartSamplingContext& context)
{
    if (!(undersampledFraction > context.maxUndersampledAreaFraction)) return;
    char text[640];
    std::snprintf(text, sizeof text,
                  "%s: chart %zu of %zu (genus %ld): %.1f%% of its surface gets less than 1/%.0f of its fair share of "
                  "samples (limit %.0f%%); the geometry image would be unusable there. A higher --resolution does not "
                  "remove the map's squeeze: bake a simpler mesh (fewer handles, or the part split into pieces)",
                  context.file.c_str(), context.chart + 1, context.charts, context.genus, 100.0 * undersampledFraction,
                  kUndersamplingFactor, 100.0 * context.maxUndersampledAreaFraction);
    throw Error(text);
}

void checkChartImage(double farArea, const ChartSamplingContext& context)
{
    if (!(farArea > kMaxFarFromImageArea)) return;
    char text[640];
    std::snprintf(
        text, sizeof text,
        "%s: chart %zu of %zu (genus %ld): %.1f%% of its surface is farther than %.0f%% of its size from the "
        "geometry image (limit %.0f%%): the map folds or squeezes it away. Bake a simpler mesh (fewer handles, "
        "or the part split into pieces)",
        context.file.c_str(), context.chart + 1, context.charts, context.genus, 100.0 * farArea,
        100.0 * kFarFromImageDistance, 100.0 * kMaxFarFromImageArea);
    throw Error(text);
}

}  // namespace ngi
