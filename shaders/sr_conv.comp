#version 450
// Convolution 1x1 / 3x3 of the super-resolution network (ngi/network_weights.h, "Conv"):
// out = act(bias + sum w * in) (+ residual), zero or replicate padding, fp32 accumulation.
// CPU reference: ngi::nn::conv2d (offline/nn/src/reference_forward.cpp).
//
// Kernel shape (measured on lavapipe, see engine/tools/ngi_bench_sr.cpp --sweep): each
// invocation computes OPG groups of 4 output channels for PX horizontally adjacent pixels.
// Activations are read with texelFetch from a uniform texel buffer, one vec4 = 4 input
// channels; the PX + KSIZE - 1 texels of a kernel row are fetched once and reused by every
// tap and output group. Weights come from a 64 KiB uniform-buffer window as one mat4 per
// (output group, input group, tap): acc += W * in is 16 FMAs per fetch-free step. Only the
// loop over input groups stays a loop (no giant unrolls: compile time stays in the
// hundreds of milliseconds).
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(constant_id = 0) const int KSIZE = 3;  // 1 or 3
layout(constant_id = 1) const int OPG = 2;    // output channel groups per invocation
layout(constant_id = 2) const int PX = 4;     // pixels per invocation (along x)

layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer inputTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN1) uniform samplerBuffer residualTensor;
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;
// Chunk layout: mat4 columns at ((og * inGroups + ig) * KSIZE^2 + tap) * 4 + j (column j =
// the 4 output channels' weights for input channel 4 * ig + j), biases at biasBase + og.
layout(set = 0, binding = NGI_SR_BINDING_WEIGHTS, std140) uniform Weights { vec4 weights[NGI_SR_UBO_VEC4S]; };

const int R = KSIZE / 2;
const int TAPS = KSIZE * KSIZE;
const int COLS = PX + KSIZE - 1;

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int x0 = int(gl_GlobalInvocationID.x) * PX;
    const int y = int(gl_GlobalInvocationID.y);
    if (x0 >= width || y >= height) return;
    const int chunkGroups = int(pc.chunkGroups), inGroups = int(pc.inGroups);
    const int og0 = int(gl_GlobalInvocationID.z) * OPG;  // first output group, within the chunk
    if (og0 >= chunkGroups) return;
    const bool replicate = (pc.flags & NGI_SR_REPLICATE) != 0u;
    const int plane = width * height;

    int ogRead[OPG];  // clamped so every weight read stays inside the chunk
    vec4 acc[OPG][PX];
    for (int o = 0; o < OPG; ++o) {
        ogRead[o] = min(og0 + o, chunkGroups - 1);
        const vec4 bias = weights[pc.biasBase + ogRead[o]];
        for (int p = 0; p < PX; ++p) acc[o][p] = bias;
    }

    for (int ig = 0; ig < inGroups; ++ig) {
        const int base = ig * plane;
        for (int ky = 0; ky < KSIZE; ++ky) {
            const int syRaw = y + ky - R;
            const bool rowInside = syRaw >= 0 && syRaw < height;
            const int rowBase = base + clamp(syRaw, 0, height - 1) * width;
            vec4 row[COLS];
            for (int c = 0; c < COLS; ++c) {
                const int sxRaw = x0 + c - R;
                const vec4 t = texelFetch(inputTensor, rowBase + clamp(sxRaw, 0, width - 1));
                row[c] = (replicate || (rowInside && sxRaw >= 0 && sxRaw < width)) ? t : vec4(0.0);
            }
            for (int kx = 0; kx < KSIZE; ++kx) {
                const int tap = ky * KSIZE + kx;
                for (int o = 0; o < OPG; ++o) {
                    const int wi = ((ogRead[o] * inGroups + ig) * TAPS + tap) * 4;
                    const mat4 w = mat4(weights[wi], weights[wi + 1], weights[wi + 2], weights[wi + 3]);
                    for (int p = 0; p < PX; ++p) acc[o][p] += w * row[p + kx];
                }
            }
        }
    }

    const bool residual = (pc.flags & NGI_SR_RESIDUAL) != 0u;
    for (int o = 0; o < OPG; ++o) {
        if (og0 + o >= chunkGroups) break;
        const int og = int(pc.groupBase) + og0 + o;
        for (int p = 0; p < PX; ++p) {
            const int x = x0 + p;
            if (x >= width) break;
            const int at = tensorIndex(og, x, y, width, height);
            vec4 v = activate(acc[o][p], pc.activation, pc.slope);
            if (residual) v += texelFetch(residualTensor, at);
            imageStore(outputTensor, at, v);
        }
    }
}
