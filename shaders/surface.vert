#version 450
// Any-LoD geometry-image grid from gl_VertexIndex: no stored vertex or index buffers.
// Three ways to place the same triangles' vertices; each pipeline runs one (its
// specialization constant VERTEX_WAY, NGI_SPEC_VERTEX_WAY in ngi_shared.h).
// Per quad (NGI_WAY_PER_QUAD), either non-indexed: 6 * (N - 1)^2 vertices, vertex v is
// corner (v % 6) of quad v / 6; or indexed with the shared topology-only quad index buffer
// (4 vertex ids per quad, triangles (0, 1, 2), (0, 2, 3); see NGI_QUADS_PER_CHUNK), where
// the split along b-d is made by rotating the quad's corners by one, which turns those two
// triangles into (b, c, d), (b, d, a) (DrawPushConstants::gridTopology says which). The
// vertex's corner is fetched and geomorphed towards the next coarser level by `morph`
// (morph_targets.comp); the quad is split along the shorter 3D diagonal of its geomorphed
// corners, read as one quadratic in `morph` (quad_diagonals.comp) -- the same rule as the
// CPU definition in core/src/lod_grid.cpp, which ngi-eval exports.
// Per quad, bilinear (NGI_WAY_PER_QUAD_BILINEAR): for a grid size that is not a nested
// level size, corners are sampled bilinearly from the coarsest level with at least N
// samples per side (morph is 0 then) and the quad's four corners decide the split.
// Shared vertices (NGI_WAY_SHARED, nested sizes): vertex v is sample (v % N, v / N),
// fetched and geomorphed here by the per-quad way's own fetchPoint, indexed by the level's
// expanded index buffer, written at run time by grid_expansion.comp with the same diagonals
// in the per-quad indexed order: the same triangles, each sample run once per post-transform
// cache miss instead of 4 times per quad.
//
// THE PUBLIC VERTEX STAGE (installed with ngi::shaders; a host writes its own fragment
// shader, material, G-buffer or depth-only pipeline against it, see SurfacePipeline):
//   set 0 (NGI_DRAW_SET_LEVEL), vertex stage: binding 0 = the level's texels (usampler2D,
//     RGBA32UI, texel.glsl), 1 = its geomorph targets (usampler2D), 2 = its per-quad
//     diagonals (sampler2D, RGBA32F); bound by ngi per draw (GeometryImageSurface::drawSet).
//   set 1 (NGI_DRAW_SET_INSTANCES), vertex stage: binding 0 = readonly std430 buffer of
//     DrawInstance (ngi_shared.h), indexed by gl_InstanceIndex in batched draws; bound by ngi.
//   sets 2.. (NGI_DRAW_HOST_SET): the host's own (SurfacePipeline's hostSetLayouts).
//   push constants: DrawPushConstants (112 bytes, vertex + fragment stages). In a batched
//     draw (instanced = 1) viewProjection is the pass's world -> clip and eye.xyz the camera
//     in world space; in a single draw viewProjection is normalized -> clip and eye.xyz the
//     camera in normalized space.
//   outputs: location 0 = normal, 1 = position (normalized asset space), 2 = barycentric
//     (noperspective; (1, 1, 1) in shared-vertex draws, which have no triangle corners to
//     tell apart: ngi draws per quad when the fragment shader reads it, see
//     Renderer::recordGridExpansion), 3 = flat vec4 (xyz: the camera in normalized space,
//     w: continuous LoD), 4 = world-space position, 5 = world-space normal (unit). World space is the
//     instance's (DrawInstance::worldFromNormalized) in batched draws; a single draw
//     (Renderer::recordDraw) has no world matrix on the GPU and writes the normalized-space
//     position and normal there. 6 = the grid vertex's uv on the chart's square (vec2 in
//     [0, 1]; it does not move with the LoD), where a chart's attribute images are sampled.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"

layout(constant_id = NGI_SPEC_VERTEX_WAY) const uint VERTEX_WAY = NGI_WAY_PER_QUAD;
layout(constant_id = NGI_SPEC_INSTANCED) const bool INSTANCED = false;

layout(set = 0, binding = 0) uniform usampler2D level;         // this level's texels
layout(set = 0, binding = 1) uniform usampler2D morphTargets;  // its geomorph targets
layout(set = 0, binding = 2) uniform sampler2D quadDiagonals;  // per quad (C, B, A) of f(morph)
layout(std430, set = 1, binding = 0) readonly buffer Instances { DrawInstance instances[]; };
layout(push_constant) uniform Push { DrawPushConstants pc; };

layout(location = 0) out vec3 outNormal;
layout(location = 1) out vec3 outPosition;
layout(location = 2) noperspective out vec3 outBarycentric;
layout(location = 3) flat out vec4 outEyeLod;
layout(location = 4) out vec3 outWorldPosition;
layout(location = 5) out vec3 outWorldNormal;
layout(location = 6) out vec2 outChartUv;  // the grid vertex on the chart's square, in [0, 1]

float morph;  // this draw's (or instance's) geomorph factor

SurfacePoint fetchPoint(ivec2 t)
{
    uvec4 p = texelFetch(level, t, 0);
    return geomorphPoint(p, morph > 0.0 ? texelFetch(morphTargets, t, 0) : p, morph);
}

