#version 450
// FMA-throughput probe (ngi-bench-sr --probe): the driver's peak fp32 multiply-add rate for
// a compute shader, the ceiling the super-resolution convolutions are measured against.
// Each invocation runs pc.iterations rounds of 8 independent vec4 multiply-adds (enough
// independent chains to hide the FMA latency of a SIMD CPU: 8 x 4 lanes x 2 FLOP per round)
// and stores their sum, so that nothing is optimized away. FLOP = 64 x iterations x invocations.
layout(local_size_x = 64) in;
layout(push_constant) uniform Push { uint iterations; float seed; } pc;
layout(set = 0, binding = 0, std430) writeonly buffer Out { vec4 sums[]; };

void main()
{
    const float s = pc.seed + float(gl_GlobalInvocationID.x) * 1e-7;
    vec4 a0 = vec4(s), a1 = vec4(s + 1.0), a2 = vec4(s + 2.0), a3 = vec4(s + 3.0);
    vec4 a4 = vec4(s + 4.0), a5 = vec4(s + 5.0), a6 = vec4(s + 6.0), a7 = vec4(s + 7.0);
    const vec4 m = vec4(0.999999, 0.999998, 0.999997, 0.999996), c = vec4(1e-6);
    for (uint i = 0u; i < pc.iterations; ++i) {
        a0 = fma(a0, m, c); a1 = fma(a1, m, c); a2 = fma(a2, m, c); a3 = fma(a3, m, c);
        a4 = fma(a4, m, c); a5 = fma(a5, m, c); a6 = fma(a6, m, c); a7 = fma(a7, m, c);
    }
    sums[gl_GlobalInvocationID.x] = a0 + a1 + a2 + a3 + a4 + a5 + a6 + a7;
}
