#version 450
// The adaptive LoD's selection, pass 2 of 4 (tile_selection.glsl), one level, finest first
// from level 1: a tile is refined when it is refined by error, or one of its children is, or a
// tile one level finer that shares a vertex with it is: in its chart the ring around its
// children, across seams its cross tiles. This is the CPU's balance (no two drawn tiles sharing
// a vertex differ by more than one level) without its iterations. One invocation per (32 tiles
// of the level, job); it writes their refined word.
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
    uint result = bits[bitWord(job, pc.firstTile + 32u * word)];
    // No tile one level finer refined (level 0 never is): refined is refined by error.
    // (An atomic read: other invocations of this dispatch set other bits of the word.)
    bool finerRefined = pc.level > 1u && (atomicOr(counters[pc.levelFlagsFirst + job], 0u) & (1u << (pc.level - 1u))) != 0u;
    for (uint i = 0u; finerRefined && i < 32u; ++i) {
        uint index = pc.firstTile + 32u * word + i;
        if (32u * word + i >= pc.tileCount) break;
        if ((result & (1u << i)) != 0u) continue;
        Tile t = tileAt(index);
        uint c = t.chart;
        int n = int(1u << (charts[c].rootLevel - (pc.level - 1u)));
        ivec2 first = 2 * ivec2(t.xy);
        bool refined = false;
        // Its four children and the twelve tiles around them, one level finer.
        for (int y = max(first.y - 1, 0); y <= min(first.y + 2, n - 1); ++y)
            for (int x = max(first.x - 1, 0); x <= min(first.x + 2, n - 1); ++x)
                refined = refined || bitOf(job, tileIndex(c, pc.level - 1u, uvec2(x, y)));
        uint list = cross[index];
        for (uint k = 0u; k < (list >> 24); ++k) refined = refined || bitOf(job, crossTiles[(list & 0xFFFFFFu) + k]);
        if (refined) result |= 1u << i;
    }
    bits[bitWord(job, pc.firstTile + 32u * word)] = result;
    if (result != 0u) atomicOr(counters[pc.levelFlagsFirst + job], 1u << pc.level);
}
