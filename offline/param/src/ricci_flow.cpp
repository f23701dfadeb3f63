// ngi offline: discrete surface Ricci flow, Newton's method (paper Eq. 1-2; Jin, Kim, Luo, Gu,
// "Discrete Surface Ricci Flow", TVCG 2008; Luo 2004 "Combinatorial Yamabe flow";
// Springborn, Schroeder, Pinkall 2008 "Conformal equivalence of triangle meshes").
//
// Which flow: the vertex-scaling ("discrete Yamabe") form, l_ij = exp((u_i + u_j) / 2) L_ij.
// Why: it applies to any triangle mesh as is (circle packing needs intersection angles in
// [0, pi/2] and inversive-distance packing can lose convexity), its Ricci energy (Eq. 1) is
// convex in u where triangles are valid, and its Hessian (Eq. 2) is exactly the cotangent
// Laplacian of the current metric: dK_i = sum_j w_ij (du_i - du_j), w_ij = (cot a_ij + cot b_ij)/2.
// Curvatures: K_i = 2 pi - sum of angles (interior), k_i = pi - sum of angles (boundary,
// geodesic curvature = turning angle). Targets: 0 inside and along the boundary, pi/2 at the
// four corners (the turning of a square corner; the paper writes pi/4, but Gauss-Bonnet,
// sum = 2 pi chi = 2 pi, requires pi/2 each).
// Newton: solve L delta = Kbar - K with one u pinned (L has the constant kernel), then halve
// the step until ||Kbar - K||^2 decreases (delta is a descent direction of that merit: its
// derivative is -||Kbar - K||^2).
// Fixed connectivity: when the conformal factor varies strongly (a closed surface opened by a
// short cut, a long spike), the target metric may not exist with every triangle valid. We
// then follow Bobenko, Pinkall, Springborn 2015 ("Discrete conformal maps and ideal
// hyperbolic polyhedra"): a triangle violating a triangle inequality gets angles (pi, 0, 0)
// and zero weights, which keeps the energy convex and C^1, so Newton still converges; the
// result reports how many triangles ended degenerate, and their layout can flip (the caller
// then untangles; see parameterize.cpp). Intrinsic Delaunay flips (Gillespie, Springborn,
// Crane 2021) would avoid degenerate triangles altogether; not implemented.
#include "ngi/param/ricci_flow.h"

#include "ngi/error.h"
#include "ngi/param/fixed_border_maps.h"
#include "triangle_geometry.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <sstream>

namespace ngi {
namespace {

struct FlowState {
    std::vector<double> curvature;  // K_i (or k_i on the boundary)
    std::vector<double> cotangent;  // per triangle corner: cot of the angle (3 per triangle)
    size_t degenerate = 0;          // triangles violating a triangle inequality (extended)
    bool valid = true;              // false only on overflow
};

// Evaluates curvatures and cotangents of the metric exp((u_i+u_j)/2) L_ij.
FlowState evaluate(const DiskMesh& disk, const DiskTopology& topology, const std::vector<double>& L,
                   const std::vector<double>& u)
{
    const auto& triangles = disk.mesh.triangles;
    const size_t n = disk.mesh.positions.size();
    FlowState state;
    state.cotangent.resize(triangles.size() * 3);
    std::vector<double> angleSum(n, 0.0);
    for (size_t t = 0; t < triangles.size(); ++t) {
        const glm::uvec3 tri = triangles[t];
        double len[3];
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
            len[k] = L[t * 3 + k] * std::exp(0.5 * (u[a] + u[b]));
        }
        if (!std::isfinite(len[0] + len[1] + len[2])) {
            state.valid = false;
            return state;
        }
        if (!detail::satisfiesTriangleInequality(len[0], len[1], len[2], 1e-10)) {
            // Convex extension (Bobenko, Pinkall, Springborn 2015): a degenerate triangle has
            // angle pi opposite its longest side, 0 elsewhere, and contributes no weight.
            const int longest = len[0] >= len[1] && len[0] >= len[2] ? 0 : (len[1] >= len[2] ? 1 : 2);
            angleSum[tri[longest]] += std::numbers::pi;
            for (int k = 0; k < 3; ++k) state.cotangent[t * 3 + k] = 0.0;
            ++state.degenerate;
            continue;
        }
        const double area = detail::triangleAreaFromLengths(len[0], len[1], len[2]);
        for (int k = 0; k < 3; ++k) {
            const double a = len[k], b = len[(k + 1) % 3], c = len[(k + 2) % 3];
            angleSum[tri[k]] += detail::angleFromLengths(a, b, c, area);
            state.cotangent[t * 3 + k] = detail::cotangentFromLengths(a, b, c, area);
        }
    }
    state.curvature.resize(n);
    for (size_t v = 0; v < n; ++v)
        state.curvature[v] =
            (topology.boundaryPosition[v] >= 0 ? std::numbers::pi : 2.0 * std::numbers::pi) - angleSum[v];
    return state;
}

}  // namespace

