// ngi offline: the square map of a disk mesh, by the method the baker asks for (paper
// section 3.1 and the comparison of section 4, Table 1):
//   tutte, harmonic, authalic  fixed-border linear maps (fixed_border_maps.cpp),
//   ricci                      discrete Ricci flow, Eq. 1-2 (ricci_flow.cpp),
//   ot                         Ricci start + semi-discrete optimal transport, Algorithm 1,
//                              Eq. 4-6 (optimal_transport.cpp), each vertex moved to its power
//                              cell's centroid, then made bijective (untangle.cpp).
// If the flat metric has degenerate triangles (ricci_flow.h), its layout can flip: it is made
// bijective by the same mean-value relaxation as the OT map (untangle.h) and the report says
// how many flips there were. Harmonic and authalic weights can be negative; if the plain solve flips triangles, the
// non-positive weights are clamped to a small positive floor and the map re-solved (Floater's
// theorem then guarantees an embedding); the report counts negative and clamped weights.
#include "ngi/param/parameterize.h"

#include "ngi/error.h"
#include "ngi/param/detail_density.h"
#include "ngi/param/disk_topology.h"
#include "ngi/param/distortion.h"
#include "ngi/param/fixed_border_maps.h"
#include "ngi/param/optimal_transport.h"
#include "ngi/param/ricci_flow.h"
#include "ngi/param/stretch_relaxation.h"
#include "ngi/param/untangle.h"
#include "ngi/stopwatch.h"

#include <glm/geometric.hpp>

#include <chrono>
#include <optional>
#include <sstream>

