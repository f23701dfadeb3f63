#version 450
// Per-quad diagonal choice for every geomorph factor t, so the vertex shader decides a
// quad's split with one fetch instead of reading all four corners twice. With corner
// positions p(t) = mix(level, morphTarget, t), the split follows the sign of
//     f(t) = |c(t) - a(t)|^2 - |d(t) - b(t)|^2 = C + B t + A t^2   (<= 0: diagonal a-c)
// stored as (C, B, A). CPU reference: core/src/lod_grid.cpp (quadDiagonal).
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"

layout(local_size_x = NGI_TILE, local_size_y = NGI_TILE) in;
layout(set = 0, binding = 0, rgba32ui) uniform readonly uimage2D level;
layout(set = 0, binding = 1, rgba32ui) uniform readonly uimage2D morphTargets;
layout(set = 0, binding = 2, rgba32f) uniform writeonly image2D quadDiagonals;
layout(push_constant) uniform Push { MipPushConstants pc; };

void main()
{
    ivec2 q = ivec2(gl_GlobalInvocationID.xy);
    int quads = int(pc.fineSize) - 1;
    if (q.x >= quads || q.y >= quads) return;
    ivec2 corner[4] = ivec2[4](q, q + ivec2(1, 0), q + ivec2(1, 1), q + ivec2(0, 1));
    vec3 p0[4], p1[4];
    for (int i = 0; i < 4; ++i) {
        p0[i] = texelPosition(imageLoad(level, corner[i]));
        p1[i] = texelPosition(imageLoad(morphTargets, corner[i]));
    }
    vec3 ac0 = p0[2] - p0[0], bd0 = p0[3] - p0[1];
    vec3 dac = (p1[2] - p1[0]) - ac0, dbd = (p1[3] - p1[1]) - bd0;
    float c = dot(ac0, ac0) - dot(bd0, bd0);
    float b = 2.0 * (dot(ac0, dac) - dot(bd0, dbd));
    float a = dot(dac, dac) - dot(dbd, dbd);
    imageStore(quadDiagonals, q, vec4(c, b, a, 0.0));
}
