// The adaptive LoD's selection on the GPU: the bindings of every select pass and the per-tile
// rules of core's selectTiles (core/src/adaptive_lod.cpp, the CPU definition), written as
// functions of one tile so that every pass evaluates them the same way.
//
// selectTiles refines top-down by error, then splits tiles until neighbours differ by at most
// one level. Here that is one bitset per job, filled level by level: first `byError` (the tile
// is visited top-down and its projected error exceeds the budget, select_refine.comp), then, in
// the same words, `refined` (byError, or a child refined, or a tile one level finer sharing a
// vertex with it, in its chart or across a seam, refined: select_close.comp). A tile is drawn when its parent
// is refined and it is not. The refined set is the smallest that holds the top-down one and is
// closed under "a finer neighbour refined", which is exactly the CPU's balanced selection.
// Requires ngi_shared.h and texel.glsl.

layout(std430, set = 0, binding = NGI_SELECT_BINDING_TILES) readonly buffer Tiles { SelectionTile tiles[]; };
layout(std430, set = 0, binding = NGI_SELECT_BINDING_CROSS) readonly buffer Cross { uint cross[]; };
layout(std430, set = 0, binding = NGI_SELECT_BINDING_CROSS_TILES) readonly buffer CrossTiles { uint crossTiles[]; };
layout(std430, set = 0, binding = NGI_SELECT_BINDING_CHARTS) readonly buffer Charts { SelectionChart charts[]; };
layout(std430, set = 0, binding = NGI_SELECT_BINDING_PERIMETER) readonly buffer Perimeter { uint perimeter[]; };
layout(std430, set = 0, binding = NGI_SELECT_BINDING_MATES) readonly buffer Mates { uint mates[]; };
layout(std430, set = 0, binding = NGI_SELECT_BINDING_VIEWS) readonly buffer Views { SelectionView views[]; };
layout(std430, set = 0, binding = NGI_SELECT_BINDING_BITS) buffer Bits { uint bits[]; };
layout(std430, set = 0, binding = NGI_SELECT_BINDING_COUNTERS) buffer Counters { uint counters[]; };
layout(push_constant) uniform Push { SelectionPushConstants pc; };

const float kInfinity = 1.0 / 0.0;

// A tile as the passes read it: its bound decoded (ngi/tile_bound_code.h: the same numbers as
// the CPU's TileBound), its chart, level and place.
struct Tile {
    vec3 centre;
    float radius;
    vec3 coneAxis;
    float coneCos;
    float error;
    float errorUp;
    uint chart;
    uint level;
    uvec2 xy;
};

// Tile (x, y) of `level` of chart c (inside its level).
uint tileIndex(uint c, uint level, uvec2 xy)
{
    uint n = 1u << (charts[c].rootLevel - level);
    return charts[c].levelFirst[level] + xy.y * n + xy.x;
}

// The place (x, y) in its level of tile `index` of chart c at `level` (tileIndex's inverse).
uvec2 placeOf(uint index, uint c, uint level)
{
    uint shift = charts[c].rootLevel - level;
    uint local = index - charts[c].levelFirst[level];
    return uvec2(local & ((1u << shift) - 1u), local >> shift);
}

// The parent of tile `index` of chart c at `level` (< its root level).
uint parentOf(uint index, uint c, uint level) { return tileIndex(c, level + 1u, placeOf(index, c, level) >> 1u); }

// The cone axis of its octahedral 2 x 8-bit code, as ngi/tile_bound_code.cpp's coneAxisOf: the
// same operations, in the same order, for the same floats as the CPU's where the device rounds
// division and sqrt correctly (lavapipe does; Vulkan allows a few ulp, which only a cull at a
// knife's edge can tell).
vec3 coneAxisOf(uint code)
{
    // precise: no fused multiply-add (the CPU's compiler for x86-64 fuses none).
    precise vec2 e = (vec2(float(min(code & 0xFFu, 254u)), float(min(code >> 8, 254u))) - 127.0) / 127.0;
    precise vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = octWrap(n.xy);
    precise float squared = n.x * n.x + n.y * n.y + n.z * n.z;
    return n / sqrt(squared);
}

Tile tileAt(uint index)
{
    SelectionTile s = tiles[index];
    Tile t;
    uvec4 texel = uvec4(s.centreXY & 0xFFFFu, s.centreXY >> 16, s.centreZAxis & 0xFFFFu, s.centreZAxis >> 16);
    t.centre = vec3(texel.xyz) * (NGI_COMPACT_EXTENT / 65536.0) + NGI_COMPACT_ORIGIN;  // exact (tile_bound_code.cpp)
    t.coneAxis = coneAxisOf(s.centreZAxis >> 16);
    vec2 radiusCone = unpackHalf2x16(s.radiusConeCos);
    t.radius = radiusCone.x;
    t.coneCos = radiusCone.y;
    vec2 errors = unpackHalf2x16(s.errors);
    t.error = errors.x;
    t.errorUp = errors.y;
    t.chart = s.chartLevel & 0xFFFFu;
    t.level = s.chartLevel >> 16;
    t.xy = placeOf(index, t.chart, t.level);
    return t;
}

