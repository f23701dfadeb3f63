#version 450
// Convolution 1x1 / 3x3 of the super-resolution network (ngi/network_weights.h, "Conv"):
// out = act(bias + sum w * in) (+ residual), zero or replicate padding, fp32 accumulation.
// CPU reference: ngi::nn::conv2d (offline/nn/src/reference_forward.cpp).
//
// Register blocking (direct convolution): one dispatch per block of OPG output channel
// groups (4 channels each); each invocation accumulates that block for PX horizontally
// adjacent pixels in registers. Activations are read with texelFetch from a uniform texel
// buffer, one vec4 = 4 input channels; the PX + KSIZE - 1 texels of a kernel row are fetched
// once and feed every tap, pixel and output group (each input value: KSIZE x OPG x 4 FMAs per
// pixel it reaches). Weights come from a uniform-buffer window that starts at the block's
// weights (dynamic offset), one vec4 = 4 output channels per (output group, input group,
// tap, input channel), in the order the loop consumes them: acc = fma(w, in.j, acc).
//
// What lavapipe (Mesa 22.3, LLVM 15, 8 lanes) needs, measured with ngi-bench-sr --micro:
// - Every weight index a compile-time constant (loops unrolled through the specialization
//   constants): a UBO offset that is not provably uniform becomes a per-lane gather.
// - No code under divergent control flow before the stores: lavapipe turns a UBO load
//   inside an if (or after an early return) into a per-lane gather too, and an early return
//   cost 18x (0.6 vs 11 GFLOP/s at 32 -> 32, 129^2). Invocations past the edge compute on
//   clamped coordinates and only skip their stores.
// - The epilogue fixed by a specialization constant (EPILOGUE): a residual fetch and a fused
//   skip behind push-constant branches made the shader 50x slower to compile and 4.6x
//   slower to run (8 -> 8 3x3: 2.5 vs 11.5 GFLOP/s), even where the branch was never taken.
// - Explicit fma(): lavapipe does not contract a * b + c.
// A BilinearSkip / CubicSkip that only consumes this conv's output is fused into its
// epilogue (EPILOGUE_SKIP): one full-resolution pass and tensor less.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(constant_id = 0) const int KSIZE = 3;  // 1 or 3
layout(constant_id = 1) const int OPG = 2;    // output channel groups per invocation
layout(constant_id = 2) const int PX = 4;     // pixels per invocation (along x)
layout(constant_id = 3) const int IN_GROUPS = 8;  // input channel groups
layout(constant_id = 4) const int EPILOGUE = 0;   // NGI_SR_EPILOGUE_* bits

layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer inputTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN1) uniform samplerBuffer residualTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN2) uniform samplerBuffer coarseTensor;  // fused bilinear skip
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;
// Block layout: vec4 at ((o * IN_GROUPS + ig) * KSIZE^2 + tap) * 4 + j = the weights of
// output channels 4 * (groupBase + o) + 0..3 for input channel 4 * ig + j; biases at BIAS + o.
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
    // No early return (see the top): invocations past the edge compute on clamped
    // coordinates and skip their stores.
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
            [[unroll]] for (int c = 0; c < COLS; ++c) {
                const int sxRaw = x0 + c - R;
                const vec4 fetched = texelFetch(inputTensor, rowBase + clamp(sxRaw, 0, width - 1));
                const bool inside = replicate || (rowInside && sxRaw >= 0 && sxRaw < width);
                const vec4 t = inside ? fetched : vec4(0.0);
                [[unroll]] for (int kx = 0; kx < KSIZE; ++kx) {
                    const int p = c - kx;
                    if (p < 0 || p >= PX) continue;
                    [[unroll]] for (int o = 0; o < OPG; ++o) {
                        const int wi = ((o * IN_GROUPS + ig) * TAPS + ky * KSIZE + kx) * 4;
                        [[unroll]] for (int j = 0; j < 4; ++j) acc[o][p] = fma(weights[wi + j], vec4(t[j]), acc[o][p]);
                    }
                }
            }
        }
    }

    const bool residual = (EPILOGUE & NGI_SR_EPILOGUE_RESIDUAL) != 0;
    const bool skip = (EPILOGUE & NGI_SR_EPILOGUE_SKIP) != 0;
    [[unroll]] for (int o = 0; o < OPG; ++o) {
        const int og = int(pc.groupBase) + o;
        [[unroll]] for (int p = 0; p < PX; ++p) {
            const int x = x0 + p;
            if (og < int(pc.outGroups) && x < width && y < height) {
                const int at = tensorIndex(og, x, y, width, height);
                vec4 v = activate(acc[o][p], pc.activation, pc.slope);
                if (residual) v += texelFetch(residualTensor, at);
                if (skip) {
                    const bool cubicSkip = (EPILOGUE & NGI_SR_EPILOGUE_CUBIC) != 0;
                    const vec4 up = cubicSkip ? cubicUpsample(coarseTensor, og, x, y) : bilinearUpsample(coarseTensor, og, x, y);
                    v += up;
                    if ((EPILOGUE & NGI_SR_EPILOGUE_BLEND) != 0) {  // as sr_bilinear_skip.comp's BLEND
                        const vec4 cubic = cubicSkip ? up : cubicUpsample(coarseTensor, og, x, y);
                        v = cubic + pc.residualGain * (v - cubic);
                    }
                }
                imageStore(outputTensor, at, v);
            }
        }
    }
}
