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
//
// Clustered sites (a conformal start shrinks protruding parts by factors of e^10 and more)
// make the plain damped Newton crawl with tiny steps from h = 0. We then follow a homotopy in
// the targets: nu(t) proportional to w(0)^(1-t) nu^t (geometric, since area ratios span
// orders of magnitude), t = 0 is solved by h = 0; each stage starts from the previous h and
// must converge with steps >= 1/8 (else dt is halved), dt grows after each success. The last
// stage is t = 1 with the caller's tolerance. The Newton systems are solved inexactly (Dembo,
// Eisenstat, Steihaug 1982, "Inexact Newton methods"), by PCG on reused factors (NewtonSystem).
#include "ngi/param/optimal_transport.h"

#include "ngi/error.h"
#include "ngi/param/power_diagram.h"
#include "ngi/stopwatch.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace ngi {
namespace {

double maxRelativeError(const std::vector<double>& area, std::span<const double> targets)
{
    double worst = 0.0;
    for (size_t i = 0; i < area.size(); ++i) worst = std::max(worst, std::abs(area[i] - targets[i]) / targets[i]);
    return worst;
}

double squaredError(const std::vector<double>& area, std::span<const double> targets)
{
    double sum = 0.0;
    for (size_t i = 0; i < area.size(); ++i) sum += (area[i] - targets[i]) * (area[i] - targets[i]);
    return sum;
}

struct NewtonStats {
    int iterations = 0;
    int halvings = 0;
    int factorizations = 0;
    double secondsPowerDiagram = 0.0;
    double secondsLinearSolve = 0.0;
};

// The Newton system H delta = b, solved by preconditioned conjugate gradients with the LDLT
// factors of an earlier iterate's Hessian, refactorized only when that stops converging
// quickly. T(h) moves little from one Newton step to the next, so the old factors are a
// near-exact preconditioner; on camel (65k sites) a factorization cost as much as ~18
// triangular solve pairs and was 17% of the whole bake. Convergence is judged per site
// relative to its target mass, not in the 2-norm: the masses span e^30 on clustered starts and
// a 2-norm test would leave the small cells' equations unsolved.
class NewtonSystem {
public:
    // Fills `delta`; false if the Hessian could not be factorized.
    bool solve(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& b, std::span<const double> scale,
               double tolerance, Eigen::VectorXd& delta, NewtonStats& stats)
    {
        if (factored_ && conjugateGradients(H, b, scale, tolerance, delta)) return true;
        solver_.compute(H);  // the pattern changes with T(h): analyse every time
        factored_ = solver_.info() == Eigen::Success;
        if (!factored_) return false;
        ++stats.factorizations;
        delta = solver_.solve(b);
        return true;
    }

private:
    static constexpr int kMaxIterations = 6;  // past this a refactorization is cheaper

    bool conjugateGradients(const Eigen::SparseMatrix<double>& H, const Eigen::VectorXd& b,
                            std::span<const double> scale, double tolerance, Eigen::VectorXd& x) const
    {
        auto converged = [&](const Eigen::VectorXd& r) {
            for (long i = 0; i < r.size(); ++i)
                if (!(std::abs(r[i]) <= tolerance * scale[size_t(i)])) return false;
            return true;
        };
        x = Eigen::VectorXd::Zero(b.size());
        Eigen::VectorXd r = b;
        Eigen::VectorXd z = solver_.solve(r);
        Eigen::VectorXd p = z;
        double rz = r.dot(z);
        for (int k = 0; k < kMaxIterations; ++k) {
            const Eigen::VectorXd q = H * p;
            const double pq = p.dot(q);
            if (!(pq > 0.0)) return false;
            const double alpha = rz / pq;
            x += alpha * p;
            r -= alpha * q;
            if (converged(r)) return true;
            z = solver_.solve(r);
            const double next = r.dot(z);
            p = z + (next / rz) * p;
            rz = next;
        }
        return false;
    }

    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;  // one per transport: H's size is fixed
    bool factored_ = false;
};

// Damped Newton from `heights` (updated in place with `cells`) towards `targets`. Returns false
// if a step below `minLambda` was needed or `maxIterations` ran out (heights/cells then hold
// the last accepted iterate).
bool dampedNewton(std::span<const glm::dvec2> sites, std::span<const double> targets, std::vector<double>& heights,
                  PowerCells& cells, double tolerance, int maxIterations, double minLambda,
                  const OptimalTransportOptions& options, NewtonSystem& system, NewtonStats& stats, double& residual)
{
    const size_t n = sites.size();
    const long m = long(n) - 1;  // h_0 pinned: reduced index i - 1
    residual = maxRelativeError(cells.area, targets);
    double error2 = squaredError(cells.area, targets);
    // The line search starts at twice the last accepted step, not at 1: far from the solution
    // the damped steps come in runs (camel: 0.125, 0.25, 0.25, 0.5, ...), and each rejected
    // trial costs a power diagram. Twice lets a run of full steps resume after one success.
    double firstLambda = 1.0;
    for (int iteration = 0; iteration < maxIterations && residual >= tolerance; ++iteration) {
        const auto solveStart = StopwatchClock::now();
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
        Eigen::VectorXd rhs(m);
        for (long i = 0; i < m; ++i) rhs[i] = targets[size_t(i + 1)] - cells.area[size_t(i + 1)];
        // Inexact Newton: the linear model is solved per cell to 1% of the error Newton is at,
        // and to a tenth of the tolerance it must reach.
        const double linearTolerance = std::clamp(0.01 * residual, 0.1 * tolerance, 0.01);
        Eigen::VectorXd delta;
        if (!system.solve(H, rhs, targets.subspan(1), linearTolerance, delta, stats)) return false;
        stats.secondsLinearSolve += secondsSince(solveStart);

        double lambda = firstLambda;
        bool accepted = false;
        std::vector<double> trial(n);
        for (; lambda >= minLambda; lambda *= 0.5) {
            trial[0] = 0.0;
            for (long i = 0; i < m; ++i) trial[size_t(i + 1)] = heights[size_t(i + 1)] + lambda * delta[i];
            const auto diagramStart = StopwatchClock::now();
            PowerCells next = computePowerCells(sites, trial, true, options.threads);
            stats.secondsPowerDiagram += secondsSince(diagramStart);
            if (next.emptyCells == 0) {
                const double nextError2 = squaredError(next.area, targets);
                const double nextResidual = maxRelativeError(next.area, targets);
                if (std::sqrt(nextError2) <= (1.0 - 0.5 * lambda) * std::sqrt(error2) || nextResidual < tolerance) {
                    heights.swap(trial);
                    cells = std::move(next);
                    error2 = nextError2;
                    residual = nextResidual;
                    accepted = true;
                    break;
                }
            }
            ++stats.halvings;
        }
        ++stats.iterations;
        if (options.progress) {
            std::ostringstream line;
            line << "optimal transport: Newton iteration " << stats.iterations << ", step " << (accepted ? lambda : 0.0)
                 << ", max relative area error " << residual;
            options.progress(line.str());
        }
        if (!accepted) return false;
        firstLambda = std::min(1.0, 2.0 * lambda);
    }
    return residual < tolerance;
}

}  // namespace

