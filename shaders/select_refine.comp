#version 450
// The adaptive LoD's selection, pass 1 of 4 (tile_selection.glsl), one level, coarsest first:
// a tile is refined by error when it is visited top-down (a root, or its parent refined by
// error) and needs refinement (Selector::needsRefinement), and its children may be drawn (a
// chart whose level 0 is not resident draws level 1 at the finest). A level-1 tile refined by
// error and not culled reports its chart's level 0 as needed, resident or not: one rule, so
// that residency does not change what is reported.
// One invocation per (32 tiles of the level, job); it writes their byError word.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"
#include "tile_selection.glsl"

layout(local_size_x = NGI_SELECT_LOCAL) in;

void main()
{
    uint word = gl_GlobalInvocationID.x, job = gl_GlobalInvocationID.y;
    uint words = (pc.tileCount + 31u) / 32u;
    if (word >= words || job >= pc.jobCount) return;
    SelectionView v = views[job];
    uint result = 0u;
    // Nothing of the next coarser level refined by error: only roots are visited.
    // (An atomic read: other invocations of this dispatch set other bits of the word.)
    bool visits = pc.roots != 0u || (atomicOr(counters[pc.levelFlagsFirst + job], 0u) & (0x10000u << (pc.level + 1u))) != 0u;
    for (uint i = 0u; visits && i < 32u; ++i) {
        uint index = pc.firstTile + 32u * word + i;
        if (32u * word + i >= pc.tileCount) break;
        uint chartLevel = tiles[index].chartLevel;
        uint c = chartLevel & 0xFFFFu;
        // Not visited top-down: not a root, and its parent not refined by error.
        if (pc.level != charts[c].rootLevel && !bitOf(job, parentOf(index, c, pc.level))) continue;
        Tile t = tileAt(index);
        if (!needsRefinement(v, t)) continue;
        if (pc.level == 1u && cullOf(v, t) == 0u) atomicOr(counters[pc.statsFirst + 4u * pc.jobCount + c], 1u);
        if (pc.level - 1u < charts[c].finestDrawable) continue;
        result |= 1u << i;
    }
    bits[bitWord(job, pc.firstTile + 32u * word)] = result;
    if (result != 0u) atomicOr(counters[pc.levelFlagsFirst + job], 0x10000u << pc.level);
}