// Grid vertex (i, j) of an N-grid sits at uv = (i, j) / (N - 1).
SurfacePoint gridPoint(ivec2 ij)
{
    int last = int(pc.levelSize) - 1;
    // Exact rational position in level texels: ij * last / (N - 1).
    ivec2 num = ij * last;
    int den = int(pc.gridSize) - 1;
    ivec2 t0 = num / den;
    vec2 f = vec2(num - t0 * den) / float(den);
    ivec2 t1 = min(t0 + 1, ivec2(last));
    SurfacePoint a = fetchPoint(t0), b = fetchPoint(ivec2(t1.x, t0.y));
    SurfacePoint c = fetchPoint(ivec2(t0.x, t1.y)), d = fetchPoint(t1);
    SurfacePoint s;
    s.position = mix(mix(a.position, b.position, f.x), mix(c.position, d.position, f.x), f.y);
    s.normal = normalize(mix(mix(a.normal, b.normal, f.x), mix(c.normal, d.normal, f.x), f.y));
    return s;
}

// The outputs of every way of drawing (one place, so they cannot drift apart).
void emit(SurfacePoint s, ivec2 gridVertex, mat4 clipFromNormalized, mat4 worldFromNormalized)
{
    outChartUv = vec2(gridVertex) / float(int(pc.gridSize) - 1);
    outNormal = s.normal;
    outPosition = s.position;
    gl_Position = clipFromNormalized * vec4(s.position, 1.0);
    if (INSTANCED) {
        // Normals by the cofactor matrix (inverse transpose up to det, any invertible world).
        mat3 m = mat3(worldFromNormalized);
        mat3 cofactor = mat3(cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1]));
        outWorldPosition = (worldFromNormalized * vec4(s.position, 1.0)).xyz;
        outWorldNormal = normalize(cofactor * s.normal) * sign(determinant(m));
    } else {
        // World space is normalized space: the batched expressions with the identity, exactly.
        outWorldPosition = s.position;
        outWorldNormal = normalize(s.normal);
    }
}

// A vertex of the per-quad ways: corner (of quad gl_VertexIndex / 4 or / 6) of the split.
void perQuadVertex(mat4 clipFromNormalized, mat4 worldFromNormalized)
{
    // Corners counter-clockwise in uv: a (0,0), b (1,0), c (1,1), d (0,1).
    const ivec2 offsets[4] = ivec2[4](ivec2(0, 0), ivec2(1, 0), ivec2(1, 1), ivec2(0, 1));
    // Non-indexed: triangles (a, b, c), (a, c, d) along diagonal ac, else (a, b, d), (b, c, d).
    const int alongAC[6] = int[6](0, 1, 2, 0, 2, 3);
    const int alongBD[6] = int[6](0, 1, 3, 1, 2, 3);
    int quadsPerRow = int(pc.gridSize) - 1;
    int quad, corner, vertexInTriangle;
    SurfacePoint s;
    ivec2 vertex;
    bool quadIndexed = pc.gridTopology == NGI_GRID_QUAD_INDEXED;
    if (quadIndexed) {
        quad = gl_VertexIndex >> 2;
        corner = gl_VertexIndex & 3;
        vertexInTriangle = corner == 3 ? 1 : corner;  // distinct within (0, 1, 2) and (0, 2, 3)
    } else {
        quad = gl_VertexIndex / 6;
        corner = gl_VertexIndex - quad * 6;
        vertexInTriangle = corner % 3;
    }
    ivec2 q = ivec2(quad % quadsPerRow, quad / quadsPerRow);
    if (VERTEX_WAY == NGI_WAY_PER_QUAD) {
        vec3 f = texelFetch(quadDiagonals, q, 0).xyz;
        bool splitAC = (f.z * morph + f.y) * morph + f.x <= 0.0;
        int k = quadIndexed ? (splitAC ? corner : (corner + 1) & 3) : (splitAC ? alongAC[corner] : alongBD[corner]);
        s = fetchPoint(q + offsets[k]);
        vertex = q + offsets[k];
    } else {
        SurfacePoint a = gridPoint(q), b = gridPoint(q + offsets[1]);
        SurfacePoint c = gridPoint(q + offsets[2]), d = gridPoint(q + offsets[3]);
        vec3 ac = c.position - a.position, bd = d.position - b.position;
        bool splitAC = dot(ac, ac) - dot(bd, bd) <= 0.0;
        int k = quadIndexed ? (splitAC ? corner : (corner + 1) & 3) : (splitAC ? alongAC[corner] : alongBD[corner]);
        s = k == 0 ? a : k == 1 ? b : k == 2 ? c : d;
        vertex = q + offsets[k];
    }
    outBarycentric = vec3(vertexInTriangle == 0, vertexInTriangle == 1, vertexInTriangle == 2);
    emit(s, vertex, clipFromNormalized, worldFromNormalized);
}

void main()
{
    mat4 clipFromNormalized = pc.viewProjection;
    mat4 worldFromNormalized = mat4(1.0);
    morph = pc.morph;
    outEyeLod = vec4(pc.eye.xyz, pc.lod);
    if (INSTANCED) {
        clipFromNormalized = instances[gl_InstanceIndex].clipFromNormalized;
        worldFromNormalized = instances[gl_InstanceIndex].worldFromNormalized;
        morph = instances[gl_InstanceIndex].morph;
        outEyeLod = vec4(instances[gl_InstanceIndex].eye.xyz, instances[gl_InstanceIndex].lod);
    }
    if (VERTEX_WAY == NGI_WAY_SHARED) {
        // Sample (v % N, v / N), geomorphed as the per-quad way geomorphs it.
        int n = int(pc.gridSize);
        ivec2 vertex = ivec2(gl_VertexIndex % n, gl_VertexIndex / n);
        SurfacePoint s = fetchPoint(vertex);
        outBarycentric = vec3(1.0);
        emit(s, vertex, clipFromNormalized, worldFromNormalized);
    } else {
        perQuadVertex(clipFromNormalized, worldFromNormalized);
    }
}
