// The shading of ngi's own fragment shaders (surface.frag, adaptive_surface.frag): headlight
// (two-sided Lambert + Blinn-Phong), normals as colours, wireframe overlay (edges from
// barycentrics, constant pixel width), and LoD colouring (one hue per mip level, blended by the
// geomorph factor). With NGI_BASE_COLOUR defined, the base colour is the chart's colour image
// sampled at the chart uv (location 6), its alpha cuts the surface out (chartUncovered) in the
// pipelines specialized to NGI_SPEC_CUT_OUT, and
// mode NGI_MODE_BASE_COLOUR shows it unlit.
// Included after #version, the include extension and ngi_shared.h.

layout(push_constant) uniform Push { DrawPushConstants pc; };
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inPosition;
layout(location = 2) noperspective in vec3 inBarycentric;
layout(location = 3) flat in vec4 inEyeLod;  // camera in normalized space, continuous LoD
// World-space position and normal: unused here, declared because every output of the vertex
// stage must have an input (else the validation layer warns: OutputNotConsumed).
layout(location = 4) in vec3 inWorldPosition;
layout(location = 5) in vec3 inWorldNormal;
layout(location = 6) in vec2 inChartUv;  // the vertex's uv on the chart's square
#ifdef NGI_BASE_COLOUR
// The chart's base colour over its square (sRGB, mipmapped, ngi/engine/color_images.h); a
// chart without one binds a 1x1 grey. Set 0, the same binding in both draws.
layout(set = 0, binding = NGI_DRAW_BINDING_BASE_COLOUR) uniform sampler2D baseColour;
#include "chart_colour.glsl"
layout(constant_id = NGI_SPEC_CUT_OUT) const bool CUT_OUT = false;  // the alpha test, where needed
#endif
layout(location = 0) out vec4 outColor;

vec3 levelColour(float level)
{
    // A hue wheel over levels 0..10, distinct neighbours.
    float h = fract(level * 0.37);
    vec3 k = clamp(abs(fract(h + vec3(0.0, 2.0 / 3.0, 1.0 / 3.0)) * 6.0 - 3.0) - 1.0, 0.0, 1.0);
    return mix(vec3(0.9), k, 0.65);
}

void main()
{
    vec3 n = normalize(inNormal);
    vec3 toEye = normalize(inEyeLod.xyz - inPosition);
    if (dot(n, toEye) < 0.0) n = -n;  // two-sided: cut surfaces show their back
    float diffuse = max(dot(n, toEye), 0.0);
    float specular = pow(max(dot(n, toEye), 0.0), 48.0);
    vec3 base = vec3(0.78, 0.80, 0.84);
    bool uncovered = false;
#ifdef NGI_BASE_COLOUR
    // The sRGB image filters in linear light; this shading works on display values (as the
    // grey above), so the sample is encoded back.
    vec4 linearColour;
    if (sampleChartColour(baseColour, inChartUv, linearColour)) base = linearToSrgb(linearColour.rgb);
    uncovered = CUT_OUT && chartUncovered(linearColour.a, gl_FragCoord.xy);
#endif
    if (pc.mode == NGI_MODE_LOD) {
        float l0 = floor(inEyeLod.w);
        base = mix(levelColour(l0), levelColour(l0 + 1.0), inEyeLod.w - l0);
    }
    vec3 colour = base * (0.18 + 0.82 * diffuse) + vec3(0.15) * specular;
    if (pc.mode == NGI_MODE_NORMALS) colour = normalize(inNormal) * 0.5 + 0.5;
#ifdef NGI_BASE_COLOUR
    if (pc.mode == NGI_MODE_BASE_COLOUR) colour = base;
#endif
    if (pc.mode == NGI_MODE_WIREFRAME) {
        vec3 d = fwidth(inBarycentric);
        vec3 a = smoothstep(vec3(0.0), d * pc.wireWidth, inBarycentric);
        float edge = 1.0 - min(min(a.x, a.y), a.z);
        colour = mix(colour, vec3(0.08, 0.10, 0.16), edge);
    }
    // Cut out where the alpha says so; last, as the derivatives above need the whole quad.
    if (uncovered) discard;
    outColor = vec4(colour, 1.0);
}
