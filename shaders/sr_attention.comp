#version 450
// NeighborhoodCrossAttention of the super-resolution network (ngi/network_weights.h):
// local (windowed) attention, cost linear in pixels. Each invocation handles one pixel and
// all heads: for every window offset inside the image (outside ones are masked out), the
// per-head logits scale * q(p).k(p + o) update a running softmax (maximum, sum and the
// rescaled weighted sum of v), i.e. one pass over k and v ("online softmax", Milakov and
// Gimelshein 2018); equal to the two-pass reference up to fp32 rounding.
// CPU reference: ngi::nn::neighborhoodCrossAttention.
// Channels, heads and window are specialization constants and the channel loops are unrolled,
// so every array index is a constant (a computed index makes lavapipe gather and scatter).
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(constant_id = 0) const int CHANNELS = 32;  // CHANNELS of q, k, v
layout(constant_id = 1) const int HEADS = 4;
layout(constant_id = 2) const int RADIUS = 1;  // window side = 2 * RADIUS + 1
const int GROUPS = (CHANNELS + 3) / 4;
const int HEAD_CHANNELS = CHANNELS / HEADS;

layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer queryTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN1) uniform samplerBuffer keyTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN2) uniform samplerBuffer valueTensor;
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    // No early return and no skipped window positions (lavapipe runs code under divergent
    // control flow per lane): invocations past the edge compute the last sample and skip
    // the store; a window position outside the image takes part with weight 0 and rescale
    // 1, which leaves the running state exactly as skipping it did.
    const bool inside = int(gl_GlobalInvocationID.x) < width && int(gl_GlobalInvocationID.y) < height;
    const int x = min(int(gl_GlobalInvocationID.x), width - 1), y = min(int(gl_GlobalInvocationID.y), height - 1);

    vec4 q[GROUPS];
    vec4 acc[GROUPS];
    [[unroll]] for (int g = 0; g < GROUPS; ++g) {
        q[g] = texelFetch(queryTensor, tensorIndex(g, x, y, width, height));
        acc[g] = vec4(0.0);
    }
    float runningMax[HEADS], runningSum[HEADS];
    [[unroll]] for (int h = 0; h < HEADS; ++h) {
        runningMax[h] = uintBitsToFloat(0xff800000u);  // -inf
        runningSum[h] = 0.0;
    }

    [[unroll]] for (int dy = -RADIUS; dy <= RADIUS; ++dy) {
        const int sy = clamp(y + dy, 0, height - 1);
        [[unroll]] for (int dx = -RADIUS; dx <= RADIUS; ++dx) {
            const int sx = clamp(x + dx, 0, width - 1);
            const bool valid = y + dy == sy && x + dx == sx;
            float logit[HEADS];
            [[unroll]] for (int h = 0; h < HEADS; ++h) logit[h] = 0.0;
            [[unroll]] for (int g = 0; g < GROUPS; ++g) {
                const vec4 prod = q[g] * texelFetch(keyTensor, tensorIndex(g, sx, sy, width, height));
                [[unroll]] for (int j = 0; j < 4; ++j) {
                    const int c = 4 * g + j;
                    if (c < CHANNELS) logit[c / HEAD_CHANNELS] += prod[j];
                }
            }
            float rescale[HEADS], weight[HEADS];
            [[unroll]] for (int h = 0; h < HEADS; ++h) {
                const float l = pc.scale * logit[h];
                const float m = valid ? max(runningMax[h], l) : runningMax[h];
                rescale[h] = valid ? exp(runningMax[h] - m) : 1.0;
                weight[h] = valid ? exp(l - m) : 0.0;
                runningSum[h] = runningSum[h] * rescale[h] + weight[h];
                runningMax[h] = m;
            }
            [[unroll]] for (int g = 0; g < GROUPS; ++g) {
                const vec4 v = texelFetch(valueTensor, tensorIndex(g, sx, sy, width, height));
                [[unroll]] for (int j = 0; j < 4; ++j) {
                    const int c = min(4 * g + j, CHANNELS - 1);
                    const int h = c / HEAD_CHANNELS;
                    acc[g][j] = acc[g][j] * rescale[h] + weight[h] * v[j];
                }
            }
        }
    }
    [[unroll]] for (int g = 0; g < GROUPS; ++g) {
        vec4 out_;
        [[unroll]] for (int j = 0; j < 4; ++j) {
            const int c = 4 * g + j;
            out_[j] = c < CHANNELS ? acc[g][j] / runningSum[c / HEAD_CHANNELS] : 0.0;
        }
        if (inside) imageStore(outputTensor, tensorIndex(g, x, y, width, height), out_);
    }
}
