#version 450
// Nested-grid mip level (Gu, Gortler, Hoppe 2002, section 7): coarse(x, y) = fine(2x, 2y).
// Boundary samples stay exact at every level; see core/include/ngi/mip_pyramid.h.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"

layout(local_size_x = NGI_TILE, local_size_y = NGI_TILE) in;
layout(set = 0, binding = 0, rgba32ui) uniform readonly uimage2D fineLevel;
layout(set = 0, binding = 1, rgba32ui) uniform writeonly uimage2D coarseLevel;
layout(push_constant) uniform Push { MipPushConstants pc; };

void main()
{
    ivec2 x = ivec2(gl_GlobalInvocationID.xy);
    if (x.x >= int(pc.coarseSize) || x.y >= int(pc.coarseSize)) return;
    imageStore(coarseLevel, x, imageLoad(fineLevel, 2 * x));
}
