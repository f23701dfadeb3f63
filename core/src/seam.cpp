// ngi core: seam tables and the weld (Gu, Gortler, Hoppe 2002, "Geometry Images", section 4;
// see seam.h for the perimeter convention).
#include "ngi/seam.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <numeric>
#include <string>

namespace ngi {

glm::uvec2 perimeterSample(uint32_t resolution, uint32_t t) {
    const uint32_t r = resolution;
    t %= 4 * r;
    if (t <= r) return {t, 0};
    if (t <= 2 * r) return {r, t - r};
    if (t <= 3 * r) return {3 * r - t, r};
    return {0, 4 * r - t};
}

uint32_t seamAlignedLevel(const std::vector<SeamSegment>& segments, uint32_t levelLimit) {
    uint32_t level = levelLimit;
    auto align = [&](uint32_t v) {
        while (level > 0 && (v & ((1u << level) - 1u)) != 0) --level;
    };
    for (const SeamSegment& s : segments) {
        align(s.a);
        align(s.b);
        align(s.length);
    }
    return level;
}

uint32_t seamLevelLimit(uint32_t levelCount) { return levelCount >= 3 ? levelCount - 3 : 0; }

uint32_t coarsestDrawnLevel(const ChartSeams& seams, uint32_t levelCount) {
    if (levelCount == 0) return 0;
    if (!seams.matched) return levelCount - 1;
    // Never a level where the seam can open: a chart whose cut has more nodes than a coarse
    // border has samples (K finer than 5 x 5) ends its LoD range at K.
    return std::min(seams.coarsestWatertightLevel, levelCount - 1);
}

void validateSeams(const ChartSeams& seams, uint32_t resolution, uint32_t levelCount, const std::string& name) {
    const uint64_t perimeter = 4ull * resolution;
    if (seams.coarsestWatertightLevel >= levelCount)
        throw Error(name + ": seam's coarsest watertight level " + std::to_string(seams.coarsestWatertightLevel) +
                    " is beyond the chart's " + std::to_string(levelCount) + " levels");
    if (seams.segments.size() > perimeter)
        throw Error(name + ": " + std::to_string(seams.segments.size()) + " seam segments for a border of " +
                    std::to_string(perimeter) + " samples");
    const uint32_t mask = (1u << seams.coarsestWatertightLevel) - 1u;
    for (size_t k = 0; k < seams.segments.size(); ++k) {
        const SeamSegment& s = seams.segments[k];
        const std::string what = name + ": seam segment " + std::to_string(k);
        if (s.length == 0) throw Error(what + " is empty");
        if (uint64_t(s.a) + s.length > perimeter || uint64_t(s.b) + s.length > perimeter)
            throw Error(what + " runs past the border's " + std::to_string(perimeter) + " samples");
        if (((s.a | s.b | s.length) & mask) != 0)
            throw Error(what + " does not end on samples of level " + std::to_string(seams.coarsestWatertightLevel));
    }
}

std::vector<uint32_t> seamWeldTable(const ChartSeams& seams, uint32_t resolution) {
    const uint32_t perimeter = 4 * resolution;
    std::vector<uint32_t> parent(perimeter);
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (const SeamSegment& s : seams.segments)
        for (uint32_t i = 0; i <= s.length; ++i) {
            const uint32_t p = find((s.a + i) % perimeter), q = find((s.b + s.length - i) % perimeter);
            // The smaller index becomes the root, so every root is its class's minimum.
            if (p < q) parent[q] = p;
            else if (q < p) parent[p] = q;
        }
    for (uint32_t t = 0; t < perimeter; ++t) parent[t] = find(t);
    return parent;
}

std::vector<uint32_t> seamWeldTable(const ChartSeams& seams, uint32_t resolution, uint32_t level) {
    if (level > seams.coarsestWatertightLevel || level >= 32 || (resolution >> level) == 0)
        throw Error("seam weld: level " + std::to_string(level) + " is coarser than the seam's coarsest watertight level " +
                    std::to_string(seams.coarsestWatertightLevel));
    const std::vector<uint32_t> full = seamWeldTable(seams, resolution);
    const uint32_t step = 1u << level;
    std::vector<uint32_t> table(size_t(4) * (resolution >> level));
    for (uint32_t t = 0; t < table.size(); ++t) table[t] = full[size_t(t) * step] / step;
    return table;
}

void weldSeams(GeometryImage& image, const std::vector<uint32_t>& table) {
    const uint32_t r = image.resolution();
    if (r == 0 || table.size() != size_t(4) * r)
        throw Error("seam weld: a table of " + std::to_string(table.size()) + " entries for an image of resolution " +
                    std::to_string(r));
    for (uint32_t t = 0; t < table.size(); ++t) {
        if (table[t] == t) continue;
        const glm::uvec2 dst = perimeterSample(r, t), src = perimeterSample(r, table[t]);
        image.at(dst.x, dst.y) = image.at(src.x, src.y);
    }
}

SeamGap measureSeamGap(const GeometryImage& image, const std::vector<uint32_t>& table) {
    SeamGap gap;
    const uint32_t r = image.resolution();
    if (r == 0 || table.size() != size_t(4) * r) return gap;
    for (uint32_t t = 0; t < table.size(); ++t) {
        if (table[t] == t) continue;
        const glm::uvec2 dst = perimeterSample(r, t), src = perimeterSample(r, table[t]);
        const glm::vec3 p = image.at(dst.x, dst.y), q = image.at(src.x, src.y);
        if (p != q) ++gap.unequalMates;
        gap.maxDistance = std::max(gap.maxDistance, double(glm::distance(p, q)));
    }
    return gap;
}

} // namespace ngi
