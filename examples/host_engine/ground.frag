#version 450
#extension GL_GOOGLE_include_directive : require
#define HOST_LIGHT_SET 0
#include "lighting.glsl"
layout(location = 0) in vec3 inColour;
layout(location = 1) in vec3 inWorldPosition;
layout(location = 0) out vec4 outColour;
void main() { outColour = vec4(shadeLambert(inColour, inWorldPosition, vec3(0.0, 1.0, 0.0)), 1.0); }
