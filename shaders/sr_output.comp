#version 450
// Super-resolution output pass: the network's output tensor (3 channels, the full-resolution
// positions) -> level 0 of the geometry image (RGBA32UI texels, see ngi_shared.h).
// Normals are DERIVED from the restored positions: the cross product of the central
// differences along x and y (one-sided on the border), oriented like the bilinear
// interpolation of the stored level's normals (which also replaces a degenerate cross
// product). So shading follows the detail the network restored.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"
#include "texel.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer positionTensor;
layout(set = 0, binding = NGI_SR_BINDING_LEVEL, rgba32ui) uniform writeonly uimage2D fullLevel;
layout(set = 0, binding = NGI_SR_BINDING_STORED, rgba32ui) uniform readonly uimage2D storedLevel;

vec3 position(int x, int y) { return texelFetch(positionTensor, tensorIndex(0, x, y, int(pc.width), int(pc.height))).xyz; }

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int X = int(gl_GlobalInvocationID.x), Y = int(gl_GlobalInvocationID.y);
    if (X >= width || Y >= height) return;
    const vec3 p = position(X, Y);
    const vec3 du = position(min(X + 1, width - 1), Y) - position(max(X - 1, 0), Y);
    const vec3 dv = position(X, min(Y + 1, height - 1)) - position(X, max(Y - 1, 0));
    vec3 n = cross(du, dv);

    const int f = int(pc.factor), cw = int(pc.inWidth), ch = int(pc.inHeight);
    const int x0 = X / f, x1 = min(x0 + 1, cw - 1), y0 = Y / f, y1 = min(y0 + 1, ch - 1);
    const float tx = float(X % f) / float(f), ty = float(Y % f) / float(f);
    const vec3 stored = mix(mix(texelNormal(imageLoad(storedLevel, ivec2(x0, y0))),
                                texelNormal(imageLoad(storedLevel, ivec2(x1, y0))), tx),
                            mix(texelNormal(imageLoad(storedLevel, ivec2(x0, y1))),
                                texelNormal(imageLoad(storedLevel, ivec2(x1, y1))), tx), ty);
    const float len = length(n);
    if (!(len > 1e-12)) n = stored;
    else if (dot(n, stored) < 0.0) n = -n;
    imageStore(fullLevel, ivec2(X, Y), makeTexel(p, n));
}
