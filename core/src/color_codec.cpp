// ngi core: the WebP coding of a chart's colour image (color_codec.h).
#include "ngi/color_codec.h"

#include "ngi/error.h"

#include <webp/decode.h>
#include <webp/encode.h>

#include <algorithm>
#include <memory>

namespace ngi {

std::vector<uint8_t> encodeColorImage(std::span<const uint8_t> rgba, uint32_t size, uint32_t quality,
                                      const std::string& where)
{
    if (size == 0 || size > uint32_t(WEBP_MAX_DIMENSION) || rgba.size() != size_t(size) * size * 4)
        throw Error(where + ": cannot code a " + std::to_string(size) + "^2 colour image (WebP holds 1 to " +
                    std::to_string(WEBP_MAX_DIMENSION) + " texels per side)");
    bool opaque = true;
    for (size_t i = 3; i < rgba.size() && opaque; i += 4) opaque = rgba[i] == 255;
    std::vector<uint8_t> rgb;
    if (opaque) {
        rgb.resize(size_t(size) * size * 3);
        for (size_t i = 0, n = size_t(size) * size; i < n; ++i) std::copy_n(&rgba[i * 4], 3, &rgb[i * 3]);
    }
    uint8_t* out = nullptr;
    const int stride = int(size) * (opaque ? 3 : 4);
    size_t bytes = 0;
    if (quality > 100)
        bytes = opaque ? WebPEncodeLosslessRGB(rgb.data(), int(size), int(size), stride, &out)
                       : WebPEncodeLosslessRGBA(rgba.data(), int(size), int(size), stride, &out);
    else
        bytes = opaque ? WebPEncodeRGB(rgb.data(), int(size), int(size), stride, float(quality), &out)
                       : WebPEncodeRGBA(rgba.data(), int(size), int(size), stride, float(quality), &out);
    std::unique_ptr<uint8_t, void (*)(void*)> owner(out, WebPFree);
    if (bytes == 0 || !out) throw Error(where + ": WebP could not code the colour image");
    return std::vector<uint8_t>(out, out + bytes);
}

std::vector<uint8_t> decodeColorImage(std::span<const uint8_t> bytes, uint32_t size, const std::string& where)
{
    int width = 0, height = 0;
    if (!WebPGetInfo(bytes.data(), bytes.size(), &width, &height)) throw Error(where + ": not a WebP image");
    if (width != int(size) || height != int(size))
        throw Error(where + ": its WebP image is " + std::to_string(width) + "x" + std::to_string(height) +
                    ", the chart's colour level " + std::to_string(size) + "x" + std::to_string(size));
    std::vector<uint8_t> rgba(size_t(size) * size * 4);
    if (!WebPDecodeRGBAInto(bytes.data(), bytes.size(), rgba.data(), rgba.size(), int(size) * 4))
        throw Error(where + ": its WebP image is corrupt or truncated");
    return rgba;
}

}  // namespace ngi
