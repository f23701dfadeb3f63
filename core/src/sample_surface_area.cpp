// The surface area of each geometry-image sample: see ngi/sample_surface_area.h.
#include "ngi/sample_surface_area.h"

#include <glm/geometric.hpp>

namespace ngi {

std::vector<double> sampleSurfaceAreas(const GeometryImage& positions)
{
    const uint32_t n = positions.size;
    std::vector<double> area(positions.texels.size(), 0.0);
    for (uint32_t y = 0; y + 1 < n; ++y)
        for (uint32_t x = 0; x + 1 < n; ++x) {
            const glm::dvec3 p00(positions.at(x, y)), p10(positions.at(x + 1, y));
            const glm::dvec3 p01(positions.at(x, y + 1)), p11(positions.at(x + 1, y + 1));
            // A (possibly skew) quad's area by its diagonals: exact for planar quads.
            const double quarter = 0.125 * glm::length(glm::cross(p11 - p00, p01 - p10));
            for (const size_t i :
                 {size_t(y) * n + x, size_t(y) * n + x + 1, size_t(y + 1) * n + x, size_t(y + 1) * n + x + 1})
                area[i] += quarter;
        }
    return area;
}

std::vector<double> surfaceAreaWeights(const GeometryImage& positions)
{
    return surfaceAreaWeights(sampleSurfaceAreas(positions));
}

std::vector<double> surfaceAreaWeights(std::span<const double> areas)
{
    std::vector<double> w(areas.begin(), areas.end());
    double sum = 0.0;
    for (const double a : w) sum += a;
    const double mean = w.empty() ? 0.0 : sum / double(w.size());
    for (double& a : w) a = mean > 0.0 ? a / mean : 1.0;
    return w;
}

}  // namespace ngi
