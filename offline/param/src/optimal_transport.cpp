// ngi offline: semi-discrete optimal transport by damped Newton (paper Algorithm 1, Eq. 4-6;
// Gu, Luo, Sun, Yau 2016 "Variational principles for Minkowski type problems, discrete
// optimal transport, and discrete Monge-Ampere equations"; damping after Kitagawa, Merigot,
// Thibert 2019 "Convergence of a Newton algorithm for semi-discrete optimal transport").
//
// E(h) = int_Omega u_h dmu - sum_i nu_i h_i (Eq. 4) is convex; grad E = w(h) - nu (Eq. 5) and
// its Hessian (Eq. 6) is the weighted graph Laplacian of the power Delaunay triangulation with
// edge weights |e_ij| / |p_i - p_j|. With CGAL's power distance |x - p|^2 - h (our h is
// CGAL's weight), moving the bisector of (i, j) needs the factor 1/2:
// dw_i/dh_j = -|e_ij| / (2 |p_i - p_j|). The gradient sums to zero and H has the constant
// kernel, so h_0 is pinned and the reduced system is solved by sparse LDLT.
#include "ngi/param/optimal_transport.h"

#include "ngi/error.h"
#include "ngi/param/power_diagram.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace ngi {
namespace {

double maxRelativeError(const std::vector<double>& area, std::span<const double> targets) {
    double worst = 0.0;
    for (size_t i = 0; i < area.size(); ++i) worst = std::max(worst, std::abs(area[i] - targets[i]) / targets[i]);
    return worst;
}

double squaredError(const std::vector<double>& area, std::span<const double> targets) {
    double sum = 0.0;
    for (size_t i = 0; i < area.size(); ++i) sum += (area[i] - targets[i]) * (area[i] - targets[i]);
    return sum;
}

} // namespace

OptimalTransportResult semiDiscreteTransport(std::span<const glm::dvec2> sites, std::span<const double> targets,
                                             const OptimalTransportOptions& options) {
    const size_t n = sites.size();
    if (targets.size() != n) throw Error("optimal transport: targets and sites differ in size");
    if (n < 2) throw Error("optimal transport: needs at least two sites");
    double total = 0.0;
    for (size_t i = 0; i < n; ++i) {
        if (!(targets[i] > 0.0) || !std::isfinite(targets[i]))
            throw Error("optimal transport: target mass " + std::to_string(i) + " is not positive");
        if (!(sites[i].x >= 0.0 && sites[i].x <= 1.0 && sites[i].y >= 0.0 && sites[i].y <= 1.0))
            throw Error("optimal transport: site " + std::to_string(i) + " lies outside the unit square");
        total += targets[i];
    }
    if (std::abs(total - 1.0) > 1e-9) throw Error("optimal transport: target masses sum to " + std::to_string(total) + ", not 1");

    OptimalTransportResult result;
    result.heights.assign(n, 0.0);
    PowerCells cells = computePowerCells(sites, result.heights, true, options.threads);
    if (cells.emptyCells > 0)
        throw Error("optimal transport: " + std::to_string(cells.emptyCells) + " sites have an empty Voronoi cell (duplicate sites?)");
    double residual = maxRelativeError(cells.area, targets);
    double error2 = squaredError(cells.area, targets);

    const long m = long(n) - 1;  // h_0 pinned: reduced index i - 1
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver;
    int iteration = 0;
    for (; iteration < options.maxIterations && residual >= options.tolerance; ++iteration) {
        std::vector<Eigen::Triplet<double>> triplets;
        triplets.reserve(cells.facets.size() * 4);
        for (const PowerFacet& f : cells.facets) {
            const double c = f.length / (2.0 * f.distance);
            const long a = long(f.i) - 1, b = long(f.j) - 1;
            if (a >= 0) triplets.emplace_back(a, a, c);
            if (b >= 0) triplets.emplace_back(b, b, c);
            if (a >= 0 && b >= 0) {
                triplets.emplace_back(a, b, -c);
                triplets.emplace_back(b, a, -c);
            }
        }
        Eigen::SparseMatrix<double> H(m, m);
        H.setFromTriplets(triplets.begin(), triplets.end());
        solver.compute(H);  // the pattern changes with T(h): analyse every time
        if (solver.info() != Eigen::Success)
            throw Error("optimal transport: Hessian factorization failed at iteration " + std::to_string(iteration + 1));
        Eigen::VectorXd rhs(m);
        for (long i = 0; i < m; ++i) rhs[i] = targets[size_t(i + 1)] - cells.area[size_t(i + 1)];
        const Eigen::VectorXd delta = solver.solve(rhs);

        double lambda = 1.0;
        bool accepted = false;
        std::vector<double> trial(n);
        size_t lastEmpty = 0;
        for (int halving = 0; halving <= options.maxHalvings; ++halving, lambda *= 0.5) {
            trial[0] = 0.0;
            for (long i = 0; i < m; ++i) trial[size_t(i + 1)] = result.heights[size_t(i + 1)] + lambda * delta[i];
            PowerCells next = computePowerCells(sites, trial, true, options.threads);
            lastEmpty = next.emptyCells;
            if (next.emptyCells > 0) {
                ++result.halvings;
                continue;
            }
            const double nextError2 = squaredError(next.area, targets);
            const double nextResidual = maxRelativeError(next.area, targets);
            if (std::sqrt(nextError2) <= (1.0 - 0.5 * lambda) * std::sqrt(error2) || nextResidual < options.tolerance) {
                result.heights.swap(trial);
                cells = std::move(next);
                error2 = nextError2;
                residual = nextResidual;
                accepted = true;
                break;
            }
            ++result.halvings;
        }
        if (options.progress) {
            std::ostringstream line;
            line << "optimal transport: iteration " << iteration + 1 << ", step " << lambda
                 << ", max relative area error " << residual;
            options.progress(line.str());
        }
        if (!accepted) {
            std::ostringstream message;
            message << "optimal transport: no admissible Newton step at iteration " << iteration + 1 << " ("
                    << lastEmpty << " empty cells at the smallest step); max relative area error " << residual;
            throw Error(message.str());
        }
    }
    result.iterations = iteration;
    result.residual = residual;
    if (residual >= options.tolerance) {
        std::ostringstream message;
        message << "optimal transport: did not converge in " << options.maxIterations
                << " Newton iterations; max relative area error " << residual << " (tolerance " << options.tolerance << ")";
        throw Error(message.str());
    }
    result.area = std::move(cells.area);
    result.centroid = std::move(cells.centroid);
    return result;
}

} // namespace ngi
