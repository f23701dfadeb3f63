// ngi core: a tile bound in 16 bytes, the form the selection on the GPU keeps for every tile
// (ngi_shared.h's SelectionTile; shaders/tile_selection.glsl decodes it). The sphere's centre
// is 16-bit unorm over compact_texel.h's box of normalized space, with a step of 1.25 / 2^16
// (not the compact texel's 1.25 / 65535: this one decodes exactly in float, fused or not), the
// normal cone's axis octahedral in 2 x 8 bits as the compact texel's normal, the radius, the
// cone's cos, `error` and `errorUp` IEEE half floats, never subnormal (a GPU may flush those). Every rounding is conservative: the radius grows by the centre's rounding
// and rounds up, the cone widens by the axis's rounding and its cos rounds down, the errors
// round up. A bound decoded from its code therefore still bounds what the tile's samples
// measured. buildTileTree keeps every bound as its code stands for, so the CPU selection and
// the GPU's decide on the same numbers.
#pragma once

#include "ngi/adaptive_lod.h"

#include <array>
#include <cstdint>

namespace ngi {

// words[0]: centre x | y << 16; words[1]: centre z | cone axis << 16 (the compact texel's xyzw);
// words[2]: half(radius) | half(coneCos) << 16; words[3]: half(error) | half(errorUp) << 16.
struct TileBoundCode {
    std::array<uint32_t, 4> words{};
};

// The code of a measured `bound`, rounded as above with a margin of 1e-6 rad on the cone. A
// radius or error that is not finite, or past half's range, codes as +infinity (it still
// bounds); a cone wider than a hemisphere after the axis's rounding codes as "no cone"
// (coneCos -1).
TileBoundCode encodeTileBound(const TileBound& bound);

// The code of a bound that decodeTileBound returned, exactly: it decodes to the same floats
// (its bits may differ only where two octahedral codes stand for one axis, on the fold).
// ngi::Error for any other bound.
TileBoundCode recodeTileBound(const TileBound& bound);

// The bound a code stands for.
TileBound decodeTileBound(const TileBoundCode& code);

// The smallest half float >= v (v >= 0 or +infinity; NaN gives +infinity), as a float.
float roundUpToHalf(float v);

}  // namespace ngi
