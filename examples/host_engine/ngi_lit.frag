#version 450
// The host's material for ngi's surfaces, written against ngi's public vertex stage
// (shaders/surface.vert, installed with ngi::shaders): world-space position and normal from
// a batched draw, the host's sun and shadow map in set 2 (the first host set).
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#define HOST_LIGHT_SET NGI_DRAW_HOST_SET
#include "lighting.glsl"

layout(push_constant) uniform Push { DrawPushConstants pc; };  // batched: pc.eye is the camera in world space
// Every output of the vertex stage has an input here (the validation layer warns otherwise).
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inPosition;
layout(location = 2) noperspective in vec3 inBarycentric;
layout(location = 3) flat in vec4 inEyeLod;
layout(location = 4) in vec3 inWorldPosition;
layout(location = 5) in vec3 inWorldNormal;
layout(location = 6) in vec2 inChartUv;  // the public vertex stage's chart uv (unused here)
layout(location = 0) out vec4 outColour;

void main()
{
    vec3 n = normalize(inWorldNormal);
    vec3 toEye = normalize(pc.eye.xyz - inWorldPosition);
    if (dot(n, toEye) < 0.0) n = -n;  // cut surfaces are two-sided
    vec3 albedo = vec3(0.86, 0.84, 0.80);
    vec3 colour = shadeLambert(albedo, inWorldPosition, n);
    vec3 h = normalize(toEye + light.toLight.xyz);
    colour += light.sun.rgb * 0.12 * pow(max(dot(n, h), 0.0), 40.0) * sunVisibility(inWorldPosition);
    outColour = vec4(colour, 1.0);
}
