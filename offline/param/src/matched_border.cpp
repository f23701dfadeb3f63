// ngi offline: matched boundary parameterization (Gu, Gortler, Hoppe 2002, "Geometry Images",
// section 4: cut nodes on grid points, equal parametric length for both sides of every cut
// path, boundary samples at equal fractions so mates sample the same surface points), with
// the interior re-solved by Floater's mean-value weights (Floater 2003, "Mean value
// coordinates") of the current layout. See matched_border.h.
#include "ngi/param/matched_border.h"

#include "ngi/error.h"
#include "ngi/mesh/cut.h"
#include "ngi/param/disk_topology.h"
#include "ngi/param/distortion.h"
#include "ngi/param/fixed_border_maps.h"
#include "ngi/param/optimal_transport.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <chrono>
#include <array>
#include <bit>
#include <cmath>
#include <map>
#include <numeric>

namespace ngi {
namespace {

// A run of the boundary between two consecutive nodes, in loop positions counted from
// corner 0 ("rel" positions): [begin, end], end <= n.
struct Segment {
    size_t begin = 0, end = 0;
    long mate = -1;        // index of the mate segment, -1 for an open (input boundary) segment
    size_t cls = 0;        // length class: a mate pair shares one
    double natural = 0.0;  // length on the border before matching (samples)
};

// Where corner c (1..3; corner 0 is the origin node) sits: on the node that starts segment
// `segment` (onNode), or strictly inside that segment.
struct CornerPlace {
    size_t segment = 0;
    bool onNode = false;
    bool free = false;  // not constrained by the length solve (placed afterwards)
};

// Integer segment lengths n_c >= 1 (units of q samples), close to the targets in weighted
// least squares, such that the segments fill the perimeter (4R / q units) and the corners
// fall where the map has them: a corner on a node exactly at c R, a corner inside a segment
// strictly inside it (its vertex then gets c R by the fraction function). Rounding, then
// greedy repair moves of one or two classes by +-1 that strictly reduce the total violation.
// False if no move helps.
bool solveLengths(const std::vector<Segment>& segments, const std::vector<double>& targets,
                  const std::vector<double>& weights, const std::array<CornerPlace, 4>& corners, uint32_t resolution,
                  uint32_t q, std::vector<long>& n)
{
    const long side = long(resolution / q);
    const size_t classCount = targets.size();
    n.assign(classCount, 1);
    for (size_t c = 0; c < classCount; ++c) n[c] = std::max(1L, long(std::llround(targets[c] / q)));
    auto violation = [&](const std::vector<long>& x) {
        long v = 0, prefix = 0;
        std::array<long, 4> before{}, after{};  // prefix sums at the corners' segments
        for (size_t k = 0; k < segments.size(); ++k) {
            for (int c = 1; c < 4; ++c)
                if (corners[c].segment == k) before[c] = prefix;
            prefix += x[segments[k].cls];
            for (int c = 1; c < 4; ++c)
                if (corners[c].segment == k) after[c] = prefix;
        }
        v += std::abs(prefix - 4 * side);
        for (int c = 1; c < 4; ++c) {
            const long at = c * side;
            if (corners[c].free) continue;
            if (corners[c].onNode)
                v += std::abs(before[c] - at);
            else
                v += std::max(0L, before[c] - (at - 1)) + std::max(0L, (at + 1) - after[c]);
        }
        return v;
    };
    auto costDelta = [&](size_t c, long delta) {
        const double was = double(n[c]) * q - targets[c], now = double(n[c] + delta) * q - targets[c];
        return weights[c] * (now * now - was * was);
    };
    long current = violation(n);
    for (size_t iteration = 0; current > 0; ++iteration) {
        if (iteration > 8 * classCount + 4 * size_t(side) + 256) return false;  // moves are single units
        long bestGain = 0;
        double bestCost = 0.0;
        std::array<std::pair<long, long>, 2> best{{{-1, 0}, {-1, 0}}};
        std::vector<long> trial = n;
        auto consider = [&](long c1, long d1, long c2, long d2) {
            trial[size_t(c1)] += d1;
            if (c2 >= 0) trial[size_t(c2)] += d2;
            const long gain = current - violation(trial);
            trial[size_t(c1)] -= d1;
            if (c2 >= 0) trial[size_t(c2)] -= d2;
            if (gain <= 0) return;
            const double cost = costDelta(size_t(c1), d1) + (c2 >= 0 ? costDelta(size_t(c2), d2) : 0.0);
            if (gain > bestGain || (gain == bestGain && cost < bestCost)) {
                bestGain = gain, bestCost = cost;
                best = {{{c1, d1}, {c2, d2}}};
            }
        };
        for (long c = 0; c < long(classCount); ++c)
            for (long delta : {-1L, 1L})
                if (n[size_t(c)] + delta >= 1) consider(c, delta, -1, 0);
        if (bestGain == 0 && classCount <= 256)
            for (long c1 = 0; c1 < long(classCount); ++c1)
                for (long c2 = c1 + 1; c2 < long(classCount); ++c2)
                    for (long d1 : {-1L, 1L})
                        for (long d2 : {-1L, 1L})
                            if (n[size_t(c1)] + d1 >= 1 && n[size_t(c2)] + d2 >= 1) consider(c1, d1, c2, d2);
        if (bestGain == 0) return false;
        for (const auto& [c, delta] : best)
            if (c >= 0) n[size_t(c)] += delta;
        current = violation(n);
    }
    return true;
}

// Rounds of transport after the border moved (each from the previous map), and the border
// length change (fraction of the perimeter) below which it is not tried. One round: a second
// one never paid where we measured (camel 0.507 -> 0.506 for 6.4 s; helmet, elephant, lion:
// rejected after 7-11 s), so it only cost time.
constexpr int kTransportRounds = 1;
constexpr double kRetransportAbove = 0.15;

}  // namespace

glm::dvec2 perimeterUv(double t, uint32_t resolution)
{
    const double r = resolution;
    if (t <= r) return {t / r, 0.0};
    if (t <= 2 * r) return {1.0, (t - r) / r};
    if (t <= 3 * r) return {(3 * r - t) / r, 1.0};
    return {0.0, (4 * r - t) / r};
}

std::vector<double> pinnedFractions(const std::vector<double>& phi, std::vector<std::pair<size_t, double>> pins)
{
    std::sort(pins.begin(), pins.end());
    // A corner and its mate can be the same pin (a corner's mate vertex is a corner too).
    pins.erase(std::unique(pins.begin(), pins.end(),
                           [](const auto& a, const auto& b) {
                               return a.first == b.first && std::abs(a.second - b.second) < 1e-12;
                           }),
               pins.end());
    for (size_t k = 1; k < pins.size(); ++k)
        if (!(pins[k].first > pins[k - 1].first && pins[k].second > pins[k - 1].second)) return std::vector<double>();
    std::vector<double> f(phi.size());
    constexpr double kStrict = 1e-3;  // blend with index spacing: no boundary edge collapses
    for (size_t k = 1; k < pins.size(); ++k) {
        const auto [i0, f0] = pins[k - 1];
        const auto [i1, f1] = pins[k];
        for (size_t index = i0; index <= i1; ++index) {
            const double u = double(index - i0) / double(i1 - i0);
            const double span = phi[i1] - phi[i0];
            const double w = span > 0.0 ? (phi[index] - phi[i0]) / span : u;
            f[index] = f0 + (f1 - f0) * ((1.0 - kStrict) * w + kStrict * u);
        }
    }
    return f;
}

bool solveMatchedInterior(const DiskMesh& disk, const DiskTopology& topology, const SquareMap& map,
                          const std::vector<glm::dvec2>& boundaryUv, unsigned threads, MatchedBorderReport& report,
                          std::vector<glm::dvec2>& uv)
{
    const std::vector<DirectedWeight> weightsMv = meanValueWeights(disk, map.uv);
    uv = solveFixedBorderMap(disk, topology, boundaryUv, weightsMv, false, false);
    // Mean-value weights of a layout with near-degenerate triangles can still fold a few of
    // them once the border moves: raise the small weights towards Tutte's (as untangle.cpp).
    for (const double floor : {1e-3, 1e-2, 1e-1, 1.0}) {
        if (countFlippedTriangles(disk, uv) == 0) break;
        uv = solveFixedBorderMap(disk, topology, boundaryUv, weightsMv, false, true, nullptr, floor);
        for (glm::dvec2& x : uv) x = glm::clamp(x, glm::dvec2(0.0), glm::dvec2(1.0));
    }
    report.flippedTriangles = countFlippedTriangles(disk, uv);
    if (report.flippedTriangles > 0) return false;
    // The moved border stretches some of the map's strips and squeezes others: transport the
    // interior once more (the paper's Algorithm 1 from the matched map; sites are nearly in
    // place, so Newton needs few steps), keeping the matched border, and keep the result if it
    // is bijective and preserves area better.
    report.areaDistortionMeanBefore = measureDistortion(disk.mesh, uv).areaMean;
    // Below this change of the border lengths the transport did not pay on real meshes (bunny00
    // 7.9%, fandisk: rejected, 10-20 s at 1024); above it (elephant 67%, 3torus 58%) it did.
    if (report.lengthChange > kRetransportAbove) try {
            std::vector<double> targets = vertexAreas(disk.mesh);
            double total = 0.0;
            for (double a : targets) total += a;
            for (double& a : targets) a /= total;
            double best = report.areaDistortionMeanBefore;
            for (int round = 0; round < kTransportRounds; ++round) {
                const auto roundStart = std::chrono::steady_clock::now();
                std::vector<glm::dvec2> sites = uv;
                for (glm::dvec2& x : sites) x = glm::clamp(x, glm::dvec2(0.0), glm::dvec2(1.0));
                OptimalTransportOptions transport;
                transport.threads = threads;
                const OptimalTransportResult ot = semiDiscreteTransport(sites, targets, transport);
                std::vector<glm::dvec2> moved = uv;
                for (size_t v = 0; v < moved.size(); ++v)
                    if (topology.boundaryPosition[v] < 0)
                        moved[v] = glm::clamp(ot.centroid[v], glm::dvec2(0.0), glm::dvec2(1.0));
                if (countFlippedTriangles(disk, moved) > 0) {
                    const std::vector<DirectedWeight> relax = meanValueWeights(disk, moved);
                    for (const double floor : {1e-3, 1e-2, 1e-1}) {
                        std::vector<glm::dvec2> relaxed =
                            solveFixedBorderMap(disk, topology, boundaryUv, relax, false, true, nullptr, floor);
                        for (glm::dvec2& x : relaxed) x = glm::clamp(x, glm::dvec2(0.0), glm::dvec2(1.0));
                        if (countFlippedTriangles(disk, relaxed) == 0) {
                            moved.swap(relaxed);
                            break;
                        }
                    }
                }
                const double after = measureDistortion(disk.mesh, moved).areaMean;
                report.roundAreaDistortionMean.push_back(after);
                report.roundSeconds.push_back(
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - roundStart).count());
                if (countFlippedTriangles(disk, moved) != 0 || !(after < best)) break;
                best = after;
                uv.swap(moved);
                report.retransported = true;
                report.transportIterations += ot.iterations;
                ++report.transportRounds;
            }
        } catch (const Error&) {
            // The mean-value map stands; the report says the transport did not run.
        }
    for (size_t v = 0; v < uv.size(); ++v)
        if (topology.boundaryPosition[v] < 0)
            report.maxInteriorMove = std::max(report.maxInteriorMove, glm::distance(uv[v], map.uv[v]));

