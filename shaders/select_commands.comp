#version 450
// The adaptive LoD's selection, pass 4 of 5 (tile_selection.glsl): one indirect draw per
// bucket, its tiles' records one after the other from the bucket's first (a prefix sum of the
// counts, in bucket order); each bucket's cursor starts at its first record, and its count
// becomes the end of its records. Records past the capacity (pc.tileCount) are not drawn, and
// counted (counters[pc.statsFirst - 1]). One invocation.
#extension GL_GOOGLE_include_directive : require
#include "ngi_shared.h"
#include "texel.glsl"
#include "tile_selection.glsl"

layout(local_size_x = 1) in;
layout(std430, set = 0, binding = NGI_SELECT_BINDING_COMMANDS) writeonly buffer Commands { uint commands[]; };

void main()
{
    uint first = 0u;
    for (uint b = 0u; b < pc.buckets; ++b) {
        uint wanted = counters[b];
        uint count = min(wanted, pc.tileCount - min(first, pc.tileCount));
        counters[pc.statsFirst - 1u] += wanted - count;
        commands[4u * b + 0u] = 6u * NGI_TILE_QUADS * NGI_TILE_QUADS;
        commands[4u * b + 1u] = count;
        commands[4u * b + 2u] = 0u;
        commands[4u * b + 3u] = first;
        counters[pc.buckets + b] = first;
        counters[b] = first + count;
        first += count;
    }
}
