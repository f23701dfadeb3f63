#version 450
// Grid expansion: one level's N-grid as shared vertices and an index buffer, written at run
// time for one geomorph factor and never stored in the asset (NGI_WAY_SHARED in surface.vert).
// Invocation (i, j) writes vertex j * N + i: sample (i, j) geomorphed by the one definition
// the per-quad draw uses (geomorphPoint, texel.glsl), as texels (2i, j) and (2i + 1, j) of
// the expanded vertices (NGI_DRAW_BINDING_VERTICES), and, for i, j < N - 1, quad (i, j)'s
// two triangles along the diagonal chosen for this factor by the same quadratic, evaluated
// by the same expression, as surface.vert's per-quad way (quad_diagonals.comp; CPU
// definition ngi::splitsAlongAC, core/src/lod_grid.cpp), with the vertex order of the shared
// quad index buffer: (a, b, c), (a, c, d) along a-c, else (b, c, d), (b, d, a). The same
// triangles with the same vertices in the same order as the per-quad draw, so the two draws
// rasterize identically.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"

layout(local_size_x = NGI_TILE, local_size_y = NGI_TILE) in;
layout(set = 0, binding = NGI_EXPANSION_BINDING_DIAGONALS, rgba32f) uniform readonly image2D quadDiagonals;
layout(std430, set = 0, binding = NGI_EXPANSION_BINDING_INDICES) writeonly buffer Indices { uint indexPairs[]; };
layout(set = 0, binding = NGI_EXPANSION_BINDING_LEVEL, rgba32ui) uniform readonly uimage2D level;
layout(set = 0, binding = NGI_EXPANSION_BINDING_TARGETS, rgba32ui) uniform readonly uimage2D morphTargets;
layout(set = 0, binding = NGI_EXPANSION_BINDING_VERTICES, rgba32ui) uniform writeonly uimage2D vertices;
layout(push_constant) uniform Push { GridExpansionPushConstants pc; };

void main()
{
    // No early return (lavapipe runs what follows one under a per-lane mask, see sr_conv.comp):
    // invocations past the grid compute on a clamped sample and skip only their stores.
    ivec2 id = ivec2(gl_GlobalInvocationID.xy);
    int n = int(pc.gridSize), quads = n - 1;
    ivec2 x = min(id, ivec2(n - 1));
    float morph = pc.morph;
    uvec4 p = imageLoad(level, x);
    SurfacePoint s = geomorphPoint(p, morph > 0.0 ? imageLoad(morphTargets, x) : p, morph);
    if (id.x < n && id.y < n) {
        imageStore(vertices, ivec2(2 * x.x, x.y), uvec4(floatBitsToUint(s.position), 0u));
        imageStore(vertices, ivec2(2 * x.x + 1, x.y), uvec4(floatBitsToUint(s.normal), 0u));
    }

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
