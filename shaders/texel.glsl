// ngi: geometry-image texel packing (see ngi_shared.h) and octahedral normals.
// Octahedral mapping: Cigolle et al. 2014, "A Survey of Efficient Representations for
// Independent Unit Vectors", JCGT 3(2). Mirrored in C++ by engine/src/texel_packing.cpp.

vec2 octWrap(vec2 v) { return (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }

uint packNormal(vec3 n)
{
    float l1 = abs(n.x) + abs(n.y) + abs(n.z);
    if (!(l1 > 0.0)) return packUnorm2x16(vec2(0.5));  // degenerate: +z
    n /= l1;
    vec2 e = n.z >= 0.0 ? n.xy : octWrap(n.xy);
    return packUnorm2x16(e * 0.5 + 0.5);
}

vec3 unpackNormal(uint bits)
{
    vec2 e = unpackUnorm2x16(bits) * 2.0 - 1.0;
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = octWrap(n.xy);
    return normalize(n);
}

vec3 texelPosition(uvec4 t) { return uintBitsToFloat(t.xyz); }
vec3 texelNormal(uvec4 t) { return unpackNormal(t.w); }
uvec4 makeTexel(vec3 p, vec3 n) { return uvec4(floatBitsToUint(p), packNormal(n)); }

// The adaptive draw's compact texel (RGBA16UI; ngi/compact_texel.h is the definition): xyz the
// position as 16-bit unorm over [NGI_COMPACT_ORIGIN, NGI_COMPACT_ORIGIN + NGI_COMPACT_EXTENT]^3
// of normalized space, w the normal octahedral in 2 x 8 bits
// (code c stands for (c - 127) / 127).
vec3 compactTexelPosition(uvec4 t) { return vec3(t.xyz) * (NGI_COMPACT_EXTENT / 65535.0) + NGI_COMPACT_ORIGIN; }
vec3 compactTexelNormal(uvec4 t)
{
    vec2 e = (vec2(float(min(t.w & 0xFFu, 254u)), float(min(t.w >> 8, 254u))) - 127.0) / 127.0;
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = octWrap(n.xy);
    return normalize(n);
}

// A surface point of a level: a sample, or one geomorphed towards its target. The one
// definition of the geomorph for every way of surface.vert, whose shared-vertex draws must
// place every vertex exactly where the per-quad draw does.
struct SurfacePoint { vec3 position; vec3 normal; };

// Texel p moved by `morph` (0..1) towards its geomorph target m (read only when morph > 0).
SurfacePoint geomorphPoint(uvec4 p, uvec4 m, float morph)
{
    SurfacePoint s = SurfacePoint(texelPosition(p), texelNormal(p));
    if (morph > 0.0) {
        s.position = mix(s.position, texelPosition(m), morph);
        s.normal = normalize(mix(s.normal, texelNormal(m), morph));
    }
    return s;
}
