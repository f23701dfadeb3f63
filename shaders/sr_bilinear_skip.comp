#version 450
// BilinearSkip / CubicSkip (ngi/network_weights.h): out = upsample_x f(coarse) + fine, exact
// interpolation (bilinear: align_corners = true, PyTorch's fp32 source coordinate X * (1 / f);
// cubic: Catmull-Rom, with pc.flags NGI_SR_CUBIC) and HermiteSkip (pc.flags NGI_SR_HERMITE,
// normals at binding 2). CPU references: ngi::nn::bilinearSkip, cubicSkip, hermiteSkip.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "sr_common.glsl"

layout(local_size_x = NGI_SR_LOCAL_X, local_size_y = NGI_SR_LOCAL_Y) in;
layout(set = 0, binding = NGI_SR_BINDING_IN0) uniform samplerBuffer coarseTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN1) uniform samplerBuffer fineTensor;
layout(set = 0, binding = NGI_SR_BINDING_IN2) uniform samplerBuffer normalTensor;
layout(set = 0, binding = NGI_SR_BINDING_OUT, rgba32f) uniform writeonly imageBuffer outputTensor;

void main()
{
    const int width = int(pc.width), height = int(pc.height);
    const int X = int(gl_GlobalInvocationID.x), Y = int(gl_GlobalInvocationID.y);
    if (X >= width || Y >= height) return;
    if ((pc.flags & NGI_SR_HERMITE) != 0u) {
        const int at = tensorIndex(0, X, Y, width, height);
        imageStore(outputTensor, at, texelFetch(fineTensor, at) + vec4(hermiteUpsample(coarseTensor, normalTensor, X, Y), 0.0));
        return;
    }
    for (int g = 0; g < int(pc.outGroups); ++g) {
        const int at = tensorIndex(g, X, Y, width, height);
        imageStore(outputTensor, at, texelFetch(fineTensor, at) + skipUpsample(coarseTensor, g, X, Y));
    }
}
