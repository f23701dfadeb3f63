// A chart's base colour image (ngi/engine/color_images.h; both draws bind it at set 0, binding
// NGI_DRAW_BINDING_BASE_COLOUR = 3) sampled at the chart uv (vertex output 6). Installed with ngi::shaders for host
// materials. Texel (x, y) of an S-texel image is the surface at grid uv (x, y) / (S - 1).

// The colour at `chartUv`, linear (the image is sRGB), with the image's alpha: the coverage the
// bake wrote (1 where the input's material is opaque, 0 or 1 by a masked material's cutoff, a
// blended material's alpha); false, and alpha 1, for the 1 x 1 stand-in of a chart without
// colour (a real colour image has at least 2 x 2 texels).
bool sampleChartColour(sampler2D image, vec2 chartUv, out vec4 linearColour)
{
    vec2 size = vec2(textureSize(image, 0));
    linearColour = vec4(0.0, 0.0, 0.0, 1.0);
    if (size.x <= 1.0) return false;
    linearColour = texture(image, (chartUv * (size - 1.0) + 0.5) / size);
    return true;
}

// The same without the alpha.
bool sampleChartColour(sampler2D image, vec2 chartUv, out vec3 linearColour)
{
    vec4 withAlpha;
    bool coloured = sampleChartColour(image, chartUv, withAlpha);
    linearColour = withAlpha.rgb;
    return coloured;
}

// Whether the fragment at window position `fragCoord` is left uncovered by `alpha`: a hashed
// alpha test (Wyman and McGuire 2017, "Hashed alpha testing") against a threshold in [0, 1)
// from interleaved gradient noise (Jimenez 2014), so that alpha a covers a fraction a of the
// pixels with no sorting. Alpha 1 covers every pixel and alpha 0 none; a masked material's 0/1
// alpha is cut exactly, but for a band about one texel wide where the filter blends the two.
// A fragment shader discards where this is true.
bool chartUncovered(float alpha, vec2 fragCoord)
{
    float threshold = fract(52.9829189 * fract(dot(floor(fragCoord), vec2(0.06711056, 0.00583715))));
    return alpha <= threshold;
}

// Linear light to its sRGB encoding (IEC 61966-2-1), for shading that works on display values.
vec3 linearToSrgb(vec3 l)
{
    return mix(l * 12.92, 1.055 * pow(l, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), l));
}
