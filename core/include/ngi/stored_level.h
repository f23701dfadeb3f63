// ngi core: the stored level, one concept under one set of names.
//
// A geometry image of full resolution R (cells per side, a power of two; R + 1 samples, see
// docs/conventions.md) keeps only one nested mip level in its asset: the stored level L.
// Everything else about what is stored follows from R and L, and is derived here rather
// than recomputed at call sites (never with a literal 1024):
//     stored resolution  S = R >> L            cells per side (ngi-bake --store-res)
//     stored size        S + 1                 samples per side (Asset::storedSize())
//     restore factor     R / S = 2^L           what the restore (bilinear or the x2^L network) undoes
//     compression ratio  CR = (R / S)^2 = 4^L  the paper's pixel ratio (1024^2 / 128^2 = 64)
// The engine names it the same way (GeometryImageSurface::storedLevel).
#pragma once

#include "ngi/error.h"

#include <bit>
#include <cstdint>
#include <string>

namespace ngi {

// Cells per side of level `storedLevel` of a `fullResolution`-cell image: R >> L.
constexpr uint32_t storedResolutionAt(uint32_t fullResolution, uint32_t storedLevel)
{
    return storedLevel < 32 ? fullResolution >> storedLevel : 0;
}

// Samples per side of that level: (R >> L) + 1.
constexpr uint32_t storedSizeAt(uint32_t fullResolution, uint32_t storedLevel)
{
    return storedResolutionAt(fullResolution, storedLevel) + 1;
}

// The upsampling factor that restores level `storedLevel` to level 0: 2^L (L < 32).
constexpr uint32_t restoreFactor(uint32_t storedLevel) { return storedLevel < 32 ? 1u << storedLevel : 0; }

// The stored level L with R >> L == S. ngi::Error unless R and S are powers of two with
// 1 <= S <= R (the message names both).
inline uint32_t storedLevelOf(uint32_t fullResolution, uint32_t storedResolution)
{
    if (!std::has_single_bit(fullResolution) || !std::has_single_bit(storedResolution) ||
        storedResolution > fullResolution)
        throw Error("stored resolution " + std::to_string(storedResolution) + " is not a power-of-two level of a " +
                    std::to_string(fullResolution) + "-cell geometry image");
    return uint32_t(std::countr_zero(fullResolution / storedResolution));
}

// CR of keeping `storedResolution` cells of a `fullResolution`-cell image: (R / S)^2, as a
// ratio of pixel counts (the paper's definition). Any positive sizes; 0 when S is 0.
constexpr double compressionRatio(uint32_t fullResolution, uint32_t storedResolution)
{
    return storedResolution == 0
        ? 0.0
        : (double(fullResolution) * fullResolution) / (double(storedResolution) * storedResolution);
}

// CR of keeping level `storedLevel` (of any full resolution): 4^L.
constexpr double compressionRatioAtLevel(uint32_t storedLevel)
{
    return double(restoreFactor(storedLevel)) * double(restoreFactor(storedLevel));
}

}  // namespace ngi
