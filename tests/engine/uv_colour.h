// Test helper: a chart's base colour that tells the uv (red = u, green = v, blue 64), so that a
// frame shows where on the chart's square each pixel's colour came from.
#pragma once

#include "ngi/asset.h"

#include <cstdint>

namespace ngi::test {

// Gives `chart` that base colour at grid level `colorLevel`.
inline void paintUvColour(ngi::AssetChart& chart, uint32_t colorLevel)
{
    chart.baseColorLevel = colorLevel;
    const uint32_t n = chart.baseColorSize();
    chart.baseColor.resize(size_t(n) * n * 4);
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x) {
            uint8_t* t = &chart.baseColor[(size_t(y) * n + x) * 4];
            t[0] = uint8_t(255 * x / (n - 1)), t[1] = uint8_t(255 * y / (n - 1)), t[2] = 64, t[3] = 255;
        }
}

// Sets the alpha of `chart`'s base colour (painted above) texel by texel: alpha(u, v), with u
// and v in [0, 1] the texel's place on the chart's square.
template <class Alpha> void setUvAlpha(ngi::AssetChart& chart, Alpha alpha)
{
    const uint32_t n = chart.baseColorSize();
    for (uint32_t y = 0; y < n; ++y)
        for (uint32_t x = 0; x < n; ++x)
            chart.baseColor[(size_t(y) * n + x) * 4 + 3] = uint8_t(alpha(double(x) / (n - 1), double(y) / (n - 1)));
}

}  // namespace ngi::test
