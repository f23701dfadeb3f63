// The matched border of a group of charts sharing curves: Gu, Gortler, Hoppe 2002 ("Geometry
// Images", section 4) across charts, with the integer lengths of group_lengths.h and the
// interiors of matched_border.h; see ngi/param/matched_group.h.
#include "ngi/param/matched_group.h"

#include "ngi/error.h"
#include "ngi/mesh/cut.h"
#include "ngi/param/disk_topology.h"
#include "ngi/param/group_lengths.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>

namespace ngi {
namespace {

struct EdgeRef {
    long chart = -1, edge = -1;  // a boundary edge: its chart and its position counted from corner 0
    bool operator==(const EdgeRef&) const = default;
};

// One chart's border, positions counted from its corner 0 ("rel", as matchBorder).
struct ChartBorder {
    DiskTopology topology;
    size_t n = 0;
    double R = 0.0;
    std::array<size_t, 4> cornerLoop{}, cornerRel{};
    std::vector<double> tau;    // perimeter parameter of every position (samples), n + 1
    std::vector<EdgeRef> mate;  // per edge (position j to j + 1)
    std::vector<char> node;
    size_t loopOf(size_t rel) const { return (cornerLoop[0] + rel) % n; }
};

struct Segment {
    size_t chart = 0, begin = 0, end = 0;  // positions [begin, end] of its chart
    long mate = -1;                        // global index of the mate segment, -1: open
    size_t cls = 0;
    double natural = 0.0;
    bool first = true;  // the class's first side (its fractions run along it)
};

}  // namespace

namespace {

// keptCorners false: corners 1-3 go where the solved lengths put c R (pinned into the shared
// fractions); true: the maps' corners are nodes and every SIDE of every square is filled to R
// (a class then fills at most two sides, so the same length system applies, per side).
MatchedGroup matchBordersWith(std::span<const GroupChart> charts, uint32_t levelLimit, double maxExtraLengthChange,
                              unsigned threads, uint32_t minLevel, bool keptCorners)
{
    MatchedGroup out;
    const size_t m = charts.size();
    for (size_t c = 0; c < m; ++c) {
        const GroupChart& g = charts[c];
        if (!g.disk || !g.map) throw Error("matched group: chart " + std::to_string(c) + " has no disk or map");
        if (!std::has_single_bit(g.resolution))
            throw Error("matched group: chart " + std::to_string(c) + "'s resolution " + std::to_string(g.resolution) +
                        " is not a power of two");
        if (g.groupVertex.size() != g.disk->mesh.positions.size())
            throw Error("matched group: chart " + std::to_string(c) + "'s group vertex table does not match its mesh");
        MatchedBorder& kept = out.charts.emplace_back();
        kept.uv = g.map->uv;
        kept.corners = g.map->corners;
        kept.report.levelLimit = levelLimit;
    }
    auto leave = [&](const std::string& why) {
        out.matched = false;
        out.problem = why;
        out.crossSeams.clear();
        for (size_t c = 0; c < m; ++c) {
            out.charts[c].uv = charts[c].map->uv;
            out.charts[c].corners = charts[c].map->corners;
            out.charts[c].seams = {};
            out.charts[c].report.matched = false;
            out.charts[c].report.problem = why;
        }
        return out;
    };
    if (m == 0) return leave("no chart");

    // Every chart's border: corners, perimeter parameters, its own cut paths.
    std::vector<ChartBorder> border(m);
    for (size_t c = 0; c < m; ++c) {
        const GroupChart& g = charts[c];
        ChartBorder& b = border[c];
        b.topology = analyzeDisk(*g.disk);
        const std::vector<uint32_t>& loop = g.disk->boundaryLoop;
        b.n = loop.size();
        b.R = g.resolution;
        for (int k = 0; k < 4; ++k) {
            const int32_t p = b.topology.boundaryPosition[g.map->corners[k]];
            if (p < 0)
                throw Error("matched group: chart " + std::to_string(c) + "'s corner " + std::to_string(k) +
                            " is not on its border");
            b.cornerLoop[k] = size_t(p);
        }
        for (int k = 0; k < 4; ++k) b.cornerRel[k] = (b.cornerLoop[k] + b.n - b.cornerLoop[0]) % b.n;
        for (int k = 1; k < 4; ++k)
            if (b.cornerRel[k] <= b.cornerRel[k - 1])
                return leave("chart " + std::to_string(c) + "'s corners are not in loop order");
        b.tau.assign(b.n + 1, 0.0);
        for (size_t j = 0; j < b.n; ++j) {
            int s = 0;
            while (s < 3 && b.cornerRel[s + 1] <= j) ++s;
            const glm::dvec2 x = g.map->uv[loop[b.loopOf(j)]];
            const double along = s == 0 ? x.x : s == 1 ? x.y : s == 2 ? 1.0 - x.x : 1.0 - x.y;
            b.tau[j] = (s + std::clamp(along, 0.0, 1.0)) * b.R;
        }
        for (int k = 0; k < 4; ++k) b.tau[b.cornerRel[k]] = k * b.R;
        b.tau[b.n] = 4 * b.R;
        for (size_t j = 0; j < b.n; ++j)
            if (b.tau[j + 1] < b.tau[j])
                return leave("chart " + std::to_string(c) + "'s boundary is not in order along the border");
        b.mate.assign(b.n, EdgeRef{});
        for (const auto& [e1, e2] : findSeamEdges(*g.disk).mates) {
            const size_t r1 = (e1 + b.n - b.cornerLoop[0]) % b.n, r2 = (e2 + b.n - b.cornerLoop[0]) % b.n;
            b.mate[r1] = {long(c), long(r2)};
            b.mate[r2] = {long(c), long(r1)};
        }
    }
    // Shared curves: an open edge of one chart whose two group vertices bound an open edge of
    // another (traversed the other way, as two sides of a cut are).
    {
        std::map<std::pair<uint32_t, uint32_t>, EdgeRef> open;
        for (size_t c = 0; c < m; ++c) {
            const ChartBorder& b = border[c];
            const std::vector<uint32_t>& loop = charts[c].disk->boundaryLoop;
            for (size_t j = 0; j < b.n; ++j) {
                if (b.mate[j].chart >= 0) continue;
                const uint32_t u = charts[c].groupVertex[loop[b.loopOf(j)]],
                               v = charts[c].groupVertex[loop[b.loopOf(j + 1)]];
                if (u == kNoGroupVertex || v == kNoGroupVertex) continue;
                const auto [it, inserted] = open.try_emplace(std::minmax(u, v), EdgeRef{long(c), long(j)});
                if (inserted || it->second.chart == long(c)) continue;
                const EdgeRef other = it->second;
                border[c].mate[j] = other;
                border[size_t(other.chart)].mate[size_t(other.edge)] = {long(c), long(j)};
                open.erase(it);
            }
        }
    }

    // Nodes: each chart's corner 0, breaks of the mate runs, slit tips, and their mates in
    // whichever chart they are, until no new node appears.
    std::vector<EdgeRef> queue;
    for (size_t c = 0; c < m; ++c) {
        ChartBorder& b = border[c];
        b.node.assign(b.n, 0);
        b.node[0] = 1;
        if (keptCorners)
            for (int k = 1; k < 4; ++k) b.node[b.cornerRel[k]] = 1;
        for (size_t j = 0; j < b.n; ++j) {
            const EdgeRef in = b.mate[(j + b.n - 1) % b.n], outMate = b.mate[j];
            if ((in.chart < 0) != (outMate.chart < 0))
                b.node[j] = 1;
            else if (in.chart >= 0) {
                const size_t nIn = border[size_t(in.chart)].n;
                const EdgeRef continued{in.chart, long((size_t(in.edge) + nIn - 1) % nIn)};
                const EdgeRef tip{long(c), long((j + b.n - 1) % b.n)};
                if (!(outMate == continued) || outMate == tip) b.node[j] = 1;
            }
        }
        for (size_t j = 0; j < b.n; ++j)
            if (b.node[j]) queue.push_back({long(c), long(j)});
    }
    while (!queue.empty()) {
        const EdgeRef at = queue.back();
        queue.pop_back();
        const ChartBorder& b = border[size_t(at.chart)];
        const size_t j = size_t(at.edge);
        const EdgeRef viaOut = b.mate[j];
        const EdgeRef viaIn = b.mate[(j + b.n - 1) % b.n];
        for (EdgeRef to : {viaOut.chart >= 0
                               ? EdgeRef{viaOut.chart, long((size_t(viaOut.edge) + 1) % border[size_t(viaOut.chart)].n)}
                               : EdgeRef{},
                           viaIn}) {
            if (to.chart < 0) continue;
            char& mark = border[size_t(to.chart)].node[size_t(to.edge)];
            if (!mark) {
                mark = 1;
                queue.push_back(to);
            }
        }
    }

    // Segments between consecutive nodes of every chart, paired with their mates.
    std::vector<Segment> segments;
    std::vector<std::map<size_t, size_t>> segmentAt(m);  // begin position -> global segment
    std::vector<size_t> firstSegment(m + 1, 0);
    for (size_t c = 0; c < m; ++c) {
        const ChartBorder& b = border[c];
        firstSegment[c] = segments.size();
        for (size_t j = 0; j < b.n; ++j)
            if (b.node[j]) {
                if (segments.size() > firstSegment[c]) segments.back().end = j;
                segmentAt[c][j] = segments.size();
                Segment& s = segments.emplace_back();
                s.chart = c;
                s.begin = j;
            }
        segments.back().end = b.n;
    }
    firstSegment[m] = segments.size();
    for (Segment& s : segments) s.natural = border[s.chart].tau[s.end] - border[s.chart].tau[s.begin];
    for (size_t i = 0; i < segments.size(); ++i) {
        Segment& s = segments[i];
        const ChartBorder& b = border[s.chart];
        const EdgeRef startMate = b.mate[s.begin];
        if (startMate.chart < 0) continue;
        const EdgeRef lastMate = b.mate[s.end - 1];
        const auto found = segmentAt[size_t(lastMate.chart)].find(size_t(lastMate.edge));
        if (lastMate.chart != startMate.chart || found == segmentAt[size_t(lastMate.chart)].end() || found->second == i)
            return leave("a shared curve's two sides do not start at nodes");
        const Segment& other = segments[found->second];
        if (other.end - other.begin != s.end - s.begin || size_t(startMate.edge) + 1 != other.end)
            return leave("a shared curve's two sides differ in their vertices");
        s.mate = long(found->second);
    }

    // Length classes (one per mate pair, one per open segment) and the charts they fill.
    // What a class fills: a chart's perimeter, or with kept corners one side of a chart.
    auto unitOf = [&](const Segment& s) {
        if (!keptCorners) return uint32_t(s.chart);
        uint32_t side = 0;
        while (side < 3 && border[s.chart].cornerRel[side + 1] <= s.begin) ++side;
        return uint32_t(4 * s.chart + side);
    };
    std::vector<BorderLengthClass> classes;
    std::vector<int> members;
    for (size_t i = 0; i < segments.size(); ++i) {
        Segment& s = segments[i];
        if (s.mate >= 0 && size_t(s.mate) < i) {
            const Segment& other = segments[size_t(s.mate)];
            s.cls = other.cls;
            s.first = false;
            BorderLengthClass& k = classes[s.cls];
            k.target = 0.5 * (k.target + s.natural);
            ++members[s.cls];
            if (unitOf(other) == unitOf(s))
                k.uses = {{unitOf(s), 2}};
            else
                k.uses.push_back({unitOf(s), 1});
            if (other.chart != s.chart) ++out.sharedCurves;
            continue;
        }
        s.cls = classes.size();
        classes.push_back({s.natural, 1.0, {{unitOf(s), 1}}});
        members.push_back(1);
    }
    for (size_t k = 0; k < classes.size(); ++k)
        classes[k].weight = double(members[k]) / std::max(classes[k].target, 1.0);
    for (const Segment& s : segments) {
        MatchedBorderReport& r = out.charts[s.chart].report;
        if (s.mate < 0)
            ++r.openSegments;
        else if (s.first && segments[size_t(s.mate)].chart == s.chart)
            ++r.cutPaths;
        r.mismatch += std::abs(classes[s.cls].target - s.natural) / (4 * border[s.chart].R);
    }

    // A plan at unit q: lengths, segment starts, corners and every vertex's perimeter position.
    struct Plan {
        uint32_t q = 1;
        std::vector<long> x;
        std::vector<double> start;                    // per global segment
        std::vector<std::array<size_t, 4>> cornerAt;  // per chart: positions of its corners
        std::vector<std::vector<double>> tau;         // per chart: new perimeter positions
        size_t walks = 0;
    };
    auto naturalFraction = [&](const Segment& s, size_t index) {
        const std::vector<double>& tau = border[s.chart].tau;
        return s.natural > 0.0 ? (tau[s.begin + index] - tau[s.begin]) / s.natural
                               : double(index) / double(s.end - s.begin);
    };
    // The first side of every class, and its shared natural fraction at vertex `index`.
    std::vector<size_t> firstOf(classes.size());
    for (size_t i = segments.size(); i-- > 0;)
        if (segments[i].first) firstOf[segments[i].cls] = i;
    auto sharedNatural = [&](size_t cls, size_t index) {
        const Segment& a = segments[firstOf[cls]];
        const double f = naturalFraction(a, index);
        return a.mate >= 0 ? 0.5 * (f + 1.0 - naturalFraction(segments[size_t(a.mate)], a.end - a.begin - index)) : f;
    };
    // The fractions along a class's first side through its pins (index, fraction), monotone;
    // empty when the pins are out of order.
    auto fractions = [&](size_t cls, std::vector<std::pair<size_t, double>> pins) {
        const Segment& a = segments[firstOf[cls]];
        const size_t len = a.end - a.begin;
        pins.push_back({0, 0.0});
        pins.push_back({len, 1.0});
        std::vector<double> phi(len + 1);
        for (size_t index = 0; index <= len; ++index) phi[index] = sharedNatural(cls, index);
        return pinnedFractions(phi, std::move(pins));
    };
    std::string why;  // why the last plan failed
    // Corners and every boundary vertex's position for the lengths p.x (false if none fits).
    auto place = [&](Plan& p) -> bool {
        p.start.assign(segments.size(), 0.0);
        for (size_t c = 0; c < m; ++c) {
            double t = 0.0;
            for (size_t i = firstSegment[c]; i < firstSegment[c + 1]; ++i) {
                p.start[i] = t;
                t += double(p.x[segments[i].cls]) * p.q;
            }
        }
        // Corners 1-3 of every chart: a node at c R, or the vertex nearest c R pinned there.
        std::vector<std::vector<std::pair<size_t, double>>> pins(classes.size());
        p.cornerAt.assign(m, {});
        for (size_t c = 0; c < m; ++c) {
            p.cornerAt[c][0] = 0;
            for (int k = 1; k < 4; ++k) {
                const double at = k * border[c].R;
                size_t i = firstSegment[c];
                while (i + 1 < firstSegment[c + 1] && p.start[i + 1] <= at) ++i;
                const Segment& s = segments[i];
                if (p.start[i] == at) {
                    p.cornerAt[c][k] = s.begin;
                    continue;
                }
                const size_t len = s.end - s.begin;
                const double L = double(p.x[s.cls]) * p.q;
                std::vector<std::pair<double, size_t>> candidates;
                for (size_t index = 1; index < len; ++index) {
                    const double along =
                        s.first ? sharedNatural(s.cls, index) : 1.0 - sharedNatural(s.cls, len - index);
                    candidates.push_back({std::abs(p.start[i] + L * along - at), index});
                }
                std::sort(candidates.begin(), candidates.end());
                bool placed = false;
                for (const auto& [distance, index] : candidates) {
                    const double fraction = (at - p.start[i]) / L;
                    pins[s.cls].push_back(s.first ? std::pair{index, fraction}
                                                  : std::pair{len - index, 1.0 - fraction});
                    if (!fractions(s.cls, pins[s.cls]).empty()) {
                        p.cornerAt[c][k] = s.begin + index;
                        placed = true;
                        break;
                    }
                    pins[s.cls].pop_back();
                }
                if (!placed) {  // one edge spans the corner, or no vertex keeps the fractions monotone
                    why = "chart " + std::to_string(c) + "'s corner " + std::to_string(k) +
                        " has no vertex to go on (a segment of " + std::to_string(len) + " edges, " +
                        std::to_string(long(L)) + " samples, " +
                        (s.mate < 0                                ? "open"
                             : segments[size_t(s.mate)].chart == c ? "a cut path"
                                                                   : "a shared curve") +
                        ")";
                    return false;
                }
            }
        }
        // Every boundary vertex's new position, nodes and corners exact.
        std::vector<std::vector<double>> f(classes.size());
        for (size_t k = 0; k < classes.size(); ++k) f[k] = fractions(k, pins[k]);
        p.tau.assign(m, {});
        for (size_t c = 0; c < m; ++c) {
            const ChartBorder& b = border[c];
            std::vector<double>& tau = p.tau[c];
            tau.assign(b.n + 1, 0.0);
            for (size_t i = firstSegment[c]; i < firstSegment[c + 1]; ++i) {
                const Segment& s = segments[i];
                const size_t len = s.end - s.begin;
                const double L = double(p.x[s.cls]) * p.q;
                for (size_t index = 0; index <= len; ++index)
                    tau[s.begin + index] = p.start[i] + L * (s.first ? f[s.cls][index] : 1.0 - f[s.cls][len - index]);
                tau[s.begin] = p.start[i];
            }
            for (int k = 1; k < 4; ++k) tau[p.cornerAt[c][k]] = k * b.R;
            tau[b.n] = 4 * b.R;
            for (size_t j = 1; j <= b.n; ++j)
                if (!(tau[j] > tau[j - 1])) {
                    why = "chart " + std::to_string(c) + "'s border would fold";
                    return false;
                }
        }
        return true;
    };
    auto plan = [&](uint32_t q, Plan& p) -> bool {
        std::vector<long> perimeters;  // per unit: a chart's 4 R, or each of its sides' R
        for (size_t c = 0; c < m; ++c)
            for (int side = 0; side < (keptCorners ? 4 : 1); ++side)
                perimeters.push_back(long((keptCorners ? 1 : 4) * charts[c].resolution / q));
        const GroupLengths lengths = solveGroupLengths(classes, perimeters, q);
        if (!lengths.solved) {
            why = lengths.problem;
            return false;
        }
        p.q = q;
        p.x = lengths.units;
        p.walks = lengths.repairWalks;
        if (place(p)) return true;
        // A corner fell on a single edge or on a vertex whose mirror breaks the fractions: move
        // one unit between two classes that fill the same charts the same number of times (every
        // perimeter stays filled) and place again, cheapest moves first (as matchBorder).
        const std::vector<long> solved = p.x;
        auto cost = [&](size_t k, long d) {
            const double was = double(solved[k]) * q - classes[k].target,
                         now = double(solved[k] + d) * q - classes[k].target;
            return classes[k].weight * (now * now - was * was);
        };
        std::vector<std::pair<double, std::pair<size_t, size_t>>> moves;
        for (size_t ka = 0; ka < classes.size(); ++ka)
            for (size_t kb = 0; kb < classes.size(); ++kb) {
                if (ka == kb || solved[kb] <= 1) continue;
                auto ua = classes[ka].uses, ub = classes[kb].uses;
                std::sort(ua.begin(), ua.end());
                std::sort(ub.begin(), ub.end());
                if (ua == ub) moves.push_back({cost(ka, 1) + cost(kb, -1), {ka, kb}});
            }
        std::sort(moves.begin(), moves.end());
        for (size_t i = 0; i < moves.size() && i < 256; ++i) {
            p.x = solved;
            ++p.x[moves[i].second.first];
            --p.x[moves[i].second.second];
            if (place(p)) return true;
        }
        return false;
    };
    double totalPerimeter = 0.0;
    for (const ChartBorder& b : border) totalPerimeter += 4 * b.R;
    auto lengthChange = [&](const Plan& p) {
        double change = 0.0;
        for (const Segment& s : segments) change += std::abs(double(p.x[s.cls]) * p.q - s.natural);
        return change / totalPerimeter;
    };

    Plan best;
    if (!plan(1, best))
        return leave("the shared borders have no integer matching at full resolution (" +
                     std::to_string(segments.size()) + " segments, " + std::to_string(out.sharedCurves) +
                     " shared curves): " + why);
    const double fullResolutionChange = lengthChange(best);
    uint32_t top = levelLimit;
    for (const GroupChart& g : charts) top = std::min(top, uint32_t(std::countr_zero(g.resolution)));
    for (uint32_t k = 1; k <= top; ++k) {
        Plan trial;
        if (!plan(1u << k, trial)) continue;
        if (k <= minLevel || lengthChange(trial) <= fullResolutionChange + maxExtraLengthChange)
            best = std::move(trial);
    }
    out.level = uint32_t(std::countr_zero(best.q));
    out.repairWalks = best.walks;

    // Each chart's interior follows its moved border.
    for (size_t c = 0; c < m; ++c) {
        const ChartBorder& b = border[c];
        MatchedBorder& chart = out.charts[c];
        MatchedBorderReport& report = chart.report;
        report.level = out.level;
        report.movedCorners = true;
        for (size_t i = firstSegment[c]; i < firstSegment[c + 1]; ++i)
            report.lengthChange += std::abs(double(best.x[segments[i].cls]) * best.q - segments[i].natural) / (4 * b.R);
        const std::vector<uint32_t>& loop = charts[c].disk->boundaryLoop;
        std::vector<glm::dvec2> boundaryUv(b.n);
        for (size_t j = 0; j < b.n; ++j) {
            boundaryUv[b.loopOf(j)] = perimeterUv(best.tau[c][j], charts[c].resolution);
            report.maxBorderMove = std::max(report.maxBorderMove, std::abs(best.tau[c][j] - b.tau[j]) / b.R);
        }
        std::vector<glm::dvec2> uv;
        if (!solveMatchedInterior(*charts[c].disk, b.topology, *charts[c].map, boundaryUv, threads, report, uv))
            return leave("chart " + std::to_string(c) + ": the interior solve after moving the border flips " +
                         std::to_string(report.flippedTriangles) + " triangles");
        chart.uv = std::move(uv);
        for (int k = 0; k < 4; ++k) chart.corners[k] = loop[b.loopOf(best.cornerAt[c][k])];
        chart.seams.matched = true;
        chart.seams.coarsestWatertightLevel = out.level;
        report.matched = true;
    }
    for (size_t i = 0; i < segments.size(); ++i) {
        const Segment& s = segments[i];
        if (s.mate < 0 || !s.first) continue;
        const Segment& other = segments[size_t(s.mate)];
        const uint32_t length = uint32_t(best.x[s.cls]) * best.q;
        const uint32_t a = uint32_t(std::lround(best.start[i])), b = uint32_t(std::lround(best.start[size_t(s.mate)]));
        if (other.chart == s.chart)
            out.charts[s.chart].seams.segments.push_back({a, b, length});
        else
            out.crossSeams.push_back({uint32_t(s.chart), a, uint32_t(other.chart), b, length});
    }
    out.matched = true;
    return out;
}

}  // namespace

MatchedGroup matchBorders(std::span<const GroupChart> charts, uint32_t levelLimit, double maxExtraLengthChange,
                          unsigned threads, uint32_t minLevel)
{
    // Free corners fit most groups; where a corner then falls on a shared stretch with no vertex
    // to pin (a one-edge segment), the maps' own corners are kept and every side is solved.
    MatchedGroup free = matchBordersWith(charts, levelLimit, maxExtraLengthChange, threads, minLevel, false);
    if (free.matched) return free;
    MatchedGroup kept = matchBordersWith(charts, levelLimit, maxExtraLengthChange, threads, minLevel, true);
    if (kept.matched) return kept;
    free.problem += "; with the maps' corners kept: " + kept.problem;
    for (MatchedBorder& chart : free.charts) chart.report.problem = free.problem;
    return free;
}

}  // namespace ngi
