// ngi offline: the base colour of an input surface at a point of one of its triangles, as a
// glTF viewer would shade it (base colour factor x base colour texture x vertex colour, in
// linear RGB), filtered over the area a sample stands for: the texture is read from a mip
// pyramid (box-filtered in linear light), trilinearly, at the level where one texel covers
// that area (Williams 1983, "Pyramidal parametrics"). The bake writes each chart's colour
// image with it; the evaluation compares colours on the surface with it.
#pragma once

#include "ngi/mesh/appearance.h"
#include "ngi/mesh/triangle_mesh.h"
#include "ngi/srgb.h"  // srgbToLinear, linearToSrgb: the colours' encoding

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include <cstdint>
#include <vector>

namespace ngi {

class SurfaceColor {
public:
    // Prepares `appearance` (as a reader returned it for `mesh`) for lookups: the mip pyramid of
    // every base colour texture a material uses, and each triangle's texel density. Keeps
    // references to both arguments, which must outlive it. Throws ngi::Error if an attribute
    // array's size does not match the mesh or a material or image index is out of range.
    SurfaceColor(const TriangleMesh& mesh, const MeshAppearance& appearance);

    // True when the surface has one colour everywhere (no texture, no vertex colour, at most
    // one material): a chart then needs no colour image of any detail.
    bool uniform() const { return uniform_; }

    // Linear RGBA at the point with barycentric coordinates `bary` in triangle `triangle`,
    // averaged over a square of side `footprint` (object units) on the surface. The alpha is
    // the coverage the material's alpha mode draws: 1 for an opaque material (whatever its
    // texture holds), 0 or 1 by the cutoff for a masked one (tested after the averaging, as a
    // viewer tests its filtered sample), the averaged alpha for a blended one.
    glm::dvec4 baseColor(uint32_t triangle, const glm::dvec3& bary, double footprint) const;

    // Samples per unit area the surface's colour needs: the area-weighted mean over triangles
    // of texels per unit area where a texture is used, and 2 per triangle's area elsewhere
    // (vertex colours and per-triangle materials vary from vertex to vertex); 0 when uniform().
    double samplesPerArea() const { return samplesPerArea_; }

private:
    struct Pyramid {
        std::vector<uint32_t> widths, heights;
        std::vector<std::vector<glm::vec4>> levels;  // linear RGBA
    };
    glm::dvec4 sampleTexture(const Pyramid& pyramid, const TextureRef& ref, glm::dvec2 uv, double lod) const;

    const TriangleMesh& mesh_;
    const MeshAppearance& appearance_;
    std::vector<Pyramid> pyramids_;      // per image (empty where no material's base colour uses it)
    std::vector<double> texelsPerArea_;  // per triangle: texture texels per unit 3D area (0: no texture)
    bool uniform_ = true;
    double samplesPerArea_ = 0.0;
};

}  // namespace ngi
