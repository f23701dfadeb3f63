#version 450
// The adaptive LoD draw (ngi/adaptive_lod.h is the CPU definition it mirrors): one instance
// per selected tile (AdaptiveTile, ngi_shared.h), NGI_TILE_QUADS^2 quads of the tile's level,
// 6 non-indexed vertices per quad, split by alternating diagonals (a-c where the quad's level
// coordinates sum to an even number). Interior vertices are geomorphed by the tile's morph;
// border vertices by their shared state, and one whose state is one level coarser is drawn
// from the coarser level, its odd ones dropped onto their even neighbour (the coarser edge).
// A sample's geomorph target is the next coarser level's surface at its uv (alternating
// diagonals), computed here from that level's texels: no per-quad data and no target images,
// and the levels need not be nested (the engine's are fitted, ngi/fitted_levels.h).
// Outputs as surface.vert's (location 3: the camera in normalized space and the tile's LoD;
// 4, 5: world space by the instance's worldFromNormalized), so host fragment shaders written
// against the public vertex stage shade adaptive draws too; plus location 6, the vertex's uv on
// the chart's square (its sample / (level size - 1); a geomorph keeps it, since each target
// is the midpoint of two samples around it), where the chart's base colour image is sampled
// (set NGI_ADAPTIVE_SET_LEVELS, binding NGI_DRAW_BINDING_BASE_COLOUR, fragment stage, as in
// the uniform draw). Host fragment shaders declare it.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"

// Compact texels (compactTexelPosition, compactTexelNormal in texel.glsl).
layout(set = NGI_ADAPTIVE_SET_LEVELS, binding = 0) uniform usampler2D level;    // the tile's level
layout(set = NGI_ADAPTIVE_SET_LEVELS, binding = 1) uniform usampler2D coarser;  // level + 1 (or itself)
layout(set = NGI_ADAPTIVE_SET_LEVELS, binding = 2) uniform usampler2D coarser2; // level + 2 (or the coarsest)
layout(std430, set = NGI_ADAPTIVE_SET_TILES, binding = 0) readonly buffer Tiles { AdaptiveTile tiles[]; };
layout(std430, set = NGI_ADAPTIVE_SET_TILES, binding = 1) readonly buffer Instances { AdaptiveInstance instances[]; };
layout(push_constant) uniform Push { DrawPushConstants pc; };

layout(location = 0) out vec3 outNormal;
layout(location = 1) out vec3 outPosition;
layout(location = 2) noperspective out vec3 outBarycentric;
layout(location = 3) flat out vec4 outEyeLod;
layout(location = 4) out vec3 outWorldPosition;
layout(location = 5) out vec3 outWorldNormal;
layout(location = 6) out vec2 outChartUv;  // the vertex's sample on the chart's square, in [0, 1]

const int P = NGI_TILE_QUADS;

// Texel s of the tile's level (which 0), the next coarser (1) or the one after (2).
uvec4 fetchTexel(int which, ivec2 s)
{
    return which == 0 ? texelFetch(level, s, 0) : which == 1 ? texelFetch(coarser, s, 0) : texelFetch(coarser2, s, 0);
}
int levelSize(int which)
{
    return which == 0 ? textureSize(level, 0).x : which == 1 ? textureSize(coarser, 0).x : textureSize(coarser2, 0).x;
}

vec3 unitOrUp(vec3 n) { return dot(n, n) > 0.0 ? normalize(n) : vec3(0.0, 0.0, 1.0); }

// The surface of level `which` (alternating diagonals) at the uv of sample s of the next finer
// level: the geomorph target of that sample (ngi::coarserSurfaceAt, fitted_levels.h).
SurfacePoint coarserSurfaceAt(int which, ivec2 s)
{
    ivec2 q = min(s >> 1, ivec2(levelSize(which) - 2));
    vec2 f = vec2(s - 2 * q) * 0.5;
    ivec2 a = q, b = q + ivec2(1, 0), c = q + ivec2(1, 1), d = q + ivec2(0, 1);
    ivec2 i0, i1, i2;
    vec3 w;
    if (((q.x + q.y) & 1) == 0) {
        if (f.x >= f.y) { i0 = a; i1 = b; i2 = c; w = vec3(1.0 - f.x, f.x - f.y, f.y); }
        else { i0 = a; i1 = c; i2 = d; w = vec3(1.0 - f.y, f.x, f.y - f.x); }
    } else {
        if (f.x + f.y <= 1.0) { i0 = a; i1 = b; i2 = d; w = vec3(1.0 - f.x - f.y, f.x, f.y); }
        else { i0 = b; i1 = c; i2 = d; w = vec3(1.0 - f.y, f.x + f.y - 1.0, 1.0 - f.x); }
    }
    uvec4 t0 = fetchTexel(which, i0), t1 = fetchTexel(which, i1), t2 = fetchTexel(which, i2);
    vec3 p = w.x * compactTexelPosition(t0) + w.y * compactTexelPosition(t1) + w.z * compactTexelPosition(t2);
    vec3 n = w.x * compactTexelNormal(t0) + w.y * compactTexelNormal(t1) + w.z * compactTexelNormal(t2);
    return SurfacePoint(p, unitOrUp(n));
}

