// ngi core: the sRGB transfer function (ngi/srgb.h).
#include "ngi/srgb.h"

#include <algorithm>
#include <cmath>

namespace ngi {

double srgbToLinear(double s)
{
    s = std::clamp(s, 0.0, 1.0);
    return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

double linearToSrgb(double l)
{
    l = std::clamp(l, 0.0, 1.0);
    return l <= 0.0031308 ? 12.92 * l : 1.055 * std::pow(l, 1.0 / 2.4) - 0.055;
}

const std::array<float, 256>& srgb8ToLinear()
{
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int i = 0; i < 256; ++i) t[size_t(i)] = float(srgbToLinear(i / 255.0));
        return t;
    }();
    return table;
}

}  // namespace ngi
