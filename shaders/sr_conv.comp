#version 450
// Convolution 1x1 / 3x3 of the super-resolution network (ngi/network_weights.h, "Conv"):
// out = act(bias + sum w * in) (+ residual), zero or replicate padding, fp32 accumulation.
// CPU reference: ngi::nn::conv2d (offline/nn/src/reference_forward.cpp).
//
// Kernel shape (measured on lavapipe: engine/tools/ngi_bench_sr.cpp --micro): one dispatch
// per block of OPG output channel groups (4 channels each); each invocation computes that
// block for PX horizontally adjacent pixels. Activations are read with texelFetch from a
// uniform texel buffer, one vec4 = 4 input channels; the PX + KSIZE - 1 texels of a kernel
// row are fetched once and reused by every tap and output group. Weights come from a
// uniform-buffer window that starts at the block's weights (dynamic offset) as one mat4 per
// (output group, input group, tap): acc += W * in. Every weight index is a compile-time
// constant (the input-group loop is unrolled through the IN_GROUPS specialization constant):
// lavapipe loads a UBO value once per subgroup only when its offset is provably uniform
// (constants and push constants); an index built from a loop counter or gl_WorkGroupID
// becomes a per-lane gather, which measured 3-5x slower. A BilinearSkip that only consumes
// this conv's output is fused into its epilogue (NGI_SR_BILINEAR_SKIP): one full-resolution
// pass and tensor less.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(constant_id = 0) const int KSIZE = 3;  // 1 or 3
layout(constant_id = 1) const int OPG = 2;    // output channel groups per invocation
layout(constant_id = 2) const int PX = 4;     // pixels per invocation (along x)
layout(constant_id = 3) const int IN_GROUPS = 8;  // input channel groups

layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer inputTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN1) uniform samplerBuffer residualTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN2) uniform samplerBuffer coarseTensor;  // fused bilinear skip
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;
// Block layout: mat4 columns at ((o * IN_GROUPS + ig) * KSIZE^2 + tap) * 4 + j (column j =
// the 4 output channels' weights for input channel 4 * ig + j), biases at BIAS + o.
layout(set = 0, binding = NGI_SR_BINDING_WEIGHTS, std140) uniform Weights { vec4 weights[NGI_SR_UBO_VEC4S]; };

const int R = KSIZE / 2;
const int TAPS = KSIZE * KSIZE;
const int COLS = PX + KSIZE - 1;
const int BIAS = OPG * IN_GROUPS * TAPS * 4;

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int x0 = int(gl_GlobalInvocationID.x) * PX;
    const int y = int(gl_GlobalInvocationID.y);
    if (x0 >= width || y >= height) return;
    const bool replicate = (pc.flags & NGI_SR_REPLICATE) != 0u;
    const int plane = width * height;

    vec4 acc[OPG][PX];
    [[unroll]] for (int o = 0; o < OPG; ++o)
        [[unroll]] for (int p = 0; p < PX; ++p) acc[o][p] = weights[BIAS + o];

    [[unroll]] for (int ig = 0; ig < IN_GROUPS; ++ig) {
        [[unroll]] for (int ky = 0; ky < KSIZE; ++ky) {
            const int syRaw = y + ky - R;
            const bool rowInside = syRaw >= 0 && syRaw < height;
            const int rowBase = ig * plane + clamp(syRaw, 0, height - 1) * width;
            // One texel live at a time: each fetched column feeds every (tap, pixel) pair
            // that reads it (lavapipe keeps a vec4 in 4 AVX registers; 16 exist).
            [[unroll]] for (int c = 0; c < COLS; ++c) {
                const int sxRaw = x0 + c - R;
                vec4 t = texelFetch(inputTensor, rowBase + clamp(sxRaw, 0, width - 1));
                if (!(replicate || (rowInside && sxRaw >= 0 && sxRaw < width))) t = vec4(0.0);
                [[unroll]] for (int kx = 0; kx < KSIZE; ++kx) {
                    const int p = c - kx;
                    if (p < 0 || p >= PX) continue;
                    [[unroll]] for (int o = 0; o < OPG; ++o) {
                        const int wi = ((o * IN_GROUPS + ig) * TAPS + ky * KSIZE + kx) * 4;
                        acc[o][p] += mat4(weights[wi], weights[wi + 1], weights[wi + 2], weights[wi + 3]) * t;
                    }
                }
            }
        }
    }

    const bool residual = (pc.flags & NGI_SR_RESIDUAL) != 0u;
    const bool skip = (pc.flags & NGI_SR_BILINEAR_SKIP) != 0u;
    [[unroll]] for (int o = 0; o < OPG; ++o) {
        const int og = int(pc.groupBase) + o;
        if (og >= int(pc.outGroups)) break;
        [[unroll]] for (int p = 0; p < PX; ++p) {
            const int x = x0 + p;
            if (x >= width) break;
            const int at = tensorIndex(og, x, y, width, height);
            vec4 v = activate(acc[o][p], pc.activation, pc.slope);
            if (residual) v += texelFetch(residualTensor, at);
            if (skip) v += skipUpsample(coarseTensor, og, x, y);
            imageStore(outputTensor, at, v);
        }
    }
}