namespace ngi {
namespace {

constexpr struct {
    const char* name;
    ParameterizationMethod method;
} kMethods[] = {{"tutte", ParameterizationMethod::Tutte},
                {"harmonic", ParameterizationMethod::Harmonic},
                {"ricci", ParameterizationMethod::RicciConformal},
                {"authalic", ParameterizationMethod::Authalic},
                {"ot", ParameterizationMethod::OptimalTransport}};

// Above this maximum |log(uv area / 3D area)| the conformal start is too clustered for the
// power diagram (e^-20: sites ~5e-5 of the mean spacing apart) and a harmonic start is tried.
constexpr double kMaxConformalStartAreaDistortion = 20.0;
// Above this the best of the conformal and harmonic starts is not transported at all; the
// stretch-minimizing start (stretch_relaxation.h) is used. The batch of all CGAL meshes at
// 1024: OT converged from all 221 starts up to e^26.2 (refined_elephant) and
// failed from every one beyond that: bull e^29.8 (46 Newton iterations, ~20 s spent before
// the stretch-minimizing start converged in 7), diplodocus e^33.8 (41), femur e^39.5 (21).
constexpr double kMaxTransportStartAreaDistortion = 28.0;

std::vector<glm::dvec2> linearMap(const DiskMesh& disk, const DiskTopology& topology,
                                  const std::array<size_t, 4>& corners, EdgeWeightKind kind, ParameterizeReport& report)
{
    const auto& loop = disk.boundaryLoop;
    std::vector<double> length(loop.size());
    for (size_t k = 0; k < loop.size(); ++k)
        length[k] = glm::length(disk.mesh.positions[loop[(k + 1) % loop.size()]] - disk.mesh.positions[loop[k]]);
    const std::vector<glm::dvec2> boundaryUv = placeBoundaryOnSquare(length, corners);
    const std::vector<DirectedWeight> weights = edgeWeights(disk, kind);
    const bool symmetric = kind != EdgeWeightKind::Authalic;
    FixedBorderSolveReport solve;
    std::vector<glm::dvec2> uv = solveFixedBorderMap(disk, topology, boundaryUv, weights, symmetric, false, &solve);
    report.negativeWeights = solve.negativeWeights;
    if (solve.negativeWeights > 0 && countFlippedTriangles(disk, uv) > 0) {
        uv = solveFixedBorderMap(disk, topology, boundaryUv, weights, symmetric, true, &solve);
        report.clampedWeights = solve.clampedWeights;
    }
    return uv;
}

}  // namespace

ParameterizationMethod parseParameterizationMethod(const std::string& name)
{
    for (const auto& m : kMethods)
        if (name == m.name) return m.method;
    throw Error("unknown parameterization '" + name + "' (valid: tutte, harmonic, ricci, authalic, ot)");
}

const char* parameterizationName(ParameterizationMethod method)
{
    for (const auto& m : kMethods)
        if (method == m.method) return m.name;
    return "unknown";
}

SquareMap parameterizeToSquare(const DiskMesh& disk, const ParameterizeOptions& options)
{
    const auto start = StopwatchClock::now();
    const DiskTopology topology = analyzeDisk(disk);
    SquareMap map;
    ParameterizeReport& report = map.report;
    const std::array<size_t, 4> corners = chooseCornerPositions(disk);
    for (int c = 0; c < 4; ++c) map.corners[c] = disk.boundaryLoop[corners[c]];
    auto say = [&](const std::string& line) {
        if (options.progress) options.progress(line);
    };

    switch (options.method) {
    case ParameterizationMethod::Tutte:
        map.uv = linearMap(disk, topology, corners, EdgeWeightKind::Uniform, report);
        break;
    case ParameterizationMethod::Harmonic:
        map.uv = linearMap(disk, topology, corners, EdgeWeightKind::Cotangent, report);
        break;
    case ParameterizationMethod::Authalic:
        map.uv = linearMap(disk, topology, corners, EdgeWeightKind::Authalic, report);
        break;
    case ParameterizationMethod::RicciConformal:
    case ParameterizationMethod::OptimalTransport: {
        RicciFlowOptions ricci;
        ricci.tolerance = options.ricciTolerance;
        ricci.maxIterations = options.ricciMaxIterations;
        ricci.progress = options.progress;
        RicciFlowResult flow;
        try {
            if (options.conformalStartFailed) throw Error("the Ricci flow on this cut failed in the cut stage");
            flow = options.conformalStart ? *options.conformalStart : ricciFlowToSquare(disk, topology, corners, ricci);
        } catch (const Error& e) {
            if (options.method == ParameterizationMethod::RicciConformal) throw;
            // OT needs a bijective start, not a conformal one: when the flow fails (the
            // cut's metric has no flat solution Newton reaches with fixed connectivity), start
            // from the harmonic map, or Tutte's if that flips.
            say(std::string("conformal map failed (") + e.what() +
                "); optimal transport starts from a fixed-border map");
            ParameterizeReport fallback;
            flow.uv = linearMap(disk, topology, corners, EdgeWeightKind::Cotangent, fallback);
            report.otStart = "harmonic (Ricci flow failed)";
            if (countFlippedTriangles(disk, flow.uv) > 0) {
                flow.uv = linearMap(disk, topology, corners, EdgeWeightKind::Uniform, fallback);
                report.otStart = "tutte (Ricci flow failed)";
            }
            flow.residual = std::nan("");
        }
        report.ricciIterations = flow.iterations;
        report.ricciResidual = flow.residual;
        report.rectangleAspect = flow.aspect;
        report.ricciDegenerateTriangles = flow.degenerateTriangles;
        report.ricciLayoutFlips = countFlippedTriangles(disk, flow.uv);
        bool outside = false;
        for (const glm::dvec2& x : flow.uv) outside = outside || x.x < 0.0 || x.x > 1.0 || x.y < 0.0 || x.y > 1.0;
        if (report.ricciLayoutFlips > 0 || outside)
            flow.uv = makeBijectiveOnSquare(disk, topology, corners, std::move(flow.uv));
        report.secondsConformal = secondsSince(start);
        {
            std::ostringstream line;
            line << "conformal map: " << flow.iterations << " Ricci iterations, curvature error " << flow.residual
                 << ", rectangle aspect " << flow.aspect << ", degenerate triangles " << flow.degenerateTriangles
                 << ", layout flips " << report.ricciLayoutFlips << " (untangled), " << report.secondsConformal << " s";
            say(line.str());
        }
        if (options.method == ParameterizationMethod::RicciConformal) {
            map.uv = std::move(flow.uv);
            break;
        }
        // The start of OT: sites of a conformal map of a long protrusion are clustered by
        // e^-(2 pi length / girth); past ~e^-20 in area the power diagram can no longer separate
        // them in double precision and Newton crawls. A fixed-border harmonic map with 3D
        // arc-length boundary spacing clusters far less when the conformal boundary itself is what
        // shrinks (free rectangle sides along a protrusion); the start with the smaller maximum
        // |log(area ratio)| is used (reported as otStart).
        report.otStartAreaDistortionMax = measureDistortion(disk.mesh, flow.uv).areaMax;
        if (report.otStart.empty()) report.otStart = "ricci";
        if (report.otStart == "ricci" && report.otStartAreaDistortionMax > kMaxConformalStartAreaDistortion) {
            const double conformal = report.otStartAreaDistortionMax;
            ParameterizeReport harmonicReport;
            std::vector<glm::dvec2> harmonic =
                linearMap(disk, topology, corners, EdgeWeightKind::Cotangent, harmonicReport);
            const MapDistortion d = measureDistortion(disk.mesh, harmonic);
            if (d.flipped == 0 && d.areaMax < report.otStartAreaDistortionMax) {
                flow.uv = std::move(harmonic);
                report.otStart = "harmonic";
                report.otStartAreaDistortionMax = d.areaMax;
            }
            std::ostringstream line;
            line << "optimal transport start: the conformal map clusters sites (max |log area ratio| " << conformal
                 << "; harmonic map " << d.areaMax << ", " << d.flipped << " flipped), start from the "
                 << report.otStart << " map";
            say(line.str());
        }
        const auto transportStart = StopwatchClock::now();
        // nu_i: the area measure, or one that follows detail (detail_density.h).
        const std::vector<double> targets = detailDensityTargets(disk, options.detailDensity);
        OptimalTransportOptions transport;
        transport.tolerance = options.otTolerance;
        transport.maxIterations = options.otMaxIterations;
        transport.threads = options.threads;
        transport.progress = options.progress;
        OptimalTransportResult ot;
        // Conformal and harmonic maps shrink a protrusion exponentially (e^40..e^75 on the CGAL
        // camel, dino, man, couplingdown, elephant-with-holes, cheese), and the damped Newton
        // then crawls. The fallback is the stretch-minimizing map (stretch_relaxation.h), which
        // spreads the shrunk regions out while staying an embedding. It is only the fallback:
        // where OT converges from the conformal start, that start's centroid map is nearer to
        // conformal and has far fewer flips (armadillo: 97 vs 684).
        std::optional<std::vector<glm::dvec2>> relaxed;
        StretchRelaxationReport relaxation;
        auto relax = [&] {
            relaxed = stretchMinimizingMap(disk, topology, corners, {}, &relaxation);
            for (glm::dvec2& x : *relaxed) {
                if (!std::isfinite(x.x) || !std::isfinite(x.y))
                    throw Error("the stretch-minimizing map has non-finite coordinates");
                x = glm::clamp(x, glm::dvec2(0.0), glm::dvec2(1.0));  // rounding at the border
            }
        };
        // Past kMaxTransportStartAreaDistortion no start converged on the CGAL data: there the
        // fallback goes first, if it is less clustered (couplingdown at 1024: conformal e^65,
        // stretch-minimizing e^112).
        bool skipped = false;
        if (report.otStartAreaDistortionMax > kMaxTransportStartAreaDistortion) {
            relax();
            skipped = relaxation.areaMax < report.otStartAreaDistortionMax;
        }
        try {
            if (skipped) {
                std::ostringstream why;
                why << "not tried: max |log area ratio| above " << kMaxTransportStartAreaDistortion;
                throw Error(why.str());
            }
            ot = semiDiscreteTransport(flow.uv, targets, transport);
        } catch (const Error& e) {
            if (!relaxed) relax();
            std::ostringstream line;
            line << "optimal transport from the " << report.otStart << " map (max |log area ratio| "
                 << report.otStartAreaDistortionMax << ") failed (" << e.what()
                 << "); retry from the stretch-minimizing map (max |log area ratio| " << relaxation.areaMax << " after "
                 << relaxation.iterations << " reweighted solves)";
            say(line.str());
            report.otStart = "stretch-minimizing (OT from the " + report.otStart + " map " +
                (skipped ? "not tried: too clustered)" : "did not converge)");
            report.otStartAreaDistortionMax = relaxation.areaMax;
            ot = semiDiscreteTransport(*relaxed, targets, transport);
        }
        report.otIterations = ot.iterations;
        report.otResidual = ot.residual;
        report.otHalvings = ot.halvings;
        report.otCentroidFlips = countFlippedTriangles(disk, ot.centroid);
        UntangleReport untangle;
        const auto untangleStart = StopwatchClock::now();
        map.uv = makeBijectiveOnSquare(disk, topology, corners, std::move(ot.centroid), &untangle);
        report.otRelaxed = untangle.relaxed;
        report.otRelaxDisplacement = untangle.maxDisplacement;
        report.secondsTransport = secondsSince(transportStart);
        std::ostringstream line;
        line << "optimal transport: " << ot.iterations << " Newton iterations, area error " << ot.residual << ", "
             << report.otCentroidFlips << " centroid flips" << (untangle.relaxed ? " (relaxed)" : "") << ", "
             << report.secondsTransport << " s (power diagrams " << ot.secondsPowerDiagram << " s, linear solves "
             << ot.secondsLinearSolve << " s with " << ot.factorizations << " factorizations, untangle "
             << secondsSince(untangleStart) << " s)";
        say(line.str());
        break;
    }
    }

    const MapDistortion distortion = measureDistortion(disk.mesh, map.uv);
    report.areaDistortionMax = distortion.areaMax;
    report.areaDistortionMean = distortion.areaMean;
    report.angleDistortionMax = distortion.angleMax;
    report.angleDistortionMean = distortion.angleMean;
    report.flippedTriangles = distortion.flipped;
    report.secondsTotal = secondsSince(start);
    return map;
}

}  // namespace ngi