    return true;
}

MatchedBorder matchBorder(const DiskMesh& disk, const SquareMap& map, uint32_t resolution, uint32_t levelLimit,
                          double maxExtraLengthChange, unsigned threads)
{
    MatchedBorder out;
    out.uv = map.uv;
    out.corners = map.corners;
    MatchedBorderReport& report = out.report;
    report.levelLimit = levelLimit;
    auto leave = [&](const std::string& why) {
        report.matched = false;
        report.problem = why;
        out.seams = {};
        out.uv = map.uv;
        out.corners = map.corners;
        return out;
    };
    if (!std::has_single_bit(resolution))
        throw Error("matched border: resolution " + std::to_string(resolution) + " is not a power of two");
    const DiskTopology topology = analyzeDisk(disk);
    const std::vector<uint32_t>& loop = disk.boundaryLoop;
    const size_t n = loop.size();
    const double R = resolution;

    // Corners in loop order, positions counted from corner 0.
    std::array<size_t, 4> cornerLoop{};
    for (int c = 0; c < 4; ++c) {
        const int32_t p = topology.boundaryPosition[map.corners[c]];
        if (p < 0) throw Error("matched border: corner " + std::to_string(c) + " is not a boundary vertex");
        cornerLoop[c] = size_t(p);
    }
    auto loopOf = [&](size_t rel) { return (cornerLoop[0] + rel) % n; };
    std::array<size_t, 4> cornerRel{};
    for (int c = 0; c < 4; ++c) cornerRel[c] = (cornerLoop[c] + n - cornerLoop[0]) % n;
    for (int c = 1; c < 4; ++c)
        if (cornerRel[c] <= cornerRel[c - 1]) throw Error("matched border: the corners are not in loop order");

    // Perimeter parameter of every boundary position (samples), corners exact.
    std::vector<double> tau(n + 1);
    for (size_t j = 0; j < n; ++j) {
        int s = 0;
        while (s < 3 && cornerRel[s + 1] <= j) ++s;
        const glm::dvec2 x = map.uv[loop[loopOf(j)]];
        const double along = s == 0 ? x.x : s == 1 ? x.y : s == 2 ? 1.0 - x.x : 1.0 - x.y;
        tau[j] = (s + std::clamp(along, 0.0, 1.0)) * R;
    }
    for (int c = 0; c < 4; ++c) tau[cornerRel[c]] = c * R;
    tau[n] = 4 * R;
    for (size_t j = 0; j < n; ++j)
        if (tau[j + 1] < tau[j]) return leave("the boundary is not in order along the border");

    // Mate of every boundary edge (edge j runs from position j to j + 1).
    std::vector<long> mate(n, -1);
    const SeamEdges seam = findSeamEdges(disk);
    for (const auto& [e1, e2] : seam.mates) {
        const size_t r1 = (e1 + n - cornerLoop[0]) % n, r2 = (e2 + n - cornerLoop[0]) % n;
        mate[r1] = long(r2), mate[r2] = long(r1);
    }

    // Nodes: corner 0 (the origin), breaks of the mate run, slit tips, and the mates of all
    // of them. Corners 1-3 need not be nodes: inside a segment, the fraction function puts
    // them on their corner.
    std::vector<char> node(n, 0);
    node[0] = 1;
    for (size_t j = 0; j < n; ++j) {
        const long in = mate[(j + n - 1) % n], outMate = mate[j];
        if ((in < 0) != (outMate < 0))
            node[j] = 1;
        else if (in >= 0 && (outMate != long((size_t(in) + n - 1) % n) || outMate == long((j + n - 1) % n)))
            node[j] = 1;
    }
    std::vector<size_t> queue;
    for (size_t j = 0; j < n; ++j)
        if (node[j]) queue.push_back(j);
    while (!queue.empty()) {
        const size_t j = queue.back();
        queue.pop_back();
        const long viaOut = mate[j] >= 0 ? long((size_t(mate[j]) + 1) % n) : -1;
        const long viaIn = mate[(j + n - 1) % n];
        for (long m : {viaOut, viaIn})
            if (m >= 0 && !node[size_t(m)]) {
                node[size_t(m)] = 1;
                queue.push_back(size_t(m));
            }
    }

    // Segments between consecutive nodes, paired with their mates.
    std::vector<Segment> segments;
    std::map<size_t, size_t> segmentAt;  // begin position -> segment
    for (size_t j = 0; j < n; ++j)
        if (node[j]) {
            if (!segments.empty()) segments.back().end = j;
            segmentAt[j] = segments.size();
            segments.emplace_back().begin = j;
        }
    segments.back().end = n;
    for (Segment& s : segments) s.natural = tau[s.end] - tau[s.begin];
    for (size_t i = 0; i < segments.size(); ++i) {
        Segment& s = segments[i];
        if (mate[s.begin] < 0) continue;
        const auto found = segmentAt.find(size_t(mate[s.end - 1]));
        if (found == segmentAt.end() || found->second == i)
            return leave("a cut path's two sides do not start at nodes");
        const Segment& m = segments[found->second];
        if (m.end - m.begin != s.end - s.begin || size_t(mate[s.begin]) + 1 != m.end)
            return leave("a cut path's two sides differ in their vertices");
        s.mate = long(found->second);
    }
    std::array<CornerPlace, 4> keptCorners{};
    for (int c = 1; c < 4; ++c) {
        size_t k = 0;
        while (k + 1 < segments.size() && segments[k + 1].begin <= cornerRel[c]) ++k;
        keptCorners[c] = {k, segments[k].begin == cornerRel[c], false};
    }

    // Length classes: one per mate pair, one per open segment.
    std::vector<double> targets, weights;
    std::vector<std::pair<size_t, double>> shorterTargets;  // one-edge paths: their shorter side
    std::vector<int> members;
    for (size_t i = 0; i < segments.size(); ++i) {
        Segment& s = segments[i];
        if (s.mate >= 0 && size_t(s.mate) < i) {
            s.cls = segments[size_t(s.mate)].cls;
            if (s.end - s.begin == 1) shorterTargets.push_back({s.cls, std::min(targets[s.cls], s.natural)});
            targets[s.cls] = 0.5 * (targets[s.cls] + s.natural);
            ++members[s.cls];
            continue;
        }
        s.cls = targets.size();
        targets.push_back(s.natural);
        members.push_back(1);
        if (s.mate >= 0)
            ++report.cutPaths;
        else
            ++report.openSegments;
    }
    for (size_t c = 0; c < targets.size(); ++c) weights.push_back(double(members[c]) / std::max(targets[c], 1.0));
    for (const Segment& s : segments) report.mismatch += std::abs(targets[s.cls] - s.natural) / (4 * R);

    // A plan: integer lengths (units of q) and where corners 1-3 sit.
    struct Plan {
        std::vector<long> x;
        uint32_t q = 1;
        std::array<CornerPlace, 4> corners{};
        std::array<size_t, 4> cornerAt{};  // loop positions (rel) of the corners
        std::vector<double> start;         // perimeter position of every segment's first node
    };
    auto natural = [&](const Segment& g, size_t index) {
        return g.natural > 0.0 ? (tau[g.begin + index] - tau[g.begin]) / g.natural
                               : double(index) / double(g.end - g.begin);
    };
    // The natural fraction of a vertex of segment i, shared by both sides of a cut path.
    auto sharedNatural = [&](size_t i, size_t index) {
        const Segment& s = segments[i];
        const double f = natural(s, index);
        return s.mate >= 0 ? 0.5 * (f + 1.0 - natural(segments[size_t(s.mate)], s.end - s.begin - index)) : f;
    };
    // The fraction of every vertex along segment i (A's direction), with the corners inside
    // the segment or its mate pinned so that they land on their corner. Empty when the pins
    // are out of order (no monotone function exists).
    auto fractions = [&](size_t i, const Plan& p) {
        const Segment& s = segments[i];
        const size_t len = s.end - s.begin;
        std::vector<double> phi(len + 1);
        for (size_t index = 0; index <= len; ++index) phi[index] = sharedNatural(i, index);
        const double L = double(p.x[s.cls]) * p.q;
        std::vector<std::pair<size_t, double>> pins{{0, 0.0}, {len, 1.0}};
        for (int c = 1; c < 4; ++c) {
            if (p.corners[c].onNode || p.corners[c].free) continue;  // free: not placed yet
            if (p.corners[c].segment == i) pins.push_back({p.cornerAt[c] - s.begin, (c * R - p.start[i]) / L});
            if (s.mate >= 0 && p.corners[c].segment == size_t(s.mate))
                pins.push_back({len - (p.cornerAt[c] - segments[size_t(s.mate)].begin),
                                1.0 - (c * R - p.start[size_t(s.mate)]) / L});
        }
        return pinnedFractions(phi, std::move(pins));
    };
    // Solves the lengths at q and places every boundary vertex (newTau). With free corners,
    // corners 1-3 go to the vertex nearest c R after the solve (a node exactly there, or a
    // vertex inside the segment that spans c R, pinned onto it).
    auto plan = [&](uint32_t q, bool freeCorners, Plan& p, std::vector<double>& newTau) {
        p.q = q;
        p.corners = keptCorners;
        p.cornerAt = cornerRel;
        if (freeCorners)
            for (int c = 1; c < 4; ++c) p.corners[c].free = true;
        if (!solveLengths(segments, targets, weights, p.corners, resolution, q, p.x)) return false;
        // Placement of the corners and vertices for the lengths p.x (false if none fits).
        auto placeAll = [&]() -> bool {
            p.start.assign(segments.size(), 0.0);
            double t = 0.0;
            for (size_t i = 0; i < segments.size(); ++i) {
                p.start[i] = t;
                t += double(p.x[segments[i].cls]) * q;
            }
            if (freeCorners)
                for (int c = 1; c < 4; ++c) {
                    size_t k = 0;
                    while (k + 1 < segments.size() && p.start[k + 1] <= c * R) ++k;
                    if (p.start[k] == c * R) {
                        p.corners[c] = {k, true, false};
                        p.cornerAt[c] = segments[k].begin;
                        continue;
                    }
                    // The vertex nearest c R whose pin keeps the fractions of the segment and of its
                    // mate monotone with the corners placed so far (a corner mirrored onto the
                    // mate's side must be the mate of that corner's vertex, or on the right side).
                    const Segment& s = segments[k];
                    const double L = double(p.x[s.cls]) * q;
                    std::vector<std::pair<double, size_t>> candidates;
                    for (size_t index = 1; index < s.end - s.begin; ++index)
                        candidates.push_back({std::abs(p.start[k] + L * sharedNatural(k, index) - c * R), index});
                    std::sort(candidates.begin(), candidates.end());
                    bool placed = false;
                    for (const auto& [distance, index] : candidates) {
                        p.corners[c] = {k, false, false};
                        p.cornerAt[c] = s.begin + index;
                        const size_t owner = s.mate >= 0 && size_t(s.mate) < k ? size_t(s.mate) : k;
                        if (!fractions(owner, p).empty()) {
                            placed = true;
                            break;
                        }
                    }
                    if (!placed) return false;  // one edge spans the corner, or no consistent vertex
                }
            newTau.assign(n + 1, 0.0);
            for (size_t i = 0; i < segments.size(); ++i) {
                const Segment& s = segments[i];
                if (s.mate >= 0 && size_t(s.mate) < i) continue;  // placed with its mate
                const std::vector<double> f = fractions(i, p);
                if (f.empty()) return false;
                const size_t len = s.end - s.begin;
                const double L = double(p.x[s.cls]) * q;
                for (size_t index = 0; index <= len; ++index) {
                    newTau[s.begin + index] = p.start[i] + L * f[index];
                    if (s.mate >= 0)
                        newTau[segments[size_t(s.mate)].begin + len - index] =
                            p.start[size_t(s.mate)] + L * (1.0 - f[index]);
                }
            }
            for (size_t i = 0; i < segments.size(); ++i) newTau[segments[i].begin] = p.start[i];  // nodes exact
            for (int c = 1; c < 4; ++c) newTau[p.cornerAt[c]] = c * R;                            // corners exact
            newTau[n] = 4 * R;
            for (size_t j = 1; j <= n; ++j)
                if (!(newTau[j] > newTau[j - 1])) return false;
            return true;
        };
        if (placeAll()) return true;
        if (!freeCorners) return false;
        // A corner fell on a single edge or on a vertex whose mirror breaks the fractions:
        // move one unit between two classes of the same multiplicity (the perimeter stays
        // filled) and place again, cheapest moves first.
        const std::vector<long> solved = p.x;
        std::vector<std::pair<double, std::pair<size_t, size_t>>> moves;
        for (size_t a = 0; a < solved.size(); ++a)
            for (size_t b = 0; b < solved.size(); ++b)
                if (a != b && members[a] == members[b] && solved[b] > 1) {
                    auto cost = [&](size_t c, long d) {
                        const double was = double(solved[c]) * q - targets[c],
                                     now = double(solved[c] + d) * q - targets[c];
                        return weights[c] * (now * now - was * was);
                    };
                    moves.push_back({cost(a, 1) + cost(b, -1), {a, b}});
                }
        std::sort(moves.begin(), moves.end());
        for (size_t m = 0; m < moves.size() && m < 256; ++m) {
            p.x = solved;
            ++p.x[moves[m].second.first];
            --p.x[moves[m].second.second];
            p.corners = keptCorners;
            p.cornerAt = cornerRel;
            for (int c = 1; c < 4; ++c) p.corners[c].free = true;
            if (placeAll()) return true;
        }
        return false;
    };
    auto lengthChange = [&](const Plan& p) {
        double change = 0.0;
        for (const Segment& s : segments) change += std::abs(double(p.x[s.cls]) * p.q - s.natural);
        return change / (4 * R);
    };

    // The corners stay where the map put them if the lengths allow it; else they move to
    // the vertices nearest the matched quarter points. Then the coarsest level whose rounding
    // stays within the allowance.
    std::vector<double> newTau;
    Plan best;
    bool freeCorners = false;
    if (!plan(1, false, best, newTau)) {
        freeCorners = true;
        if (!plan(1, true, best, newTau)) {
            // A path of one edge has no vertex to spread a distorted side over: retry with its
            // shorter side as target (elk: one edge spans a whole side of the map, its mate 0.5
            // samples, and the mean forced the corners onto single edges).
            for (const auto& [cls, shorter] : shorterTargets) {
                targets[cls] = shorter;
                weights[cls] = double(members[cls]) / std::max(shorter, 1.0);
            }
            if (shorterTargets.empty() || !plan(1, true, best, newTau))
                return leave("the border has no integer matching (" + std::to_string(segments.size()) + " segments)");
        }
    }
    const double fullResolutionChange = lengthChange(best);
    report.lengthChange = fullResolutionChange;
    const uint32_t top = std::min<uint32_t>(levelLimit, uint32_t(std::countr_zero(resolution)));
    for (uint32_t k = 1; k <= top; ++k) {
        Plan trial;
        std::vector<double> trialTau;
        if (!plan(1u << k, freeCorners, trial, trialTau)) continue;
        const double change = lengthChange(trial);
        if (change <= fullResolutionChange + maxExtraLengthChange) {
            best = std::move(trial);
            newTau = std::move(trialTau);
            report.lengthChange = change;
        }
    }
    const uint32_t level = uint32_t(std::countr_zero(best.q));
    report.level = level;
    report.movedCorners = freeCorners;
    for (int c = 0; c < 4; ++c) out.corners[c] = loop[loopOf(best.cornerAt[c])];

    std::vector<glm::dvec2> boundaryUv(n);
    for (size_t j = 0; j < n; ++j) {
        boundaryUv[loopOf(j)] = perimeterUv(newTau[j], resolution);
        report.maxBorderMove = std::max(report.maxBorderMove, std::abs(newTau[j] - tau[j]) / R);
    }
    std::vector<glm::dvec2> uv;
    if (!solveMatchedInterior(disk, topology, map, boundaryUv, threads, report, uv))
        return leave("the interior solve after moving the border flips " + std::to_string(report.flippedTriangles) +
                     " triangles");

    out.uv = std::move(uv);
    out.seams.matched = true;
    out.seams.coarsestWatertightLevel = level;
    for (size_t i = 0; i < segments.size(); ++i) {
        const Segment& s = segments[i];
        if (s.mate < 0 || size_t(s.mate) < i) continue;
        out.seams.segments.push_back({uint32_t(std::lround(best.start[i])),
                                      uint32_t(std::lround(best.start[size_t(s.mate)])),
                                      uint32_t(best.x[s.cls]) * best.q});
    }
    report.matched = true;
    return out;
}

}  // namespace ngi
