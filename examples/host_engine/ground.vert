#version 450
// The host's own geometry: a ground quad (two triangles from gl_VertexIndex) at y = 0.
layout(push_constant) uniform Push { mat4 viewProjection; vec4 colour; float halfSize; } pc;
layout(location = 0) out vec3 outColour;
layout(location = 1) out vec3 outWorldPosition;
void main()
{
    const vec2 corners[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    vec2 c = corners[gl_VertexIndex] * pc.halfSize;
    outColour = pc.colour.rgb;
    outWorldPosition = vec3(c.x, 0.0, c.y);
    gl_Position = pc.viewProjection * vec4(outWorldPosition, 1.0);
}
