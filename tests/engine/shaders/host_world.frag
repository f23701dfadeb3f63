#version 450
// A host's fragment shader on ngi's public vertex stage (tests/engine/host_vertex_stage_test):
// writes the world-space position (colour 0) and normal (colour 1) as 0.5 + 0.5 * v / scale,
// scale from a host set (set 2, SurfacePipeline::firstHostSet).
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
layout(push_constant) uniform Push { DrawPushConstants pc; };
layout(set = NGI_DRAW_HOST_SET, binding = 0) uniform Host { vec4 scale; } host;
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inPosition;
layout(location = 2) noperspective in vec3 inBarycentric;
layout(location = 3) flat in vec4 inEyeLod;
layout(location = 4) in vec3 inWorldPosition;
layout(location = 5) in vec3 inWorldNormal;
layout(location = 6) in vec2 inChartUv;  // the public vertex stage's chart uv (unused here)
layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
void main()
{
    outPosition = vec4(0.5 + 0.5 * inWorldPosition / host.scale.x, 1.0);
    outNormal = vec4(0.5 + 0.5 * normalize(inWorldNormal), 1.0);
}
