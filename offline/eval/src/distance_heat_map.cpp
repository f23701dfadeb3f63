// Where one surface is far from another, as a picture (ngi/eval/distance_heat_map.h).
#include "ngi/eval/distance_heat_map.h"

#include "ngi/param/detail_transfer.h"

#include <algorithm>
#include <cmath>

namespace ngi {

DistanceHeatMap distanceHeatMap(const TriangleMesh& reference, const TriangleMesh& candidate,
                                const ReferenceFrame& frame, double redAt, unsigned threads)
{
    std::vector<glm::dvec3> points;
    points.reserve(reference.triangles.size() * 4);
    for (const glm::uvec3& t : reference.triangles) {
        const glm::dvec3 a = reference.positions[t.x], b = reference.positions[t.y], c = reference.positions[t.z];
        points.insert(points.end(), {a, b, c, (a + b + c) / 3.0});
    }
    const std::vector<double> squared = squaredDistancesToSurface(candidate, points, std::max(1u, threads));
    std::vector<double> distances(reference.triangles.size());
    DistanceHeatMap map;
    for (size_t t = 0; t < distances.size(); ++t) {
        distances[t] =
            std::sqrt(std::max({squared[4 * t], squared[4 * t + 1], squared[4 * t + 2], squared[4 * t + 3]})) *
            frame.scale;
        map.farthest = std::max(map.farthest, distances[t]);
    }
    map.redAt = redAt > 0.0 ? redAt : std::max(map.farthest, 1e-9);
    std::vector<glm::vec3> colours(distances.size());
    for (size_t t = 0; t < colours.size(); ++t)
        colours[t] = heatColour(1.0 + 0.5 * std::log10(std::max(distances[t] / map.redAt, 1e-3)));
    std::vector<RgbImage> sides;
    for (const double yaw : {35.0, 215.0})
        sides.push_back(renderMeshPicture(reference, pictureViewFor(reference, yaw), 512, colours));
    map.image = contactSheet(sides, 2);
    return map;
}

}  // namespace ngi
