// ngi-host-demo: the host's sun light and shadow map, shared by its ground, props and its
// material for ngi's surfaces. HOST_LIGHT_SET: the set number in the including pipeline's layout.
layout(set = HOST_LIGHT_SET, binding = 0) uniform sampler2D shadowMap;  // depth, nearest, compared here
layout(set = HOST_LIGHT_SET, binding = 1) uniform Light {
    mat4 lightViewProjection;  // world -> the shadow map's clip space (orthographic)
    vec4 toLight;              // xyz: unit direction towards the sun
    vec4 sun;                  // rgb: sun colour
    vec4 ambient;              // rgb: sky colour; w: depth bias in shadow-map depth units
    vec4 shadowTexel;          // xy: 1 / shadow map size
} light;

// Fraction of the sun that reaches `worldPosition`: 3 x 3 percentage-closer filtering.
float sunVisibility(vec3 worldPosition)
{
    vec4 c = light.lightViewProjection * vec4(worldPosition, 1.0);
    vec3 ndc = c.xyz / c.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) return 1.0;
    float lit = 0.0;
    for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x)
            lit += ndc.z - light.ambient.w <= texture(shadowMap, uv + vec2(x, y) * light.shadowTexel.xy).r ? 1.0 : 0.0;
    return lit / 9.0;
}

vec3 shadeLambert(vec3 albedo, vec3 worldPosition, vec3 normal)
{
    float diffuse = max(dot(normal, light.toLight.xyz), 0.0);
    float visible = diffuse > 0.0 ? sunVisibility(worldPosition) : 0.0;
    return albedo * (light.ambient.rgb + light.sun.rgb * diffuse * visible);
}
