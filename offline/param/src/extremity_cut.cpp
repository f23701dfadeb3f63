// ngi offline: cut augmentation through extremities (Gu, Gortler, Hoppe 2002, "Geometry
// Images", section 3.2: parameterize, find the point of worst stretch, cut the shortest path
// from it to the current cut, repeat while it helps).
//
// Measure: GGH use the geometric stretch of a Floater map. We use the map the bake starts OT
// from, the paper's conformal map by Ricci flow (Eq. 1-2): under vertex scaling, the flat area
// around vertex i is ~e^{u_i} times its 3D area, so log(mean_A e^u) - u_i is the log factor by
// which vertex i is shrunk relative to a uniform map. A protrusion the cut leaves closed
// shrinks like e^{-2 pi length / girth} (camel's legs: e^30 on the first cut), which clusters
// OT's sites beyond what the power diagram separates; a slit along the protrusion unrolls it
// onto the boundary (camel: e^14 after four paths, OT converges in 43 Newton iterations).
// For genus >= 1 both cut graphs of cut.h are augmented; the shorter of two good cuts is kept,
// else the less shrunk (elephant: tree-cotree e^78, face peeling e^36).
#include "ngi/param/extremity_cut.h"

#include "ngi/error.h"
#include "ngi/param/disk_topology.h"
#include "ngi/param/distortion.h"
#include "ngi/param/fixed_border_maps.h"
#include "ngi/param/ricci_flow.h"
#include "ngi/stopwatch.h"

#include <cmath>
#include <exception>
#include <glm/geometric.hpp>
#include <limits>
#include <optional>
#include <sstream>
#include <thread>

