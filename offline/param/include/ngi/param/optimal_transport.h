// ngi offline: semi-discrete optimal transport from the uniform measure on the unit square to
// weighted points (paper section 3.1, "Area Preservation via Optimal Transport", Algorithm 1,
// Eq. 3-6), solved by damped Newton on the heights h of the power diagram.
#pragma once

#include <glm/vec2.hpp>

#include <functional>
#include <span>
#include <string>
#include <vector>

namespace ngi {

struct OptimalTransportOptions {
    double tolerance = 1e-3;  // stop when max_i |w_i(h) - nu_i| / nu_i < tolerance
    int maxIterations = 100;  // Newton iterations in all (direct attempt + homotopy stages)
    unsigned threads = 2;     // threads for clipping the cells
    std::function<void(const std::string&)> progress;
};

struct OptimalTransportResult {
    std::vector<double> heights;       // h, with h_0 = 0 pinned
    std::vector<double> area;          // w_i(h): cell areas at the solution
    std::vector<glm::dvec2> centroid;  // centroid of each cell W_i n Omega
    int iterations = 0;                // Newton iterations
    int halvings = 0;                  // total step halvings over all iterations
    double residual = 0.0;             // max_i |w_i - nu_i| / nu_i at the end
    double secondsPowerDiagram = 0.0;  // where the time went: power diagrams (incl. line search)
    double secondsLinearSolve = 0.0;   // Hessian assembly, factorization and solves
    int factorizations = 0;            // Hessians factorized; the other steps reused old factors (PCG)
};

// Finds h such that the power cell of site p_i inside [0,1]^2 has area nu_i. `targets` must
// be positive and sum to 1 (the square's area), `sites` distinct points of [0,1]^2.
// Newton step: H delta = nu - w(h) with H from Eq. 6 (dw_i/dh_j = -|e_ij| / (2 |p_i - p_j|)
// under CGAL's weight convention), h_0 pinned; the step is halved while a cell is empty or
// ||w - nu|| fails to drop by the factor (1 - lambda/2) (Kitagawa, Merigot, Thibert 2019),
// starting from twice the last accepted step; steps are solved to a per-cell tolerance by PCG
// on an earlier Hessian's factors where that converges in a few iterations.
// If that crawls (12 iterations without convergence, or a step below 1/8), a homotopy in the
// targets from the Voronoi areas to nu takes over (see optimal_transport.cpp).
// Throws ngi::Error when it does not converge (message: iteration, residual, empty cells).
OptimalTransportResult semiDiscreteTransport(std::span<const glm::dvec2> sites, std::span<const double> targets,
                                             const OptimalTransportOptions& options = {});

}  // namespace ngi
