#version 450
// The adaptive LoD's selection, pass 3 of 5 (tile_selection.glsl), one level: counts
// the drawn tiles of each bucket (a group's chart and level: one indirect draw) and the culled
// ones, per job. One invocation per (32 tiles, job).
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
    // No tile of the next coarser level refined: none of this level is drawn but roots.
    if (pc.roots == 0u && (counters[pc.levelFlagsFirst + job] & (1u << (pc.level + 1u))) == 0u) return;
    SelectionView v = views[job];
    uint culledFrustum = 0u, culledBackface = 0u;
    for (uint i = 0u; i < 32u; ++i) {
        uint index = pc.firstTile + 32u * word + i;
        if (32u * word + i >= pc.tileCount) break;
        if (!isDrawn(job, index)) continue;
        Tile t = tileAt(index);
        uint cull = cullOf(v, t);
        if (cull == 1u) {
            ++culledFrustum;
        } else if (cull == 2u) {
            ++culledBackface;
        } else {
            atomicAdd(counters[bucketOf(v.group, t.chart, t.level)], 1u);
            atomicAdd(counters[pc.statsFirst + 4u * job + NGI_SELECT_STAT_DRAWN], 1u);
        }
    }
    if (culledFrustum > 0u) atomicAdd(counters[pc.statsFirst + 4u * job + NGI_SELECT_STAT_CULLED_FRUSTUM], culledFrustum);
    if (culledBackface > 0u)
        atomicAdd(counters[pc.statsFirst + 4u * job + NGI_SELECT_STAT_CULLED_BACKFACE], culledBackface);
}
