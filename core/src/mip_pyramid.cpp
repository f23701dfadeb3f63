// Nested-grid mip pyramid of a geometry image: Gu, Gortler, Hoppe 2002, section 7.
// See ngi/mip_pyramid.h for why the scheme keeps the boundary exact.
#include "ngi/mip_pyramid.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <string>

namespace ngi {

bool isNestedGridSize(uint32_t size)
{
    if (size < 2) return false;
    const uint32_t cells = size - 1;
    return (cells & (cells - 1)) == 0;
}

uint32_t mipLevelCount(uint32_t fullSize)
{
    if (!isNestedGridSize(fullSize))
        throw Error("mip pyramid: " + std::to_string(fullSize) + " samples per side is not 2^k+1");
    uint32_t count = 1;
    for (uint32_t cells = fullSize - 1; cells > 1; cells >>= 1) ++count;
    return count;
}

uint32_t mipLevelSize(uint32_t fullSize, uint32_t level) { return ((fullSize - 1) >> level) + 1; }

GeometryImage downsampleNested(const GeometryImage& fine, uint32_t levels)
{
    if (levels >= mipLevelCount(fine.size))
        throw Error("mip pyramid: cannot go " + std::to_string(levels) + " levels below " + std::to_string(fine.size) +
                    " samples");
    const uint32_t step = 1u << levels;
    GeometryImage coarse(mipLevelSize(fine.size, levels));
    for (uint32_t y = 0; y < coarse.size; ++y)
        for (uint32_t x = 0; x < coarse.size; ++x) coarse.at(x, y) = fine.at(x * step, y * step);
    return coarse;
}

GeometryImage upsampleNested(const GeometryImage& coarse, bool normalize)
{
    if (!isNestedGridSize(coarse.size))
        throw Error("mip pyramid: " + std::to_string(coarse.size) + " samples per side is not 2^k+1");
    GeometryImage fine(2 * (coarse.size - 1) + 1);
    for (uint32_t y = 0; y < fine.size; ++y)
        for (uint32_t x = 0; x < fine.size; ++x) {
            const uint32_t x0 = x / 2, y0 = y / 2, x1 = (x + 1) / 2, y1 = (y + 1) / 2;
            if (x0 == x1 && y0 == y1) {
                fine.at(x, y) = coarse.at(x0, y0);
                continue;
            }
            glm::vec3 v = (coarse.at(x0, y0) + coarse.at(x1, y0)) + (coarse.at(x0, y1) + coarse.at(x1, y1));
            if (normalize) {
                const float len = glm::length(v);
                v = len > 0.0f ? v / len : coarse.at(x0, y0);
            } else {
                v *= 0.25f;
            }
            fine.at(x, y) = v;
        }
    return fine;
}

std::vector<GeometryImage> buildMipPyramid(const GeometryImage& full)
{
    const uint32_t count = mipLevelCount(full.size);
    std::vector<GeometryImage> levels;
    levels.reserve(count);
    levels.push_back(full);
    for (uint32_t level = 1; level < count; ++level) levels.push_back(downsampleNested(levels.back()));
    return levels;
}

}  // namespace ngi
