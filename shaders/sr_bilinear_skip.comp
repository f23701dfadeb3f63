#version 450
// BilinearSkip / CubicSkip (ngi/network_weights.h): out = upsample_x f(coarse) + fine, exact
// interpolation (bilinear: align_corners = true, PyTorch's fp32 source coordinate X * (1 / f);
// cubic: Catmull-Rom) and HermiteSkip (normals at binding 2), the kind a specialization
// constant (NGI_SR_SKIP_*). CPU references: ngi::nn::bilinearSkip, cubicSkip, hermiteSkip.
// BLEND (the network's output skip, a chart whose residual gain g = pc.residualGain is not 1):
// out = c + g (out - c), c the Catmull-Rom of the coarse input (ngi::nn::referenceForward's
// residualGain; its own pipeline, so g = 1 runs exactly the code without it).
// The kind is a specialization constant and nothing returns early: on lavapipe, code under
// divergent control flow and the unused kinds' code cost (the Hermite skip at 1025^2 took
// 220 ms with the kind a push-constant branch).
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer coarseTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN1) uniform samplerBuffer fineTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN2) uniform samplerBuffer normalTensor;
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;

layout(constant_id = 0) const int KIND = NGI_SR_SKIP_BILINEAR;  // NGI_SR_SKIP_*
layout(constant_id = 1) const int BLEND = 0;                     // 1: blend toward the Catmull-Rom

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int X = int(gl_GlobalInvocationID.x), Y = int(gl_GlobalInvocationID.y);
    // Invocations past the edge compute the last sample and skip the store.
    const int x = min(X, width - 1), y = min(Y, height - 1);
    const bool inside = X < width && Y < height;
    if (KIND == NGI_SR_SKIP_HERMITE) {
        // One invocation per (fine column, coarse row): the column's rows and tangents are
        // computed once for the f fine rows between two coarse rows (8x fewer fetches at x8).
        const int f = int(pc.factor), y0 = min(Y, int(pc.inHeight) - 1);
        const bool columnInside = X < width && Y < int(pc.inHeight);
        const HermiteColumn c = hermiteColumn(coarseTensor, normalTensor, x, y0);
        // BLEND's Catmull-Rom, column-wise as the Hermite: the four coarse rows' horizontal
        // passes once per invocation (cubicUpsample's rows and border rule, the same sums).
        vec4 cubicRows[4];
        if (BLEND != 0) {
            const int cw = int(pc.inWidth), ch = int(pc.inHeight), x0 = x / f;
            const vec4 wx = catmullRomWeights(float(x % f) / float(f));
            [[unroll]] for (int ky = 0; ky < 4; ++ky) {
                const int yy = y0 - 1 + ky;
                if (yy < 0) cubicRows[ky] = 2.0 * cubicRow(coarseTensor, 0, x0, 0, wx, cw, ch) - cubicRow(coarseTensor, 0, x0, 1, wx, cw, ch);
                else if (yy >= ch)
                    cubicRows[ky] = 2.0 * cubicRow(coarseTensor, 0, x0, ch - 1, wx, cw, ch) - cubicRow(coarseTensor, 0, x0, ch - 2, wx, cw, ch);
                else cubicRows[ky] = cubicRow(coarseTensor, 0, x0, yy, wx, cw, ch);
            }
        }
        const int rows = min(f, height - y0 * f);
        for (int t = 0; t < rows; ++t) {
            const int at = tensorIndex(0, x, y0 * f + t, width, height);
            vec4 v = texelFetch(fineTensor, at) + vec4(hermiteCurve(c.p0, c.m0, c.p1, c.m1, float(t) / float(f)), 0.0);
            if (BLEND != 0) {
                const vec4 wy = catmullRomWeights(float(t) / float(f));
                vec4 cubic = vec4(0.0);
                [[unroll]] for (int ky = 0; ky < 4; ++ky) cubic += wy[ky] * cubicRows[ky];
                v = cubic + pc.residualGain * (v - cubic);
            }
            if (columnInside) imageStore(outputTensor, at, v);
        }
    } else {
        for (int g = 0; g < int(pc.outGroups); ++g) {
            const int at = tensorIndex(g, x, y, width, height);
            const vec4 up = KIND == NGI_SR_SKIP_CUBIC ? cubicUpsample(coarseTensor, g, x, y) : bilinearUpsample(coarseTensor, g, x, y);
            vec4 v = texelFetch(fineTensor, at) + up;
            if (BLEND != 0) {
                const vec4 cubic = KIND == NGI_SR_SKIP_CUBIC ? up : cubicUpsample(coarseTensor, g, x, y);
                v = cubic + pc.residualGain * (v - cubic);
            }
            if (inside) imageStore(outputTensor, at, v);
        }
    }
}
