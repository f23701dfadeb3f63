// ngi core: seam tables and the weld (Gu, Gortler, Hoppe 2002, "Geometry Images", section 4;
// see seam.h for the perimeter convention).
#include "ngi/seam.h"

#include "ngi/error.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <numeric>
#include <string>

namespace ngi {

glm::uvec2 perimeterSample(uint32_t resolution, uint32_t t)
{
    const uint32_t r = resolution;
    t %= 4 * r;
    if (t <= r) return {t, 0};
    if (t <= 2 * r) return {r, t - r};
    if (t <= 3 * r) return {3 * r - t, r};
    return {0, 4 * r - t};
}

uint32_t seamAlignedLevel(const std::vector<SeamSegment>& segments, uint32_t levelLimit)
{
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

uint32_t coarsestDrawnLevel(const ChartSeams& seams, uint32_t levelCount)
{
    if (levelCount == 0) return 0;
    if (!seams.matched) return levelCount - 1;
    // Never a level where the seam can open: a chart whose cut has more nodes than a coarse
    // border has samples (K finer than 5 x 5) ends its LoD range at K.
    return std::min(seams.coarsestWatertightLevel, levelCount - 1);
}

void validateSeams(const ChartSeams& seams, uint32_t resolution, uint32_t levelCount, const std::string& name)
{
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

void validateCrossSeams(const std::vector<CrossSeamSegment>& crossSeams, const std::vector<ChartSeams>& seams,
                        const std::vector<uint32_t>& resolutions, const std::string& name)
{
    const size_t charts = std::min(seams.size(), resolutions.size());
    for (size_t k = 0; k < crossSeams.size(); ++k) {
        const CrossSeamSegment& s = crossSeams[k];
        const std::string what = name + ": cross seam " + std::to_string(k);
        if (!(s.chartA < s.chartB) || s.chartB >= charts)
            throw Error(what + " joins charts " + std::to_string(s.chartA) + " and " + std::to_string(s.chartB) +
                        " of " + std::to_string(charts) + " (needs chartA < chartB < the chart count)");
        const ChartSeams& a = seams[s.chartA];
        const ChartSeams& b = seams[s.chartB];
        if (!a.matched || !b.matched) throw Error(what + " joins a chart whose border is not matched");
        if (a.coarsestWatertightLevel != b.coarsestWatertightLevel)
            throw Error(what + " joins charts of coarsest watertight levels " +
                        std::to_string(a.coarsestWatertightLevel) + " and " +
                        std::to_string(b.coarsestWatertightLevel));
        if (s.length == 0) throw Error(what + " is empty");
        const uint64_t pa = 4ull * resolutions[s.chartA], pb = 4ull * resolutions[s.chartB];
        if (uint64_t(s.a) + s.length > pa || uint64_t(s.b) + s.length > pb)
            throw Error(what + " runs past a border (" + std::to_string(pa) + " and " + std::to_string(pb) +
                        " samples)");
        const uint32_t mask = (1u << a.coarsestWatertightLevel) - 1u;
        if (((s.a | s.b | s.length) & mask) != 0)
            throw Error(what + " does not end on samples of level " + std::to_string(a.coarsestWatertightLevel));
    }
}

GroupWeldPlan groupWeldPlan(const std::vector<ChartSeams>& seams, const std::vector<uint32_t>& resolutions,
                            const std::vector<CrossSeamSegment>& crossSeams, uint32_t level)
{
    const size_t charts = seams.size();
    if (resolutions.size() != charts) throw Error("group weld: the tables do not match");
    std::vector<size_t> offset(charts + 1, 0);
    for (size_t c = 0; c < charts; ++c) {
        const uint32_t r = resolutions[c] >> level;
        if (r == 0) throw Error("group weld: chart " + std::to_string(c) + " has no level " + std::to_string(level));
        offset[c + 1] = offset[c] + 4 * size_t(r);
    }
    std::vector<size_t> parent(offset.back());
    std::iota(parent.begin(), parent.end(), size_t(0));
    auto find = [&](size_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    auto unite = [&](size_t a, size_t b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the smallest index stays canonical
    };
    auto aligned = [&](uint32_t v, size_t c) {
        if (!seams[c].matched || level > seams[c].coarsestWatertightLevel || (v & ((1u << level) - 1)) != 0)
            throw Error("group weld: chart " + std::to_string(c) + "'s seams are not aligned to level " +
                        std::to_string(level));
        return v >> level;
    };
    // A chart's own mates take part where it shares a curve (a class may run through both);
    // charts of other components weld themselves.
    std::vector<char> grouped(charts, 0);
    for (const CrossSeamSegment& s : crossSeams) {
        if (s.chartA >= charts || s.chartB >= charts)
            throw Error("group weld: a cross seam names a chart out of range");
        grouped[s.chartA] = grouped[s.chartB] = 1;
    }
    for (size_t c = 0; c < charts; ++c) {
        if (!seams[c].matched || !grouped[c]) continue;
        const size_t perimeter = offset[c + 1] - offset[c];
        for (const SeamSegment& s : seams[c].segments) {
            const uint32_t a = aligned(s.a, c), b = aligned(s.b, c), length = aligned(s.length, c);
            for (uint32_t i = 0; i <= length; ++i)
                unite(offset[c] + (a + i) % perimeter, offset[c] + (b + length - i) % perimeter);
        }
    }
    for (const CrossSeamSegment& s : crossSeams) {
        const uint32_t a = aligned(s.a, s.chartA), b = aligned(s.b, s.chartB), length = aligned(s.length, s.chartA);
        const size_t pa = offset[s.chartA + 1] - offset[s.chartA], pb = offset[s.chartB + 1] - offset[s.chartB];
        for (uint32_t i = 0; i <= length; ++i)
            unite(offset[s.chartA] + (a + i) % pa, offset[s.chartB] + (b + length - i) % pb);
    }
    GroupWeldPlan plan;
    plan.gather.resize(charts);
    plan.scatter.resize(charts);
    std::vector<uint32_t> slotOf(offset.back(), ~0u);
    for (size_t c = 0; c < charts; ++c)
        for (size_t t = 0; t < offset[c + 1] - offset[c]; ++t) {
            const size_t root = find(offset[c] + t);
            if (root == offset[c] + t) continue;
            if (slotOf[root] == ~0u) {
                slotOf[root] = plan.slots++;
                const size_t rc = size_t(std::upper_bound(offset.begin(), offset.end(), root) - offset.begin()) - 1;
                plan.gather[rc].push_back({uint32_t(root - offset[rc]), slotOf[root]});
            }
            plan.scatter[c].push_back({uint32_t(t), slotOf[root]});
        }
    return plan;
}

double weldGroupSeams(const std::vector<GeometryImage*>& images, const std::vector<ChartSeams>& seams,
                      const std::vector<uint32_t>& resolutions, const std::vector<CrossSeamSegment>& crossSeams,
                      uint32_t level)
{
    const size_t charts = images.size();
    if (seams.size() != charts || resolutions.size() != charts)
        throw Error("group weld: the tables do not match the images");
    for (size_t c = 0; c < charts; ++c)
        if (!images[c] || images[c]->size != (resolutions[c] >> level) + 1)
            throw Error("group weld: chart " + std::to_string(c) + "'s image is not level " + std::to_string(level));
    const GroupWeldPlan plan = groupWeldPlan(seams, resolutions, crossSeams, level);
    std::vector<glm::vec3> values(plan.slots);
    for (size_t c = 0; c < charts; ++c)
        for (const glm::uvec2& g : plan.gather[c]) {
            const glm::uvec2 s = perimeterSample(resolutions[c] >> level, g.x);
            values[g.y] = images[c]->at(s.x, s.y);
        }
    double moved = 0.0;
    for (size_t c = 0; c < charts; ++c)
        for (const glm::uvec2& g : plan.scatter[c]) {
            const glm::uvec2 d = perimeterSample(resolutions[c] >> level, g.x);
            moved = std::max(moved, double(glm::distance(images[c]->at(d.x, d.y), values[g.y])));
            images[c]->at(d.x, d.y) = values[g.y];
        }
    return moved;
}

std::vector<uint32_t> seamWeldTable(const ChartSeams& seams, uint32_t resolution)
{
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
            if (p < q)
                parent[q] = p;
            else if (q < p)
                parent[p] = q;
        }
    for (uint32_t t = 0; t < perimeter; ++t) parent[t] = find(t);
    return parent;
}

std::vector<uint32_t> seamWeldTable(const ChartSeams& seams, uint32_t resolution, uint32_t level)
{
    if (level > seams.coarsestWatertightLevel || level >= 32 || (resolution >> level) == 0)
        throw Error("seam weld: level " + std::to_string(level) +
                    " is coarser than the seam's coarsest watertight level " +
                    std::to_string(seams.coarsestWatertightLevel));
    const std::vector<uint32_t> full = seamWeldTable(seams, resolution);
    const uint32_t step = 1u << level;
    std::vector<uint32_t> table(size_t(4) * (resolution >> level));
    for (uint32_t t = 0; t < table.size(); ++t) table[t] = full[size_t(t) * step] / step;
    return table;
}

void weldSeams(GeometryImage& image, const std::vector<uint32_t>& table)
{
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

SeamGap measureSeamGap(const GeometryImage& image, const std::vector<uint32_t>& table)
{
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

}  // namespace ngi
