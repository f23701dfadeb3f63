#version 450
// Grid expansion: one level's N-grid index buffer for shared-vertex draws, written at run
// time for one geomorph factor and never stored in the asset (NGI_WAY_SHARED in surface.vert,
// which geomorphs each sample itself from the level's texels). Invocation (i, j) writes quad
// (i, j)'s two triangles along the diagonal chosen for this factor by the same quadratic,
// evaluated by the same expression, as surface.vert's per-quad way (quad_diagonals.comp; CPU
// definition ngi::splitsAlongAC, core/src/lod_grid.cpp), with the vertex order of the shared
// quad index buffer: (a, b, c), (a, c, d) along a-c, else (b, c, d), (b, d, a). The same
// triangles with the same vertices in the same order as the per-quad draw, so the two draws
// rasterize identically.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"

layout(local_size_x = NGI_TILE, local_size_y = NGI_TILE) in;
layout(set = 0, binding = NGI_EXPANSION_BINDING_DIAGONALS, rgba32f) uniform readonly image2D quadDiagonals;
layout(std430, set = 0, binding = NGI_EXPANSION_BINDING_INDICES) writeonly buffer Indices { uint indexPairs[]; };
layout(push_constant) uniform Push { GridExpansionPushConstants pc; };

void main()
{
    // No early return (lavapipe runs what follows one under a per-lane mask, see sr_conv.comp):
    // invocations past the grid compute on a clamped quad and skip only their stores.
    ivec2 id = ivec2(gl_GlobalInvocationID.xy);
    int n = int(pc.gridSize), quads = n - 1;
    float morph = pc.morph;
    ivec2 q = min(id, ivec2(quads - 1));
    vec3 f = imageLoad(quadDiagonals, q).xyz;
    bool splitAC = (f.z * morph + f.y) * morph + f.x <= 0.0;
    // Corners counter-clockwise in uv: a (i, j), b (i + 1, j), c (i + 1, j + 1), d (i, j + 1),
    // as offsets from the first sample of the quad's chunk (NGI_EXPANSION_BINDING_INDICES).
    int chunkFirstRow = q.y - q.y % int(pc.chunkRows);
    uint a = uint((q.y - chunkFirstRow) * n + q.x), b = a + 1u, c = a + uint(n) + 1u, d = a + uint(n);
    uvec3 t0 = splitAC ? uvec3(a, b, c) : uvec3(b, c, d);
    uvec3 t1 = splitAC ? uvec3(a, c, d) : uvec3(b, d, a);
    // Two 16-bit indices per store: three stores per quad (lavapipe stores lane by lane).
    uint first = 3u * uint(q.y * quads + q.x);
    if (id.x < quads && id.y < quads) {
        indexPairs[first + 0u] = t0.x | (t0.y << 16);
        indexPairs[first + 1u] = t0.z | (t1.x << 16);
        indexPairs[first + 2u] = t1.y | (t1.z << 16);
    }
}
