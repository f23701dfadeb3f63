#version 450
// PixelShuffle by `factor` + crop to the nested fine grid (ngi/network_weights.h):
// out[c](Y, X) = in[c * f^2 + (Y % f) * f + X % f](Y / f, X / f), PyTorch channel order.
// CPU reference: ngi::nn::pixelShuffleCrop.
//
// One invocation per (coarse column, fine row): it writes the f fine pixels of that row
// segment. For a fixed output channel the f values of the segment are f consecutive input
// channels, i.e. f / 4 texels (f >= 4), so each fetched texel serves 4 output pixels instead
// of one (measured: ngi-bench-sr, pixel_shuffle row).
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
// The factor is a specialization constant so that the segment loop unrolls (and no code runs
// under divergent control flow before the stores: lavapipe executes it per lane).
layout(constant_id = 0) const int FACTOR = 8;
layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer inputTensor;
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int f = FACTOR, channels = int(pc.channels);
    const int inWidth = int(pc.inWidth), inHeight = int(pc.inHeight);
    // Invocations past the edge read the last segment and skip the stores.
    const int cx = min(int(gl_GlobalInvocationID.x), inWidth - 1), Y = min(int(gl_GlobalInvocationID.y), height - 1);
    const bool inside = int(gl_GlobalInvocationID.x) < inWidth && int(gl_GlobalInvocationID.y) < height;
    const int cy = Y / f, rowBase = (Y % f) * f;
    const int inGroups = int(pc.inGroups);
    for (int g = 0; g < int(pc.outGroups); ++g) {
        vec4 cached[4];
        [[unroll]] for (int j = 0; j < f; ++j) {
            const int X = cx * f + j;
            vec4 v = vec4(0.0);
            [[unroll]] for (int lane = 0; lane < 4; ++lane) {
                const int c = 4 * g + lane;
                const int ic = c * f * f + rowBase + j;
                // f % 4 == 0: rowBase + j = j (mod 4), so the fetch is every 4th j, fixed.
                if (j == 0 || f % 4 != 0 || j % 4 == 0)
                    cached[lane] = texelFetch(inputTensor, tensorIndex(min(ic / 4, inGroups - 1), cx, cy, inWidth, inHeight));
                v[lane] = c < channels ? cached[lane][ic % 4] : 0.0;
            }
            if (inside && X < width) imageStore(outputTensor, tensorIndex(g, X, Y, width, height), v);
        }
    }
}
