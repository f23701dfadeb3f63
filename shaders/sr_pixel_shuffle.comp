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
layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer inputTensor;
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int cx = int(gl_GlobalInvocationID.x), Y = int(gl_GlobalInvocationID.y);
    const int f = int(pc.factor), channels = int(pc.channels);
    const int inWidth = int(pc.inWidth), inHeight = int(pc.inHeight);
    if (cx >= inWidth || Y >= height) return;
    const int cy = Y / f, rowBase = (Y % f) * f;
    for (int g = 0; g < int(pc.outGroups); ++g) {
        vec4 cached[4];
        for (int j = 0; j < f; ++j) {
            const int X = cx * f + j;
            if (X >= width) break;
            vec4 v = vec4(0.0);
            [[unroll]] for (int lane = 0; lane < 4; ++lane) {
                const int c = 4 * g + lane;
                if (c >= channels) break;
                const int ic = c * f * f + rowBase + j;
                if (j == 0 || ic % 4 == 0) cached[lane] = texelFetch(inputTensor, tensorIndex(ic / 4, cx, cy, inWidth, inHeight));
                v[lane] = cached[lane][ic % 4];
            }
            imageStore(outputTensor, tensorIndex(g, X, Y, width, height), v);
        }
    }
}
