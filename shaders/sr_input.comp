#version 450
// Super-resolution input pass: the stored geometry-image level (RGBA32UI texels, see
// ngi_shared.h) -> network tensor 0 (positions, pc.channels == 0) or tensor 1 (unit
// normals decoded from the octahedral encoding, pc.channels == 1), 3 channels + a zero lane.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"
#include "texel.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(set = 0, binding = NGI_SR_BINDING_LEVEL, rgba32ui) uniform readonly uimage2D storedLevel;
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
    if (x >= width || y >= height) return;
    const uvec4 t = imageLoad(storedLevel, ivec2(x, y));
    const vec3 v = pc.channels == 0u ? texelPosition(t) : texelNormal(t);
    imageStore(outputTensor, tensorIndex(0, x, y, width, height), vec4(v, 0.0));
}