OptimalTransportResult semiDiscreteTransport(std::span<const glm::dvec2> sites, std::span<const double> targets,
                                             const OptimalTransportOptions& options)
{
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
    if (std::abs(total - 1.0) > 1e-9)
        throw Error("optimal transport: target masses sum to " + std::to_string(total) + ", not 1");
    const std::vector<double> nu(targets.begin(), targets.end());

    OptimalTransportResult result;
    result.heights.assign(n, 0.0);
    PowerCells cells = computePowerCells(sites, result.heights, true, options.threads);
    if (cells.emptyCells > 0)
        throw Error("optimal transport: " + std::to_string(cells.emptyCells) +
                    " sites have an empty Voronoi cell (duplicate sites?)");
    const std::vector<double> start = cells.area;  // w(0): the targets at t = 0

    NewtonStats stats;
    NewtonSystem system;
    double residual = 0.0;
    // First try the direct damped Newton with a limited budget; if it crawls, use the homotopy.
    std::vector<double> savedHeights = result.heights;
    PowerCells savedCells = cells;
    bool done = dampedNewton(sites, nu, result.heights, cells, options.tolerance, 12, 1.0 / 8.0, options, system, stats,
                             residual);
    if (!done) {
        result.heights = savedHeights;
        cells = std::move(savedCells);
        double t = 0.0, dt = 0.25;
        std::vector<double> stageTargets(n);
        while (!done) {
            if (stats.iterations >= options.maxIterations) break;
            const double next = std::min(1.0, t + dt);
            double sum = 0.0;
            for (size_t i = 0; i < n; ++i)
                sum += stageTargets[i] = std::pow(start[i], 1.0 - next) * std::pow(nu[i], next);
            for (double& x : stageTargets) x /= sum;
            std::vector<double> heights = result.heights;
            PowerCells stageCells = cells;
            const bool last = next >= 1.0;
            const double stageTolerance = last ? options.tolerance : 0.05;
            const bool ok = dampedNewton(sites, stageTargets, heights, stageCells, stageTolerance,
                                         last ? options.maxIterations - stats.iterations : 8, last ? 1e-12 : 0.125,
                                         options, system, stats, residual);
            if (ok) {
                result.heights.swap(heights);
                cells = std::move(stageCells);
                t = next;
                dt = std::min(1.0, dt * 1.5);
                done = last;
                if (options.progress) options.progress("optimal transport: homotopy reached t = " + std::to_string(t));
            } else if (last && dt <= 1e-3) {
                break;
            } else {
                dt *= 0.5;
                if (dt < 1e-4) break;
            }
        }
        residual = maxRelativeError(cells.area, nu);
    }
    result.iterations = stats.iterations;
    result.halvings = stats.halvings;
    result.secondsPowerDiagram = stats.secondsPowerDiagram;
    result.secondsLinearSolve = stats.secondsLinearSolve;
    result.factorizations = stats.factorizations;
    result.residual = residual;
    if (!(residual < options.tolerance)) {
        std::ostringstream message;
        message << "optimal transport: did not converge in " << stats.iterations
                << " Newton iterations; max relative area error " << residual << " (tolerance " << options.tolerance
                << ")";
        throw Error(message.str());
    }
    result.area = std::move(cells.area);
    result.centroid = std::move(cells.centroid);
    return result;
}

}  // namespace ngi