// Sample s of level `which` moved by m towards its geomorph target, the next coarser level's
// surface at its uv (none past the coarsest level).
SurfacePoint morphedSample(int which, ivec2 s, float m)
{
    uvec4 t = fetchTexel(which, s);
    SurfacePoint p = SurfacePoint(compactTexelPosition(t), compactTexelNormal(t));
    if (m > 0.0 && levelSize(which + 1) < levelSize(which)) {
        SurfacePoint target = coarserSurfaceAt(which + 1, s);
        p.position = mix(p.position, target.position, m);
        p.normal = unitOrUp(mix(p.normal, target.normal, m));
    }
    return p;
}

// Border vertex v's 16-bit state (see NGI_TILE_COARSER_BIT).
uint borderState(AdaptiveTile tile, ivec2 v)
{
    int b = v.y == 0 ? v.x : v.x == P ? P + v.y : v.y == P ? 3 * P - v.x : 4 * P - v.y;
    return (tile.border[b >> 1] >> (16 * (b & 1))) & 0xFFFFu;
}

void main()
{
    AdaptiveTile tile = tiles[gl_InstanceIndex];
    const ivec2 offsets[4] = ivec2[4](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 1));
    const int alongAC[6] = int[6](0, 1, 2, 0, 2, 3);
    const int alongBD[6] = int[6](0, 1, 3, 1, 2, 3);
    int quad = gl_VertexIndex / 6, corner = gl_VertexIndex - quad * 6;
    ivec2 q = ivec2(quad % P, quad / P);
    ivec2 v = q + offsets[((q.x + q.y) & 1) == 0 ? alongAC[corner] : alongBD[corner]];

    bool fromCoarser = false;
    float m = tile.morph;
    if (v.x == 0 || v.y == 0 || v.x == P || v.y == P) {
        uint state = borderState(tile, v);
        if ((state & NGI_TILE_COARSER_BIT) != 0u && ((v.x | v.y) & 1) != 0) {
            v -= (v.y == 0 || v.y == P) ? ivec2(1, 0) : ivec2(0, 1);
            state = borderState(tile, v);
        }
        fromCoarser = (state & NGI_TILE_COARSER_BIT) != 0u;
        m = float(state & 0x7FFFu) / NGI_TILE_MORPH_SCALE;
    }
    uint tileLevel = tile.levelInstance & 0xFFu;
    AdaptiveInstance instance = instances[tile.levelInstance >> 8];
    ivec2 s = ivec2(int(tile.x), int(tile.y)) + v;
    SurfacePoint p = fromCoarser ? morphedSample(1, s >> 1, m) : morphedSample(0, s, m);

    int vertexInTriangle = corner % 3;
    outBarycentric = vec3(vertexInTriangle == 0, vertexInTriangle == 1, vertexInTriangle == 2);
    outNormal = p.normal;
    outPosition = p.position;
    outChartUv = vec2(s) / float(textureSize(level, 0).x - 1);
    outEyeLod = vec4(instance.eye.xyz, float(tileLevel) + tile.morph);
    gl_Position = instance.clipFromNormalized * vec4(p.position, 1.0);
    // Normals by the cofactor matrix (inverse transpose up to det, any invertible world).
    mat3 w = mat3(instance.worldFromNormalized);
    mat3 cofactor = mat3(cross(w[1], w[2]), cross(w[2], w[0]), cross(w[0], w[1]));
    outWorldPosition = (instance.worldFromNormalized * vec4(p.position, 1.0)).xyz;
    outWorldNormal = unitOrUp(cofactor * p.normal) * sign(determinant(w));
}