namespace ngi {
namespace {

struct Shrink {
    double worst = std::numeric_limits<double>::quiet_NaN();     // over all vertices
    double interior = std::numeric_limits<double>::quiet_NaN();  // over vertices off the cut
    uint32_t tip = 0;                                            // vertex of the uncut input mesh at the worst shrink
    std::optional<RicciFlowResult> flow;                         // the conformal start, if the flow converged
    bool flowFailed = false;                                     // the flow ran and threw
    std::string flowError;                                       // why it threw
    double flowSeconds = 0.0;                                    // time of the flow (converged or not)
};

// The worst shrink of the conformal start on `cut` (NaN if the Ricci flow fails), and the
// extremity to cut through next: the interior vertex most shrunk by a Tutte map (GGH use a
// fixed-border map too). The conformal map's own worst point often sits next to a junction of
// the cut graph, where a path to the cut would be a few edges long and change nothing, while
// the fixed-border map points at the protrusions that the cut leaves closed.
Shrink measureShrink(const CutResult& cut, size_t inputVertices)
{
    Shrink shrink;
    const DiskMesh& disk = cut.disk;
    DiskTopology topology;
    std::array<size_t, 4> corners{};
    try {
        topology = analyzeDisk(disk);
        corners = chooseCornerPositions(disk);
    } catch (const Error&) {
        return shrink;
    }
    const std::vector<double> area = vertexAreas(disk.mesh);
    double total = 0.0;
    for (double a : area) total += a;
    const StopwatchClock::time_point flowStart = StopwatchClock::now();
    try {
        const RicciFlowResult& flow =
            shrink.flow.emplace(ricciFlowToSquare(disk, topology, corners, RicciFlowOptions{}));
        double uMax = -std::numeric_limits<double>::infinity();
        for (double u : flow.u) uMax = std::max(uMax, u);
        double scaled = 0.0;  // mean_A e^u, shifted by uMax against overflow
        for (size_t i = 0; i < area.size(); ++i) scaled += area[i] * std::exp(flow.u[i] - uMax);
        const double logMean = std::log(scaled / total) + uMax;
        shrink.worst = -std::numeric_limits<double>::infinity();
        for (size_t i = 0; i < area.size(); ++i) shrink.worst = std::max(shrink.worst, logMean - flow.u[i]);
    } catch (const Error& e) {
        shrink.worst = std::numeric_limits<double>::quiet_NaN();
        shrink.flow.reset();
        shrink.flowFailed = true;
        shrink.flowError = e.what();
    }
    shrink.flowSeconds = secondsSince(flowStart);
    // Tutte map with the boundary spaced by 3D arc length.
    const auto& loop = disk.boundaryLoop;
    std::vector<double> length(loop.size());
    for (size_t k = 0; k < loop.size(); ++k)
        length[k] = glm::distance(disk.mesh.positions[loop[(k + 1) % loop.size()]], disk.mesh.positions[loop[k]]);
    std::vector<glm::dvec2> uv;
    try {
        uv = solveFixedBorderMap(disk, topology, placeBoundaryOnSquare(length, corners),
                                 edgeWeights(disk, EdgeWeightKind::Uniform), true, false);
    } catch (const Error&) {
        return shrink;
    }
    std::vector<double> uvArea(area.size(), 0.0);
    for (const glm::uvec3& t : disk.mesh.triangles) {
        const glm::dvec2 a = uv[t[1]] - uv[t[0]], b = uv[t[2]] - uv[t[0]];
        const double twice = std::abs(a.x * b.y - a.y * b.x);
        for (int k = 0; k < 3; ++k) uvArea[t[k]] += twice / 6.0;
    }
    shrink.interior = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < area.size(); ++i) {
        // A tip on the cut cannot be cut through; split-edge midpoints are not input vertices.
        if (topology.boundaryPosition[i] >= 0 || disk.originalVertex[i] >= inputVertices) continue;
        const double s = std::log(area[i] / total) - std::log(std::max(uvArea[i], 1e-300));
        if (s > shrink.interior) shrink.interior = s, shrink.tip = disk.originalVertex[i];
    }
    return shrink;
}

// The progress line of one measured cut.
std::string describeRound(const CutResult& cut, const Shrink& shrink)
{
    std::ostringstream line;
    line << "cut (" << cut.report.method << ", " << cut.report.extremityPaths << " extremity paths, "
         << cut.disk.mesh.positions.size() << " vertices): length " << cut.report.cutLength
         << ", conformal start shrinks by up to e^" << shrink.worst << " (Tutte map: e^" << shrink.interior
         << "); Ricci flow " << shrink.flowSeconds << " s"
         << (shrink.flow ? ", " + std::to_string(shrink.flow->iterations) + " iterations" : ": " + shrink.flowError);
    return line.str();
}

// A cut whose Ricci flow converges beats one whose flow fails (OT then starts from a
// fixed-border map); between two failed ones the Tutte map's shrink decides.
double score(const Shrink& shrink)
{
    if (!std::isnan(shrink.worst)) return shrink.worst;
    return 1e6 + (shrink.interior > 0.0 ? shrink.interior : 1e6);
}

ExtremityCutPlan planOf(const TriangleMesh& mesh, const CutOptions& chosen)
{
    ExtremityCutPlan plan{chosen.graph, {}};
    for (uint32_t v : chosen.extremities) plan.tips.push_back(mesh.positions[v]);
    return plan;
}

struct Candidate {
    ExtremityCutResult result;  // rounds left empty: the caller collects them
    Shrink best;
};

// Augmentation from one cut graph and start extremities: one extremity path per round while
// it helps. A cut whose Ricci flow fails (a protrusion left closed shrinks so much that the
// fixed-connectivity metric degenerates: camel, dino, man on their first cut) is measured by
// its Tutte map instead, and paths are added until the flow converges with a small enough
// shrink. Every measured cut is appended to `rounds`.
// `first`, if given, is cutToDisk(mesh, cutOptions) made already.
Candidate augment(const TriangleMesh& mesh, const ExtremityCutOptions& options, CutOptions cutOptions,
                  std::vector<ExtremityCutRound>& rounds, std::optional<CutResult> first = std::nullopt)
{
    auto say = [&](const CutResult& cut, const Shrink& shrink) {
        if (options.progress) options.progress(describeRound(cut, shrink));
    };
    Candidate candidate;
    ExtremityCutResult& found = candidate.result;
    CutResult cut = first ? std::move(*first) : cutToDisk(mesh, cutOptions);
    Shrink shrink = measureShrink(cut, mesh.positions.size());
    rounds.push_back({shrink.worst, cut.report.cutLength, shrink.interior});
    say(cut, shrink);
    auto keep = [&](CutResult&& kept, const Shrink& measured) {
        found.cut = std::move(kept);
        found.conformalShrink = measured.worst;
        found.conformalStart = measured.flow;
        found.conformalStartFailed = measured.flowFailed;
        found.plan = planOf(mesh, cutOptions);
        candidate.best = measured;
    };
    keep(std::move(cut), shrink);
    const Shrink* best = &candidate.best;
    int stalled = 0;  // paths in a row that did not improve the best shrink by e^0.1
    for (int paths = 0; paths < options.maxPaths; ++paths) {
        const bool converged = !std::isnan(shrink.worst);
        // A failed flow with a mild Tutte map is not a closed protrusion (elephant's flows
        // fail on every cut from e^14 to e^6, and 11 paths there cost 20 s for nothing visible).
        if ((converged ? shrink.worst <= options.maxConformalShrink : shrink.interior <= options.maxTutteShrink) ||
            !(shrink.interior > 0.0))
            break;
        cutOptions.extremities.push_back(shrink.tip);
        CutResult next = cutToDisk(mesh, cutOptions);
        shrink = measureShrink(next, mesh.positions.size());
        rounds.push_back({shrink.worst, next.report.cutLength, shrink.interior});
        say(next, shrink);
        // GGH stop when the stretch stops improving: three paths in a row that gain less than
        // e^0.1 end the search (elephant-with-holes: twelve paths left e^43.17 as it was, 18 s).
        stalled = score(shrink) > score(*best) - 0.1 ? stalled + 1 : 0;
        if (score(shrink) < score(*best)) {
            keep(std::move(next), shrink);
        } else if (!std::isnan(best->worst) && (std::isnan(shrink.worst) || shrink.worst > best->worst + 1.0)) {
            break;  // the path made it worse: GGH stop when stretch stops improving
        } else if (std::isnan(best->worst) && std::isnan(shrink.worst) && shrink.interior > best->interior + 1.0) {
            break;  // neither flow converges and the Tutte map got worse
        }
        if (stalled >= 3) break;
    }
    return candidate;
}

}  // namespace

