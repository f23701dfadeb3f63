#version 450
// Baseline for benchmarks: the same surface drawn the ordinary way, from a vertex buffer
// (position, normal) and an index buffer, with surface.frag's shading.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"

layout(push_constant) uniform Push { DrawPushConstants pc; };
layout(location = 0) in vec3 inPosition;
layout(location = 1) in vec3 inNormal;
layout(location = 0) out vec3 outNormal;
layout(location = 1) out vec3 outPosition;
layout(location = 2) noperspective out vec3 outBarycentric;
layout(location = 3) flat out vec4 outEyeLod;  // surface.frag's camera and LoD

void main()
{
    outNormal = inNormal;
    outPosition = inPosition;
    outBarycentric = vec3(1.0);
    outEyeLod = vec4(pc.eye.xyz, pc.lod);
    gl_Position = pc.viewProjection * vec4(inPosition, 1.0);
}
