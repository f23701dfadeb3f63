// ngi offline eval, peers: QSlim-style simplification (Garland & Heckbert 1997) through
// meshoptimizer's meshopt_simplify.
#include "ngi/eval/simplify.h"

#include "ngi/error.h"
#include "surface_checks.h"

#include <meshoptimizer.h>

#include <cstdint>

namespace ngi {

SimplifyResult simplifyMesh(const TriangleMesh& mesh, const SimplifyOptions& options)
{
    detail::checkSurface(mesh, "simplify: mesh");
    std::vector<float> positions;
    positions.reserve(mesh.positions.size() * 3);
    for (const glm::dvec3& p : mesh.positions) {
        positions.push_back(float(p.x));
        positions.push_back(float(p.y));
        positions.push_back(float(p.z));
    }
    std::vector<unsigned int> indices;
    indices.reserve(mesh.triangles.size() * 3);
    for (const glm::uvec3& t : mesh.triangles) indices.insert(indices.end(), {t.x, t.y, t.z});

    std::vector<unsigned int> kept(indices.size());
    float error = 0.0f;
    const size_t target = size_t(options.targetTriangleCount) * 3;
    const size_t count = meshopt_simplify(kept.data(), indices.data(), indices.size(), positions.data(),
                                          mesh.positions.size(), 3 * sizeof(float), target, options.maxRelativeError,
                                          options.lockBorder ? unsigned(meshopt_SimplifyLockBorder) : 0u, &error);
    kept.resize(count);

    // Compact: renumber the used vertices in order of first use.
    SimplifyResult result;
    std::vector<uint32_t> remap(mesh.positions.size(), UINT32_MAX);
    for (size_t i = 0; i + 2 < kept.size(); i += 3) {
        glm::uvec3 t;
        for (int k = 0; k < 3; ++k) {
            uint32_t& r = remap[kept[i + k]];
            if (r == UINT32_MAX) {
                r = uint32_t(result.mesh.positions.size());
                result.mesh.positions.push_back(mesh.positions[kept[i + k]]);
            }
            t[k] = r;
        }
        result.mesh.triangles.push_back(t);
    }
    result.relativeError = error;
    result.reachedTarget = count <= target;
    return result;
}

}  // namespace ngi
