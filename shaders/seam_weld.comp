#version 450
// Seam weld (core/include/ngi/seam.h, CPU reference ngi::weldSeams): copies every border
// sample's canonical mate onto it, so the two sides of a cut are bitwise equal after the
// restore. One invocation per (destination, source) pair of perimeter indices of this level;
// sources are canonical and never written, so the copies do not race.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"

layout(local_size_x = 64) in;
layout(set = 0, binding = 0, rgba32ui) uniform uimage2D level;
layout(set = 0, binding = 1, std430) readonly buffer Pairs { uvec2 pairs[]; };
layout(push_constant) uniform Push { SeamWeldPushConstants pc; };

// Perimeter index t (counter-clockwise from (0, 0)) -> sample of a level of resolution r.
ivec2 perimeterSample(uint t, uint r)
{
    t %= 4u * r;
    if (t <= r) return ivec2(t, 0);
    if (t <= 2u * r) return ivec2(r, t - r);
    if (t <= 3u * r) return ivec2(3u * r - t, r);
    return ivec2(0, 4u * r - t);
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.pairCount) return;
    uvec2 p = pairs[pc.pairOffset + i];
    imageStore(level, perimeterSample(p.x, pc.resolution), imageLoad(level, perimeterSample(p.y, pc.resolution)));
}