RicciFlowResult ricciFlowToSquare(const DiskMesh& disk, const DiskTopology& topology,
                                  const std::array<size_t, 4>& cornerPositions, const RicciFlowOptions& options)
{
    const auto& triangles = disk.mesh.triangles;
    const auto& p = disk.mesh.positions;
    const size_t n = p.size();

    std::vector<double> L(triangles.size() * 3);  // original length of the side opposite each corner
    for (size_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k)
            L[t * 3 + k] = glm::length(p[triangles[t][(k + 2) % 3]] - p[triangles[t][(k + 1) % 3]]);

    std::vector<double> target(n, 0.0);
    for (size_t c : cornerPositions) target[disk.boundaryLoop[c]] = 0.5 * std::numbers::pi;

    RicciFlowResult result;
    result.u.assign(n, 0.0);
    FlowState state = evaluate(disk, topology, L, result.u);
    if (!state.valid || state.degenerate > 0) throw Error("Ricci flow: the input mesh violates a triangle inequality");

    // Vertex 0 is pinned: the reduced index of v is v - 1.
    const long m = long(n) - 1;
    auto residualOf = [&](const FlowState& s, double* maxAbs) {
        double sum = 0.0, mx = 0.0;
        for (size_t v = 0; v < n; ++v) {
            const double r = target[v] - s.curvature[v];
            sum += r * r;
            mx = std::max(mx, std::abs(r));
        }
        if (maxAbs) *maxAbs = mx;
        return sum;
    };
    // Where the flow is stuck, for the failure messages: the vertex of the largest curvature
    // error, on the boundary or not, and how many of its triangles are degenerate.
    auto worstVertex = [&](const FlowState& s) {
        size_t worst = 0;
        for (size_t v = 0; v < n; ++v)
            if (std::abs(target[v] - s.curvature[v]) > std::abs(target[worst] - s.curvature[worst])) worst = v;
        size_t around = 0, degenerate = 0;
        for (size_t t = 0; t < triangles.size(); ++t)
            for (int k = 0; k < 3; ++k)
                if (triangles[t][k] == worst) {
                    ++around;
                    bool flat = true;
                    for (int j = 0; j < 3; ++j) flat = flat && s.cotangent[t * 3 + j] == 0.0;
                    degenerate += flat;
                }
        std::ostringstream text;
        text << " at " << (topology.boundaryPosition[worst] >= 0 ? "boundary" : "interior") << " vertex " << worst
             << " (" << degenerate << " of its " << around << " triangles degenerate, curvature " << s.curvature[worst]
             << ", target " << target[worst] << ", u " << result.u[worst] << ")";
        return text.str();
    };
    double maxResidual = 0.0;
    double merit = residualOf(state, &maxResidual);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    bool analyzed = false;
    int iteration = 0;
    for (; iteration < options.maxIterations && maxResidual >= options.tolerance; ++iteration) {
        std::vector<Eigen::Triplet<double>> triplets;
        triplets.reserve(triangles.size() * 9);
        for (size_t t = 0; t < triangles.size(); ++t) {
            for (int k = 0; k < 3; ++k) {
                const long a = long(triangles[t][(k + 1) % 3]) - 1, b = long(triangles[t][(k + 2) % 3]) - 1;
                const double w = 0.5 * state.cotangent[t * 3 + k];
                if (a >= 0) triplets.emplace_back(a, a, w);
                if (b >= 0) triplets.emplace_back(b, b, w);
                if (a >= 0 && b >= 0) {
                    triplets.emplace_back(a, b, -w);
                    triplets.emplace_back(b, a, -w);
                }
            }
        }
        Eigen::SparseMatrix<double> H(m, m);
        H.setFromTriplets(triplets.begin(), triplets.end());
        if (!analyzed) {
            solver.analyzePattern(H);
            analyzed = true;
        }
        solver.factorize(H);
        if (solver.info() != Eigen::Success) {
            // Degenerate triangles can disconnect a vertex's weights: regularize slightly.
            for (long i = 0; i < m; ++i) H.coeffRef(i, i) += 1e-10;
            solver.factorize(H);
            if (solver.info() != Eigen::Success)
                throw Error("Ricci flow: Newton system factorization failed at iteration " +
                            std::to_string(iteration + 1));
        }
        Eigen::VectorXd gradient(m);
        for (long i = 0; i < m; ++i) gradient[i] = target[size_t(i + 1)] - state.curvature[size_t(i + 1)];
        const Eigen::VectorXd delta = solver.solve(gradient);

        double lambda = 1.0;
        bool accepted = false;
        std::vector<double> trial(n);
        for (int halving = 0; halving <= options.maxHalvings; ++halving, lambda *= 0.5) {
            trial[0] = result.u[0];
            for (long i = 0; i < m; ++i) trial[size_t(i + 1)] = result.u[size_t(i + 1)] + lambda * delta[i];
            FlowState next = evaluate(disk, topology, L, trial);
            if (!next.valid) continue;
            double nextMax = 0.0;
            const double nextMerit = residualOf(next, &nextMax);
            if (nextMerit <= (1.0 - 1e-4 * lambda) * merit || nextMax < options.tolerance) {
                result.u.swap(trial);
                state = std::move(next);
                merit = nextMerit;
                maxResidual = nextMax;
                accepted = true;
                break;
            }
        }
        if (options.progress) {
            std::ostringstream line;
            line << "Ricci flow: iteration " << iteration + 1 << ", step " << lambda << ", max curvature error "
                 << maxResidual << ", degenerate triangles " << state.degenerate;
            options.progress(line.str());
        }
        if (!accepted) {
            std::ostringstream message;
            message << "Ricci flow: no admissible Newton step at iteration " << iteration + 1
                    << " (triangle inequalities or no decrease); max curvature error " << maxResidual
                    << worstVertex(state);
            throw Error(message.str());
        }
    }
    result.iterations = iteration;
    result.residual = maxResidual;
    result.degenerateTriangles = state.degenerate;
    if (maxResidual >= options.tolerance) {
        std::ostringstream message;
        message << "Ricci flow: did not converge in " << options.maxIterations << " iterations; max curvature error "
                << maxResidual << worstVertex(state) << " (tolerance " << options.tolerance << ")";
        throw Error(message.str());
    }

    // Embed the flat metric. Boundary edge lengths of the flat metric place the boundary.
    const auto& loop = disk.boundaryLoop;
    std::vector<double> boundaryLength(loop.size());
    for (size_t k = 0; k < loop.size(); ++k) {
        const uint32_t a = loop[k], b = loop[(k + 1) % loop.size()];
        boundaryLength[k] = glm::length(p[b] - p[a]) * std::exp(0.5 * (result.u[a] + result.u[b]));
    }
    double side[4] = {0, 0, 0, 0};
    for (size_t k = 0; k < loop.size(); ++k) side[boundarySide(k, cornerPositions, loop.size())] += boundaryLength[k];
    result.aspect = 0.5 * (side[0] + side[2]) / (0.5 * (side[1] + side[3]));
    const std::vector<glm::dvec2> boundaryUv = placeBoundaryOnSquare(boundaryLength, cornerPositions);

    std::vector<DirectedWeight> weights;
    weights.reserve(triangles.size() * 6);
    for (size_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = triangles[t][(k + 1) % 3], b = triangles[t][(k + 2) % 3];
            const double w = 0.5 * state.cotangent[t * 3 + k];
            weights.push_back({a, b, w});
            weights.push_back({b, a, w});
        }
    result.uv = solveFixedBorderMap(disk, topology, boundaryUv, weights, /*symmetric=*/true, /*clampNegative=*/false);
    return result;
}

}  // namespace ngi
