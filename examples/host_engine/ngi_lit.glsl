// The host's material for ngi's surfaces (ngi_lit.frag, for DrawBatch and the adaptive draw
// alike: both bind the chart's base colour at set 0, binding NGI_DRAW_BINDING_BASE_COLOUR),
// written against ngi's public vertex stage (shaders/surface.vert, installed with ngi::shaders): world-space position
// and normal from a batched draw, the chart uv, the host's sun and shadow map in set 2 (the
// first host set). Included after #version, the include extension and lighting.glsl.

layout(push_constant) uniform Push { DrawPushConstants pc; };  // batched: pc.eye is the camera in world space
// Every output of the vertex stage has an input here (the validation layer warns otherwise).
layout(location = 0) in vec3 inNormal;
layout(location = 1) in vec3 inPosition;
layout(location = 2) noperspective in vec3 inBarycentric;
layout(location = 3) flat in vec4 inEyeLod;
layout(location = 4) in vec3 inWorldPosition;
layout(location = 5) in vec3 inWorldNormal;
layout(location = 6) in vec2 inChartUv;  // the vertex's uv on its chart's square
// Both draws bind each chart's base colour here (an sRGB image: samples are linear; a 1 x 1
// image stands for a chart without colour).
layout(set = 0, binding = NGI_DRAW_BINDING_BASE_COLOUR) uniform sampler2D baseColour;
#include "chart_colour.glsl"
layout(location = 0) out vec4 outColour;

void main()
{
    vec3 n = normalize(inWorldNormal);
    vec3 toEye = normalize(pc.eye.xyz - inWorldPosition);
    if (dot(n, toEye) < 0.0) n = -n;  // cut surfaces are two-sided
    vec3 albedo = vec3(0.86, 0.84, 0.80);
    // This demo lights display values (as its constant albedo): the linear sample, encoded.
    vec4 linearColour;
    if (sampleChartColour(baseColour, inChartUv, linearColour)) albedo = linearToSrgb(linearColour.rgb);
    if (chartUncovered(linearColour.a, gl_FragCoord.xy)) discard;  // the colour's alpha is coverage
    vec3 colour = shadeLambert(albedo, inWorldPosition, n);
    vec3 h = normalize(toEye + light.toLight.xyz);
    colour += light.sun.rgb * 0.12 * pow(max(dot(n, h), 0.0), 40.0) * sunVisibility(inWorldPosition);
    outColour = vec4(colour, 1.0);
}
