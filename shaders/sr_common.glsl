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

// Exact bilinear upsampling by pc.factor of channel group g of a pc.inWidth x pc.inHeight
// tensor at fine sample (X, Y) (align_corners = true; PyTorch's fp32 source coordinate
// X * (1 / f)). Shared by sr_bilinear_skip.comp and the conv's fused skip. The caller adds it
// to the fine value: fine + bilinear(...), in that order.
vec4 bilinearUpsample(samplerBuffer coarse, int g, int X, int Y)
{
    const int f = int(pc.factor), cw = int(pc.inWidth), ch = int(pc.inHeight);
    const float step = 1.0 / float(f);
    const int x0 = X / f, x1 = min(x0 + 1, cw - 1), y0 = Y / f, y1 = min(y0 + 1, ch - 1);
    const float tx = float(X) * step - float(x0), ty = float(Y) * step - float(y0);
    const vec4 top = texelFetch(coarse, tensorIndex(g, x0, y0, cw, ch)) * (1.0 - tx) +
                     texelFetch(coarse, tensorIndex(g, x1, y0, cw, ch)) * tx;
    const vec4 bottom = texelFetch(coarse, tensorIndex(g, x0, y1, cw, ch)) * (1.0 - tx) +
                        texelFetch(coarse, tensorIndex(g, x1, y1, cw, ch)) * tx;
    return top * (1.0 - ty) + bottom * ty;
}
