#version 450
// Bicubic restoration of level 0 from the stored level in one pass (a chart no network
// restores, under super-resolution): positions by Catmull-Rom upsampling by the factor
// f = (fine - 1) / (coarse - 1), rows first, linear extrapolation beyond the border: the
// network's CubicSkip with a zero residual, CPU reference ngi::nn::cubicSkip (what ngi-eval's
// --bicubic and the bake's rate control restore), so the engine draws what they measure.
// Normals: the stored normals by Catmull-Rom clamped at the border and renormalized, as the
// network's output pass (sr_output.comp) writes them. Levels 1 .. stored - 1 are then nested
// subsamples of level 0 (mip_downsample.comp), as after a network restore.
#extension GL_EXT_control_flow_attributes : require
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"

layout(local_size_x = NGI_TILE, local_size_y = NGI_TILE) in;
layout(set = 0, binding = 0, rgba32ui) uniform writeonly uimage2D fineLevel;
layout(set = 0, binding = 1, rgba32ui) uniform readonly uimage2D coarseLevel;
layout(push_constant) uniform Push { MipPushConstants pc; };

// ngi::nn::catmullRomWeights, the same expressions as sr_common.glsl.
vec4 catmullRomWeights(float t)
{
    const float t2 = t * t, t3 = t2 * t;
    return vec4(-0.5 * t3 + t2 - 0.5 * t, 1.5 * t3 - 2.5 * t2 + 1.0, -1.5 * t3 + 2.0 * t2 + 0.5 * t, 0.5 * t3 - 0.5 * t2);
}

vec3 storedPosition(int x, int y) { return texelPosition(imageLoad(coarseLevel, ivec2(x, y))); }

// Stored position (x, y) of row y, extrapolated linearly beyond the border in x.
vec3 cubicSample(int x, int y, int n)
{
    if (x < 0) return 2.0 * storedPosition(0, y) - storedPosition(1, y);
    if (x >= n) return 2.0 * storedPosition(n - 1, y) - storedPosition(n - 2, y);
    return storedPosition(x, y);
}

vec3 cubicRow(int x0, int y, vec4 wx, int n)
{
    vec3 r = vec3(0.0);
    [[unroll]] for (int kx = 0; kx < 4; ++kx) r += wx[kx] * cubicSample(x0 - 1 + kx, y, n);
    return r;
}

void main()
{
    const ivec2 X = ivec2(gl_GlobalInvocationID.xy);
    if (X.x >= int(pc.fineSize) || X.y >= int(pc.fineSize)) return;
    const int n = int(pc.coarseSize), f = int((pc.fineSize - 1u) / (pc.coarseSize - 1u));
    const int x0 = X.x / f, y0 = X.y / f;
    const vec4 wx = catmullRomWeights(float(X.x % f) / float(f)), wy = catmullRomWeights(float(X.y % f) / float(f));
    vec3 p = vec3(0.0), nrm = vec3(0.0);
    [[unroll]] for (int ky = 0; ky < 4; ++ky) {
        const int y = y0 - 1 + ky;
        vec3 r;
        if (y < 0) r = 2.0 * cubicRow(x0, 0, wx, n) - cubicRow(x0, 1, wx, n);
        else if (y >= n) r = 2.0 * cubicRow(x0, n - 1, wx, n) - cubicRow(x0, n - 2, wx, n);
        else r = cubicRow(x0, y, wx, n);
        p += wy[ky] * r;
        const int yc = clamp(y, 0, n - 1);
        vec3 rn = vec3(0.0);
        [[unroll]] for (int kx = 0; kx < 4; ++kx)
            rn += wx[kx] * texelNormal(imageLoad(coarseLevel, ivec2(clamp(x0 - 1 + kx, 0, n - 1), yc)));
        nrm += wy[ky] * rn;
    }
    // Stored samples: the texel itself (Catmull-Rom at t = 0 is the sample; the packed normal stays).
    if (X.x % f == 0 && X.y % f == 0) { imageStore(fineLevel, X, imageLoad(coarseLevel, X / f)); return; }
    imageStore(fineLevel, X, makeTexel(p, length(nrm) > 1e-12 ? nrm : texelNormal(imageLoad(coarseLevel, ivec2(x0, y0)))));
}
