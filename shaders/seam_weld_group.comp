#version 450
// Seam weld across the charts of a split component (core/include/ngi/seam.h groupWeldPlan; CPU
// reference ngi::weldGroupSeams): the shared curves' samples of one level made bitwise equal
// in every chart. Two passes over every chart: gather (scatter = 0) copies each canonical
// sample of this chart into its value slot, then scatter (1) copies the slots onto the samples
// that take them. Canonical samples are only read and every slot has one writer, so a pass
// does not race; a barrier separates the passes.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "perimeter.glsl"

layout(local_size_x = 64) in;
layout(set = 0, binding = 0, rgba32ui) uniform uimage2D level;
layout(set = 0, binding = 1, std430) readonly buffer Pairs { uvec2 pairs[]; };  // (perimeter index, slot)
layout(set = 0, binding = 2, std430) buffer Values { uvec4 values[]; };
layout(push_constant) uniform Push { GroupWeldPushConstants pc; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.pairCount) return;
    uvec2 p = pairs[pc.pairOffset + i];
    ivec2 sample_ = perimeterSample(p.x, pc.resolution);
    if (pc.scatter == 0u) values[p.y] = imageLoad(level, sample_);
    else imageStore(level, sample_, values[p.y]);
}
