// ngi: constants and push-constant layouts shared by C++ and GLSL (STYLE.md rule 2).
// Included by every shader and by the engine; the layouts are written once, here.
#ifndef NGI_SHARED_H
#define NGI_SHARED_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
namespace ngi::gpu {
using uint = uint32_t;
using vec4 = glm::vec4;
using mat4 = glm::mat4;
#endif

// Compute workgroups over geometry-image texels: NGI_TILE x NGI_TILE invocations.
#define NGI_TILE 8

// Geometry-image texels on the GPU are RGBA32UI: xyz = floatBitsToUint(position, normalized
// to the asset's bbox), w = packUnorm2x16(octahedral(normal)). Integer texels keep the float
// bits exact (a float format could flush the packed normal's bit pattern as a denormal).

// The shared topology-only index buffer: quad q's vertices are 4q + corner (0..3), indexed
// as (0, 1, 2), (0, 2, 3). 16-bit indices cover NGI_QUADS_PER_CHUNK quads; bigger grids are
// drawn in chunks with vertexOffset = 4 * NGI_QUADS_PER_CHUNK * chunk.
#define NGI_QUADS_PER_CHUNK 16384

// Shading modes of surface.frag.
#define NGI_MODE_SHADED 0
#define NGI_MODE_NORMALS 1
#define NGI_MODE_WIREFRAME 2
#define NGI_MODE_LOD 3

// mip_downsample.comp, mip_upsample.comp, morph_targets.comp.
struct MipPushConstants {
    uint fineSize;    // samples per side of the finer level
    uint coarseSize;  // samples per side of the coarser level ((fine - 1) / 2 + 1)
    uint pad0;
    uint pad1;
};

// surface.vert / surface.frag: one draw of the geometry-image grid.
struct DrawPushConstants {
    mat4 viewProjection;  // normalized asset space -> clip space
    vec4 eye;             // xyz: camera position in normalized asset space
    uint gridSize;        // vertices per side of the drawn grid N (2 .. full size)
    uint levelSize;       // samples per side of the mip level the grid samples
    float morph;          // 0..1: blend towards the next coarser level (geomorph)
    uint mode;            // NGI_MODE_*
    float lod;            // continuous LoD drawn (LoD colouring)
    float wireWidth;      // wireframe line width in pixels
    uint quadIndexed;     // 1: drawn with the shared quad index buffer (4 vertices per quad)
    uint pad0;
};

#ifdef __cplusplus
static_assert(sizeof(MipPushConstants) == 16);
static_assert(sizeof(DrawPushConstants) == 112, "must fit the 128-byte push-constant minimum");
} // namespace ngi::gpu
#endif

#endif