// Bit `tile` of `job`'s bitset: a level's words hold byError until select_close.comp makes them
// refined (which holds byError), finest level first, so one bitset serves both. Level 0, the
// last run of tiles, has no words: its tiles are never refined.
uint bitWord(uint job, uint tile) { return job * pc.wordsPerJob + (tile >> 5); }
bool bitOf(uint job, uint tile)
{
    return (tile >> 5) < pc.wordsPerJob && (bits[bitWord(job, tile)] & (1u << (tile & 31u))) != 0u;
}

// How far the tile's sphere lies outside the frustum (<= 0: it meets it); as Selector::outsideFrustum.
float outsideFrustum(SelectionView v, Tile t)
{
    float outside = -kInfinity;
    for (uint k = 0u; k < v.planeCount; ++k)
        outside = max(outside, -(dot(v.planes[k].xyz, t.centre) + v.planes[k].w) - t.radius);
    return outside;
}

// Pixels one normalized unit covers at the tile's nearest point (Selector::pixelsPerUnit).
float pixelsPerUnit(SelectionView v, Tile t)
{
    if ((v.flags & 1u) == 0u) return 1.0;
    float wCentre = (v.clipFromNormalized * vec4(t.centre, 1.0)).w;
    float wNear = max(wCentre - t.radius * v.gradW, v.gradW * outsideFrustum(v, t));
    if (!(wNear > 0.0)) return kInfinity;
    return 0.5 * v.viewportHeight * v.rowY / wNear;
}

bool touchesPerimeter(Tile t)
{
    uint last = (1u << (charts[t.chart].rootLevel - t.level)) - 1u;
    return t.xy.x == 0u || t.xy.y == 0u || t.xy.x == last || t.xy.y == last;
}
uint levelCap(Tile t)
{
    uint c = t.chart;
    return touchesPerimeter(t) ? charts[c].perimeterLevel : charts[c].coarsestLevel;
}

// Selector::needsRefinement.
bool needsRefinement(SelectionView v, Tile t)
{
    uint level = t.level;
    if (level == 0u) return false;
    if (level > levelCap(t)) return true;
    if (t.error <= 0.0) return false;
    return t.error * pixelsPerUnit(v, t) > v.budget;
}

// Selector::morph, quantized as quantizeMorph.
float tileMorph(SelectionView v, Tile t)
{
    if ((v.flags & 1u) == 0u) return 0.0;
    uint level = t.level;
    if (level + 1u > levelCap(t) || level + 1u > charts[t.chart].rootLevel) return 0.0;
    float ppu = pixelsPerUnit(v, t);
    if (!(ppu < kInfinity)) return 0.0;
    float allowed = v.budget / ppu;
    if (t.errorUp <= allowed) return 1.0;
    if (!(t.errorUp > t.error)) return 0.0;
    if (t.error >= allowed) return 0.0;
    float m = t.error > 0.0 ? log(allowed / t.error) / log(t.errorUp / t.error)
                            : (allowed - t.error) / (t.errorUp - t.error);
    m = isnan(m) || isinf(m) ? 0.0 : clamp(m, 0.0, 1.0);
    return floor(m * float(NGI_TILE_MORPH_SCALE) + 0.5) / float(NGI_TILE_MORPH_SCALE);
}

// Whether tile `index` is drawn for `job`: its parent is refined (or it is a root) and it is
// not. Reads bits and the tile's chart and level only, so the passes decode drawn tiles alone.
bool isDrawn(uint job, uint index)
{
    uint chartLevel = tiles[index].chartLevel;
    if (chartLevel == NGI_SELECT_NO_TILE || bitOf(job, index)) return false;
    uint c = chartLevel & 0xFFFFu, level = chartLevel >> 16;
    return level == charts[c].rootLevel || bitOf(job, parentOf(index, c, level));
}

// The drawn tile of chart c over its full-resolution cell `cell`: the first not refined on the
// way down from the root.
uint drawnTileOver(uint job, uint c, uvec2 cell)
{
    uint level = charts[c].rootLevel;
    uint tile = tileIndex(c, level, uvec2(0u));
    for (; level > 0u && bitOf(job, tile); --level)
        tile = tileIndex(c, level - 1u, cell >> (uint(findMSB(uint(NGI_TILE_QUADS))) + level - 1u));
    return tile;
}

// The bucket (one indirect draw) of a tile of chart c at `level` drawn by a job of `group`.
uint bucketOf(uint group, uint c, uint level) { return group * pc.bucketsPerGroup + charts[c].bucketFirst + level; }

// Backface culling by the normal cone (Selector::cullBackface).
bool cullBackface(SelectionView v, Tile t)
{
    if (t.coneCos <= 0.0) return false;
    vec3 d = t.centre - v.eye.xyz;
    float distance = length(d);
    if (!(distance > t.radius)) return false;
    float between = acos(clamp(dot(d / distance, t.coneAxis), -1.0, 1.0));
    float cone = acos(clamp(t.coneCos, -1.0, 1.0));
    float sphere = asin(clamp(t.radius / distance, 0.0, 1.0));
    return between + cone + sphere < 0.5 * 3.14159265358979;
}

// 0 drawn, 1 culled by the frustum, 2 by the normal cone.
uint cullOf(SelectionView v, Tile t)
{
    if ((v.flags & 3u) != 3u) return 0u;
    if (outsideFrustum(v, t) > 0.0) return 1u;
    if ((v.flags & 4u) != 0u && charts[t.chart].closed != 0u && cullBackface(v, t)) return 2u;
    return 0u;
}
