#version 450
// The geometry image shown flat: one textured rectangle, corners in NDC from push constants.
layout(push_constant) uniform Push { vec4 rect; } pc;  // x0, y0, x1, y1 (NDC)
layout(location = 0) out vec2 outUv;

void main()
{
    const vec2 corners[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1));
    vec2 c = corners[gl_VertexIndex];
    outUv = c;
    gl_Position = vec4(mix(pc.rect.xy, pc.rect.zw, c), 0.5, 1.0);
}
