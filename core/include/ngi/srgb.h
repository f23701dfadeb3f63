// ngi core: the sRGB transfer function (IEC 61966-2-1), shared by the readers (8-bit colours),
// the bake (colour images), the rate control, the evaluation and the engine (mip chains).
#pragma once

#include <array>

namespace ngi {

// An sRGB-encoded value in [0, 1] to linear light; values outside [0, 1] are clamped first.
double srgbToLinear(double srgb);
// Linear light in [0, 1] to its sRGB encoding; values outside [0, 1] are clamped first.
double linearToSrgb(double linear);
// srgbToLinear(i / 255) for every 8-bit code i.
const std::array<float, 256>& srgb8ToLinear();

}  // namespace ngi
