#version 450
// Seam weld (core/include/ngi/seam.h, CPU reference ngi::weldSeams): copies every border
// sample's canonical mate onto it, so the two sides of a cut are bitwise equal after the
// restore. One invocation per (destination, source) pair of perimeter indices of this level;
// sources are canonical and never written, so the copies do not race.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "perimeter.glsl"

layout(local_size_x = 64) in;
layout(set = 0, binding = 0, rgba32ui) uniform uimage2D level;
layout(set = 0, binding = 1, std430) readonly buffer Pairs { uvec2 pairs[]; };
layout(push_constant) uniform Push { SeamWeldPushConstants pc; };


void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.pairCount) return;
    uvec2 p = pairs[pc.pairOffset + i];
    imageStore(level, perimeterSample(p.x, pc.resolution), imageLoad(level, perimeterSample(p.y, pc.resolution)));
}
