// ngi: shared helpers of the super-resolution ops (shaders/sr_*.comp). Tensor layout and
// bindings: ngi_shared.h ("C4 planes", NGI_SR_BINDING_*). Includers enable
// GL_EXT_control_flow_attributes: the small fixed loops are unrolled, because lavapipe keeps
// an array indexed by a loop counter (r[k] below) in per-lane scratch memory.

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

// Catmull-Rom weights of the coarse samples x0 - 1 .. x0 + 2 at fraction t (CubicSkip,
// ngi/network_weights.h; CPU reference ngi::nn::catmullRomWeights, same expressions).
vec4 catmullRomWeights(float t)
{
    const float t2 = t * t, t3 = t2 * t;
    return vec4(-0.5 * t3 + t2 - 0.5 * t, 1.5 * t3 - 2.5 * t2 + 1.0, -1.5 * t3 + 2.0 * t2 + 0.5 * t, 0.5 * t3 - 0.5 * t2);
}

// Coarse sample (x, y) of channel group g, extrapolated linearly beyond the border in x.
vec4 cubicSample(samplerBuffer coarse, int g, int x, int y, int cw, int ch)
{
    if (x < 0) return 2.0 * texelFetch(coarse, tensorIndex(g, 0, y, cw, ch)) - texelFetch(coarse, tensorIndex(g, 1, y, cw, ch));
    if (x >= cw)
        return 2.0 * texelFetch(coarse, tensorIndex(g, cw - 1, y, cw, ch)) - texelFetch(coarse, tensorIndex(g, cw - 2, y, cw, ch));
    return texelFetch(coarse, tensorIndex(g, x, y, cw, ch));
}

vec4 cubicRow(samplerBuffer coarse, int g, int x0, int y, vec4 wx, int cw, int ch)
{
    vec4 r = vec4(0.0);
    [[unroll]] for (int kx = 0; kx < 4; ++kx) r += wx[kx] * cubicSample(coarse, g, x0 - 1 + kx, y, cw, ch);
    return r;
}

// Catmull-Rom upsampling by pc.factor of channel group g at fine sample (X, Y), linear
// extrapolation beyond the border; rows first, as ngi::nn::cubicSkip.
vec4 cubicUpsample(samplerBuffer coarse, int g, int X, int Y)
{
    const int f = int(pc.factor), cw = int(pc.inWidth), ch = int(pc.inHeight);
    const int x0 = X / f, y0 = Y / f;
    const vec4 wx = catmullRomWeights(float(X % f) / float(f)), wy = catmullRomWeights(float(Y % f) / float(f));
    vec4 sum = vec4(0.0);
    [[unroll]] for (int ky = 0; ky < 4; ++ky) {
        const int y = y0 - 1 + ky;
        vec4 r;
        if (y < 0) r = 2.0 * cubicRow(coarse, g, x0, 0, wx, cw, ch) - cubicRow(coarse, g, x0, 1, wx, cw, ch);
        else if (y >= ch) r = 2.0 * cubicRow(coarse, g, x0, ch - 1, wx, cw, ch) - cubicRow(coarse, g, x0, ch - 2, wx, cw, ch);
        else r = cubicRow(coarse, g, x0, y, wx, cw, ch);
        sum += wy[ky] * r;
    }
    return sum;
}

// HermiteSkip (ngi/network_weights.h; CPU reference ngi::nn::hermiteSkip). Positions and
// normals are channel group 0 (xyz) of pc.inWidth x pc.inHeight tensors.
vec3 hermiteFetch(samplerBuffer t, int x, int y) { return texelFetch(t, tensorIndex(0, x, y, int(pc.inWidth), int(pc.inHeight))).xyz; }

vec3 projectOnTangentPlane(vec3 m, vec3 n) { return m - n * dot(n, m); }

vec3 hermiteCurve(vec3 p0, vec3 m0, vec3 p1, vec3 m1, float t)
{
    const float t2 = t * t, t3 = t2 * t;
    return (2.0 * t3 - 3.0 * t2 + 1.0) * p0 + (t3 - 2.0 * t2 + t) * m0 + (-2.0 * t3 + 3.0 * t2) * p1 + (t3 - t2) * m1;
}

// Catmull-Rom's tangent at index i of a line of n samples a (i - 1), b (i), c (i + 1):
// one-sided at the ends (its linear extrapolation).
vec3 lineTangent(int i, int n, vec3 a, vec3 b, vec3 c) { return i == 0 ? c - b : i == n - 1 ? b - a : 0.5 * (c - a); }

// Row pass at coarse row y: R(y, X).
vec3 hermiteRow(samplerBuffer coarse, samplerBuffer normals, int y, int x0, int x1, float t)
{
    const int cw = int(pc.inWidth);
    const vec3 a = hermiteFetch(coarse, max(x0 - 1, 0), y), p0 = hermiteFetch(coarse, x0, y);
    const vec3 p1 = hermiteFetch(coarse, x1, y), b = hermiteFetch(coarse, min(x1 + 1, cw - 1), y);
    const vec3 m0 = projectOnTangentPlane(lineTangent(x0, cw, a, p0, p1), hermiteFetch(normals, x0, y));
    const vec3 m1 = projectOnTangentPlane(lineTangent(x1, cw, p0, p1, b), hermiteFetch(normals, x1, y));
    return hermiteCurve(p0, m0, p1, m1, t);
}

// The row normal N(y, X): Catmull-Rom of the normals (C1 like the row), renormalized.
vec3 hermiteRowNormal(samplerBuffer normals, int y, int x0, vec4 wx)
{
    const vec3 v = cubicRow(normals, 0, x0, y, wx, int(pc.inWidth), int(pc.inHeight)).xyz;
    const float len = length(v);
    return len > 0.0 ? v / len : hermiteFetch(normals, x0, y);
}

// The column of the normal-projected Hermite upsampling by pc.factor at fine column X between
// coarse rows y0 and y1 = y0 + 1 (clamped): rows first, then the column through the four
// rows y0 - 1 .. y0 + 2 (clamped; the clamped ones are unused), whose tangents at rows y0 and
// y1 are projected with those rows' normals. The same for the f fine rows of that coarse row.
struct HermiteColumn {
    vec3 p0, m0, p1, m1;
};

HermiteColumn hermiteColumn(samplerBuffer coarse, samplerBuffer normals, int X, int y0)
{
    const int f = int(pc.factor), cw = int(pc.inWidth), ch = int(pc.inHeight);
    const int x0 = X / f, x1 = min(x0 + 1, cw - 1), y1 = min(y0 + 1, ch - 1);
    const float tx = float(X % f) / float(f);
    vec3 r[4];
    [[unroll]] for (int k = 0; k < 4; ++k) r[k] = hermiteRow(coarse, normals, clamp(y0 - 1 + k, 0, ch - 1), x0, x1, tx);
    const vec4 wx = catmullRomWeights(tx);
    HermiteColumn c;
    c.p0 = r[1];
    c.p1 = r[2];
    c.m0 = projectOnTangentPlane(lineTangent(y0, ch, r[0], r[1], r[2]), hermiteRowNormal(normals, y0, x0, wx));
    c.m1 = projectOnTangentPlane(lineTangent(y1, ch, r[1], r[2], r[3]), hermiteRowNormal(normals, y1, x0, wx));
    return c;
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
