#version 450
// The adaptive LoD's selection, pass 5 of 5 (tile_selection.glsl), one level: writes
// each drawn tile's record (gpu::AdaptiveTile) into its bucket, with the state of each of its
// border vertices as TileSelection::borderState gives it: the coarsest level of the drawn tiles
// that hold the vertex (over its seam mates too), the largest morph there. Counts the drawn
// triangles (a border vertex drawn one level coarser drops its odd neighbours' triangles).
// One invocation per (32 tiles, job).
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"
#include "tile_selection.glsl"
#include "perimeter.glsl"

layout(local_size_x = NGI_SELECT_LOCAL) in;
layout(std430, set = 0, binding = NGI_SELECT_BINDING_RECORDS) writeonly buffer Records { AdaptiveTile records[]; };

// The later of two holders (holdState): the coarser level, the larger morph at one level.
uvec2 hold(uvec2 state, uint level, float morph)
{
    uint m = uint(morph * float(NGI_TILE_MORPH_SCALE) + 0.5);
    if (level > state.x) return uvec2(level, m);
    if (level == state.x) return uvec2(level, max(state.y, m));
    return state;
}

// The state of full-resolution sample s of chart c from its own chart's tiles: the drawn tiles
// over the (up to four) cells that meet at it.
uvec2 stateInChart(uint job, SelectionView v, uint c, ivec2 s, uvec2 state)
{
    int r = int(charts[c].resolution);
    for (int dy = -1; dy <= 0; ++dy)
        for (int dx = -1; dx <= 0; ++dx) {
            ivec2 cell = s + ivec2(dx, dy);
            if (cell.x < 0 || cell.y < 0 || cell.x >= r || cell.y >= r) continue;
            Tile t = tileAt(drawnTileOver(job, c, uvec2(cell)));
            state = hold(state, t.level, tileMorph(v, t));
        }
    return state;
}

uvec2 borderState(uint job, SelectionView v, uint c, ivec2 s)
{
    int r = int(charts[c].resolution);
    uvec2 state = uvec2(0u, 0u);
    if (s.x != 0 && s.y != 0 && s.x != r && s.y != r) return stateInChart(job, v, c, s, state);
    int t = s.y == 0 ? s.x : s.x == r ? r + s.y : s.y == r ? 3 * r - s.x : 4 * r - s.y;
    uint group = perimeter[charts[c].perimeterFirst + uint(t)];
    if ((group >> 24) == 0u) return stateInChart(job, v, c, s, state);
    for (uint k = 0u; k < (group >> 24); ++k) {
        uint mate = mates[(group & 0xFFFFFFu) + k];
        uint mc = mate >> 16;
        state = stateInChart(job, v, mc, perimeterSample(mate & 0xFFFFu, charts[mc].resolution), state);
    }
    return state;
}

void main()
{
    uint word = gl_GlobalInvocationID.x, job = gl_GlobalInvocationID.y;
    uint words = (pc.tileCount + 31u) / 32u;
    if (word >= words || job >= pc.jobCount) return;
    // No tile of the next coarser level refined: none of this level is drawn but roots.
    if (pc.roots == 0u && (counters[pc.levelFlagsFirst + job] & (1u << (pc.level + 1u))) == 0u) return;
    SelectionView v = views[job];
    const int P = NGI_TILE_QUADS;
    uint triangles = 0u;
    for (uint i = 0u; i < 32u; ++i) {
        uint index = pc.firstTile + 32u * word + i;
        if (32u * word + i >= pc.tileCount) break;
        if (!isDrawn(job, index)) continue;
        Tile t = tileAt(index);
        if (cullOf(v, t) != 0u) continue;
        uint c = t.chart, level = t.level;
        uint bucket = bucketOf(v.group, c, level);
        uint slot = atomicAdd(counters[pc.buckets + bucket], 1u);
        if (slot >= counters[bucket]) continue;  // past the records' capacity (select_commands.comp)
        AdaptiveTile record;
        ivec2 origin = ivec2(t.xy) * P;
        record.x = uint(origin.x);
        record.y = uint(origin.y);
        record.levelInstance = level | (v.instance << 8);
        record.morph = tileMorph(v, t);
        uint dropped = 0u;
        for (int b = 0; b < 4 * P; ++b) {
            ivec2 o = b <= P ? ivec2(b, 0) : b <= 2 * P ? ivec2(P, b - P) : b <= 3 * P ? ivec2(3 * P - b, P) : ivec2(0, 4 * P - b);
            uvec2 state = borderState(job, v, c, (origin + o) << level);
            uint bits16 = (state.x > level ? NGI_TILE_COARSER_BIT : 0u) | state.y;
            if ((b & 1) == 0) record.border[b >> 1] = bits16;
            else record.border[b >> 1] |= bits16 << 16;
            if (((o.x | o.y) & 1) != 0 && state.x > level) ++dropped;
        }
        records[slot] = record;
        triangles += 2u * uint(P * P) - dropped;
    }
    if (triangles > 0u) atomicAdd(counters[pc.statsFirst + 4u * job + NGI_SELECT_STAT_TRIANGLES], triangles);
}
