#version 450
// The host's props: axis-aligned boxes, 36 vertices from gl_VertexIndex, one draw per box.
layout(push_constant) uniform Push { mat4 viewProjection; vec4 centre; vec4 halfExtent; vec4 colour; } pc;
layout(location = 0) out vec3 outColour;
layout(location = 1) out vec3 outWorldPosition;
layout(location = 2) flat out vec3 outNormal;
void main()
{
    // Face f: axis f / 2, sign +/-; two triangles over the face's corners in (u, v).
    const vec2 quad[6] = vec2[6](vec2(-1, -1), vec2(1, -1), vec2(1, 1), vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    int face = gl_VertexIndex / 6;
    int axis = face / 2;
    float s = (face & 1) == 0 ? 1.0 : -1.0;
    vec2 uv = quad[gl_VertexIndex % 6];
    vec3 p = axis == 0 ? vec3(s, uv.x, uv.y) : axis == 1 ? vec3(uv.y, s, uv.x) : vec3(uv.x, uv.y, s);
    vec3 n = vec3(0.0);
    n[axis] = s;
    outNormal = n;
    outColour = pc.colour.rgb;
    outWorldPosition = pc.centre.xyz + p * pc.halfExtent.xyz;
    gl_Position = pc.viewProjection * vec4(outWorldPosition, 1.0);
}
