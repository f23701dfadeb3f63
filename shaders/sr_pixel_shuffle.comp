#version 450
// PixelShuffle by `factor` + crop to the nested fine grid (ngi/network_weights.h):
// out[c](Y, X) = in[c * f^2 + (Y % f) * f + X % f](Y / f, X / f), PyTorch channel order.
// One invocation per output pixel, all channel groups. CPU reference: ngi::nn::pixelShuffleCrop.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer inputTensor;
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int X = int(gl_GlobalInvocationID.x), Y = int(gl_GlobalInvocationID.y);
    if (X >= width || Y >= height) return;
    const int f = int(pc.factor), channels = int(pc.channels);
    const int sub = (Y % f) * f + X % f;
    const int cx = X / f, cy = Y / f;
    for (int g = 0; g < int(pc.outGroups); ++g) {
        vec4 v = vec4(0.0);
        for (int j = 0; j < 4; ++j) {
            const int c = 4 * g + j;
            if (c >= channels) break;
            const int ic = c * f * f + sub;
            v[j] = texelFetch(inputTensor, tensorIndex(ic / 4, cx, cy, int(pc.inWidth), int(pc.inHeight)))[ic % 4];
        }
        imageStore(outputTensor, tensorIndex(g, X, Y, width, height), v);
    }
}