ExtremityCutResult cutThroughExtremities(const TriangleMesh& mesh, const ExtremityCutOptions& options)
{
    // The cut graph: for genus >= 1 or several boundary loops both constructions are augmented
    // (tree-cotree is shorter and wins on smooth tori; face peeling wins where a tree-cotree loop
    // runs back to a far root, as on elephant: e^78 vs e^36). Where both end with a shrink OT
    // handles (<= maxConformalShrink) the shorter cut is kept: the seam is what the geometry
    // image then pays for (matched border lengths; femur: face peeling + 1 path e^11.7, 3x the
    // length of tree-cotree + 2 paths, LoD-0 CD 0.032 against 0.013 x1e-4). Otherwise the less
    // shrunk one.
    std::vector<ExtremityCutRound> rounds;
    CutResult first = cutToDisk(mesh, options.cut);
    Candidate chosen;
    if (first.report.method != "tree-cotree" && first.report.method != "face peeling") {
        chosen = augment(mesh, options, options.cut, rounds, std::move(first));
    } else {
        // The two searches are independent (each round costs a Ricci flow: b9_mesh's 76 boundary
        // loops, 17 rounds, 19 s), so the other graph's runs on a second thread; its rounds and
        // progress lines are appended after the first's, as a sequential run would give them.
        CutOptions other = options.cut;
        other.graph = options.cut.graph == CutGraph::TreeCotree ? CutGraph::FacePeeling : CutGraph::TreeCotree;
        std::vector<ExtremityCutRound> otherRounds;
        std::vector<std::string> otherLines;
        ExtremityCutOptions buffered = options;
        if (options.progress)
            buffered.progress = [&otherLines](const std::string& line) { otherLines.push_back(line); };
        Candidate second;
        std::exception_ptr otherFailure, firstFailure;
        auto augmentOther = [&] {
            try {
                second = augment(mesh, buffered, other, otherRounds);
            } catch (...) {
                otherFailure = std::current_exception();
            }
        };
        std::thread worker;
        if (options.threads > 1) worker = std::thread(augmentOther);
        try {
            chosen = augment(mesh, options, options.cut, rounds, std::move(first));
        } catch (...) {
            firstFailure = std::current_exception();  // rethrown once the worker is joined
        }
        if (worker.joinable()) worker.join();
        if (firstFailure) std::rethrow_exception(firstFailure);
        if (options.threads <= 1) augmentOther();
        for (const std::string& line : otherLines) options.progress(line);
        if (otherFailure) std::rethrow_exception(otherFailure);
        rounds.insert(rounds.end(), otherRounds.begin(), otherRounds.end());
        auto good = [&](const Candidate& c) { return c.best.worst <= options.maxConformalShrink; };  // false for NaN
        const bool secondWins = good(chosen) && good(second)
            ? second.result.cut.report.cutLength < chosen.result.cut.report.cutLength
            : score(second.best) < score(chosen.best);
        if (secondWins) chosen = std::move(second);
    }
    ExtremityCutResult result = std::move(chosen.result);
    result.rounds = std::move(rounds);
    return result;
}

ExtremityCutResult cutByPlan(const TriangleMesh& mesh, const ExtremityCutPlan& plan, const ExtremityCutOptions& options)
{
    CutOptions cutOptions = options.cut;
    cutOptions.graph = plan.graph;
    cutOptions.extremities.clear();  // the plan's tips include the search's start extremities
    for (const glm::dvec3& tip : plan.tips) {
        uint32_t nearest = 0;
        double best = std::numeric_limits<double>::infinity();
        for (size_t v = 0; v < mesh.positions.size(); ++v) {
            const double d = glm::distance(mesh.positions[v], tip);
            if (d < best) best = d, nearest = uint32_t(v);
        }
        cutOptions.extremities.push_back(nearest);
    }
    // The base cut depends on the mesh's numbering, so a planned tip can fall on it here and be
    // skipped (joinExtremities), leaving its protrusion closed: then augment on this mesh as the
    // search would. Otherwise measure the one cut (each augmentation round costs a Ricci flow
    // at this mesh's size: 17 s at 65k vertices).
    ExtremityCutOptions once = options;
    CutResult cut = cutToDisk(mesh, cutOptions);
    if (cut.report.extremityPaths >= plan.tips.size()) once.maxPaths = 0;
    std::vector<ExtremityCutRound> rounds;
    ExtremityCutResult result = augment(mesh, once, cutOptions, rounds, std::move(cut)).result;
    result.rounds = std::move(rounds);
    return result;
}

}  // namespace ngi
