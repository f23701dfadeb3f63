#version 450
// Texels of one mip level as colours (nearest: every sample is visible as a square).
layout(set = 0, binding = 0) uniform sampler2D picture;
layout(location = 0) in vec2 inUv;
layout(location = 0) out vec4 outColor;

void main() { outColor = vec4(texture(picture, inUv).rgb, 1.0); }
