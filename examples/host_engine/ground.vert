#version 450
// The host's own geometry: a flat-coloured ground quad (two triangles from gl_VertexIndex).
layout(push_constant) uniform Push { mat4 viewProjection; vec4 colour; float halfSize; } pc;
layout(location = 0) out vec3 outColour;
void main()
{
    const vec2 corners[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    vec2 c = corners[gl_VertexIndex] * pc.halfSize;
    outColour = pc.colour.rgb;
    gl_Position = pc.viewProjection * vec4(c.x, 0.0, c.y, 1.0);
}
