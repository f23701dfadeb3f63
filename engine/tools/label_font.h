// A 5x7 bitmap font for labelling contact sheets (digits, capital letters and a few signs;
// lower-case letters print as capitals). Hand-made for ngi; public domain.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ngi {

// Draws `text` into an RGBA8 image with its top-left at (x, y), each font pixel `scale`
// image pixels wide, clipped to the image.
void drawLabel(std::vector<uint8_t>& rgba, uint32_t width, uint32_t height, int x, int y, const std::string& text,
               int scale, const uint8_t colour[3]);

// Width in pixels of `text` drawn at `scale`.
int labelWidth(const std::string& text, int scale);

}  // namespace ngi
