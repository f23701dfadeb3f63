#version 450
// Super-resolution output pass: the network's output tensor (3 channels, the full-resolution
// positions) -> level 0 of the geometry image (RGBA32UI texels, see ngi_shared.h).
// Normals are the stored level's normals interpolated by Catmull-Rom (clamped at the
// border) and renormalized, not derived from the restored positions: finite differences of
// any interpolated grid show its sub-cell ripples in the shading (measured: hatching on the
// bunny with Catmull-Rom and Hermite alike, none with the stored normals), while the stored
// normals are the surface's own at every stored sample and smooth between them. A degenerate
// interpolated normal falls back to the cross product of the restored positions' differences.
// Every restored sample holding a NaN or an infinity is counted (binding NGI_SR_BINDING_CHECK,
// zeroed by SuperResolution::record, read by checkLastRestore): weights whose values overflow
// must end in an error naming the network, not in a blank image.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"
#include "texel.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer positionTensor;
layout(set = 0, binding = NGI_SR_BINDING_LEVEL, rgba32ui) uniform writeonly uimage2D fullLevel;
layout(set = 0, binding = NGI_SR_BINDING_STORED, rgba32ui) uniform readonly uimage2D storedLevel;
layout(set = 0, binding = NGI_SR_BINDING_CHECK, std430) buffer Check { uint nonFiniteSamples; };

vec3 position(int x, int y) { return texelFetch(positionTensor, tensorIndex(0, x, y, int(pc.width), int(pc.height))).xyz; }

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int f = int(pc.factor), cw = int(pc.inWidth), ch = int(pc.inHeight);
    // One invocation per (fine column, coarse row): the 4 Catmull-Rom rows of stored normals
    // are interpolated once for the f fine rows between two coarse rows. No early return
    // (lavapipe runs code under divergent control flow per lane): invocations past the edge
    // compute the last column / coarse row and skip the count and the stores.
    const int X = min(int(gl_GlobalInvocationID.x), width - 1), y0 = min(int(gl_GlobalInvocationID.y), ch - 1);
    const bool inside = int(gl_GlobalInvocationID.x) < width && int(gl_GlobalInvocationID.y) < ch;
    const int x0 = X / f;
    const vec4 wx = catmullRomWeights(float(X % f) / float(f));
    vec3 rows[4];
    [[unroll]] for (int ky = 0; ky < 4; ++ky) {
        const int y = clamp(y0 - 1 + ky, 0, ch - 1);
        vec3 row = vec3(0.0);
        [[unroll]] for (int kx = 0; kx < 4; ++kx)
            row += wx[kx] * texelNormal(imageLoad(storedLevel, ivec2(clamp(x0 - 1 + kx, 0, cw - 1), y)));
        rows[ky] = row;
    }
    const int fineRows = min(f, height - y0 * f);
    uint nonFinite = 0u;
    for (int t = 0; t < fineRows; ++t) {
        const int Y = y0 * f + t;
        const vec3 p = position(X, Y);
        const vec4 wy = catmullRomWeights(float(t) / float(f));
        vec3 n = vec3(0.0);
        [[unroll]] for (int ky = 0; ky < 4; ++ky) n += wy[ky] * rows[ky];
        if (!(length(n) > 1e-12)) {
            const vec3 du = position(min(X + 1, width - 1), Y) - position(max(X - 1, 0), Y);
            const vec3 dv = position(X, min(Y + 1, height - 1)) - position(X, max(Y - 1, 0));
            n = cross(du, dv);
        }
        if (any(isnan(p)) || any(isinf(p))) ++nonFinite;
        if (inside) imageStore(fullLevel, ivec2(X, Y), makeTexel(p, n));
    }
    if (inside && nonFinite > 0u) atomicAdd(nonFiniteSamples, nonFinite);
}
