#version 450
// Geomorph targets for continuous LoD: for every sample of a level, the point of the next
// coarser level's SURFACE at the same uv. Because levels are nested, that surface is made of
// this level's even samples: an even sample is its own target, an edge midpoint goes to the
// midpoint of its two even neighbours, and a cell centre goes to the midpoint of the coarse
// quad's shorter 3D diagonal (the diagonal the coarse grid is split along). At morph = 1 the
// fine grid lies exactly on the coarse triangles, so stepping to the coarser grid never pops.
// CPU reference: ngi::morphTarget (core/src/lod_grid.cpp).
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"

layout(local_size_x = NGI_TILE, local_size_y = NGI_TILE) in;
layout(set = 0, binding = 0, rgba32ui) uniform readonly uimage2D level;
layout(set = 0, binding = 1, rgba32ui) uniform writeonly uimage2D morphTargets;
layout(push_constant) uniform Push { MipPushConstants pc; };

void main()
{
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (x.x >= int(pc.fineSize) || x.y >= int(pc.fineSize)) return;
    bool oddX = (x.x & 1) == 1, oddY = (x.y & 1) == 1;
    uvec4 result;
    if (!oddX && !oddY) {
        result = imageLoad(level, x);
    } else if (oddX != oddY) {
        ivec2 d = oddX ? ivec2(1, 0) : ivec2(0, 1);
        uvec4 a = imageLoad(level, x - d), b = imageLoad(level, x + d);
        result = makeTexel((texelPosition(a) + texelPosition(b)) * 0.5, texelNormal(a) + texelNormal(b));
    } else {
        uvec4 a = imageLoad(level, x + ivec2(-1, -1)), b = imageLoad(level, x + ivec2(1, -1));
        uvec4 c = imageLoad(level, x + ivec2(1, 1)), d = imageLoad(level, x + ivec2(-1, 1));
        vec3 pa = texelPosition(a), pb = texelPosition(b), pc_ = texelPosition(c), pd = texelPosition(d);
        vec3 ac = pc_ - pa, bd = pd - pb;
        if (dot(ac, ac) <= dot(bd, bd))
            result = makeTexel((pa + pc_) * 0.5, texelNormal(a) + texelNormal(c));
        else
            result = makeTexel((pb + pd) * 0.5, texelNormal(b) + texelNormal(d));
    }
    imageStore(morphTargets, x, result);
}
