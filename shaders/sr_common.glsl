// ngi: shared helpers of the super-resolution ops (shaders/sr_*.comp). Tensor layout and
// bindings: ngi_shared.h ("C4 planes", NGI_SR_BINDING_*).

layout(push_constant) uniform Push { SrPushConstants pc; };

// Texel index of channel group g at (x, y) of a width x height tensor.
int tensorIndex(int g, int x, int y, int width, int height) { return (g * height + y) * width + x; }

float activate(float v, uint activation, float slope)
{
    if (activation == NGI_SR_ACT_RELU) return max(v, 0.0);
    if (activation == NGI_SR_ACT_LEAKY) return v < 0.0 ? slope * v : v;
    return v;
}

vec4 activate(vec4 v, uint activation, float slope)
{
    return vec4(activate(v.x, activation, slope), activate(v.y, activation, slope), activate(v.z, activation, slope),
                activate(v.w, activation, slope));
}
