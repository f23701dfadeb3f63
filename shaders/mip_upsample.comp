#version 450
// Bilinear restoration of the next finer nested level (the --no-sr path): even samples copy
// the coarse level, edge midpoints average two coarse samples, cell centres average four.
// Repeating it from the stored level reproduces bilinear interpolation of that level exactly.
// Normals are averaged the same way and renormalized. CPU reference: ngi::upsampleNested.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"

layout(local_size_x = NGI_TILE, local_size_y = NGI_TILE) in;
layout(set = 0, binding = 0, rgba32ui) uniform writeonly uimage2D fineLevel;
layout(set = 0, binding = 1, rgba32ui) uniform readonly uimage2D coarseLevel;
layout(push_constant) uniform Push { MipPushConstants pc; };

void main()
{
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (x.x >= int(pc.fineSize) || x.y >= int(pc.fineSize)) return;
    ivec2 c0 = x / 2;
    ivec2 c1 = (x + 1) / 2;
    uvec4 t00 = imageLoad(coarseLevel, c0);
    uvec4 t10 = imageLoad(coarseLevel, ivec2(c1.x, c0.y));
    uvec4 t01 = imageLoad(coarseLevel, ivec2(c0.x, c1.y));
    uvec4 t11 = imageLoad(coarseLevel, c1);
    // Average in the same order as the CPU reference: ((a + b) + (c + d)) * 0.25.
    vec3 p = ((texelPosition(t00) + texelPosition(t10)) + (texelPosition(t01) + texelPosition(t11))) * 0.25;
    vec3 n = (texelNormal(t00) + texelNormal(t10)) + (texelNormal(t01) + texelNormal(t11));
    if ((x.x & 1) == 0 && (x.y & 1) == 0) { imageStore(fineLevel, x, t00); return; }
    imageStore(fineLevel, x, makeTexel(p, length(n) > 0.0 ? n : texelNormal(t00)));
}
