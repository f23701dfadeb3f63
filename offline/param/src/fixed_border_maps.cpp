// ngi offline: fixed-border linear parameterizations (the baselines of the paper's Table 1
// and the untangling step of the OT map).
//   Tutte 1963, "How to draw a graph": uniform weights, convex border -> embedding.
//   Eck et al. 1995, "Multiresolution analysis of arbitrary meshes": harmonic map, cotangent
//     weights w_ij = (cot alpha_ij + cot beta_ij) / 2.
//   Desbrun, Meyer, Alliez 2002, "Intrinsic parameterizations of surface meshes": authalic
//     (chi) weights w_ij = (cot gamma_ij + cot delta_ij) / |x_i - x_j|^2.
//   Floater 2003, "Mean value coordinates": w_ij = (tan(a_ij/2) + tan(b_ij/2)) / r_ij.
// Each interior vertex i satisfies sum_j w_ij (u_j - u_i) = 0; the boundary is fixed on the
// square. Floater's theorem: positive weights + convex border => bijective straight-line map.
#include "ngi/param/fixed_border_maps.h"

#include "ngi/error.h"
#include "triangle_geometry.h"

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include <glm/geometric.hpp>

#include <cmath>
#include <string>

namespace ngi {

std::vector<DirectedWeight> edgeWeights(const DiskMesh& disk, EdgeWeightKind kind)
{
    const auto& p = disk.mesh.positions;
    std::vector<DirectedWeight> weights;
    weights.reserve(disk.mesh.triangles.size() * 6);
    for (const glm::uvec3& tri : disk.mesh.triangles) {
        double len[3];  // len[k] = side opposite corner k
        for (int k = 0; k < 3; ++k) len[k] = glm::length(p[tri[(k + 2) % 3]] - p[tri[(k + 1) % 3]]);
        const double area = detail::triangleAreaFromLengths(len[0], len[1], len[2]);
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = tri[(k + 1) % 3], j = tri[(k + 2) % 3];  // edge opposite corner k
            switch (kind) {
            case EdgeWeightKind::Uniform:
                // Every edge of an interior vertex has two triangles: 0.5 + 0.5 = 1.
                weights.push_back({i, j, 0.5});
                weights.push_back({j, i, 0.5});
                break;
            case EdgeWeightKind::Cotangent: {
                const double w = 0.5 * detail::cotangentFromLengths(len[k], len[(k + 1) % 3], len[(k + 2) % 3], area);
                weights.push_back({i, j, w});
                weights.push_back({j, i, w});
                break;
            }
            case EdgeWeightKind::Authalic: {
                // Row i gets cot(angle at j) / |ij|^2; row j gets cot(angle at i) / |ij|^2.
                const int ci = (k + 1) % 3, cj = (k + 2) % 3;
                const double cotI = detail::cotangentFromLengths(len[ci], len[(ci + 1) % 3], len[(ci + 2) % 3], area);
                const double cotJ = detail::cotangentFromLengths(len[cj], len[(cj + 1) % 3], len[(cj + 2) % 3], area);
                const double r2 = len[k] * len[k];
                weights.push_back({i, j, cotJ / r2});
                weights.push_back({j, i, cotI / r2});
                break;
            }
            }
        }
    }
    return weights;
}

std::vector<DirectedWeight> meanValueWeights(const DiskMesh& disk, const std::vector<glm::dvec2>& uv)
{
    std::vector<DirectedWeight> weights;
    weights.reserve(disk.mesh.triangles.size() * 6);
    for (const glm::uvec3& tri : disk.mesh.triangles) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t i = tri[k], j = tri[(k + 1) % 3], l = tri[(k + 2) % 3];
            const glm::dvec2 a = uv[j] - uv[i], b = uv[l] - uv[i];
            const double ra = glm::length(a), rb = glm::length(b);
            // Unsigned angle at i: tan(angle/2) = |a x b| / (|a||b| + a.b) >= 0.
            const double cross = std::abs(a.x * b.y - a.y * b.x);
            const double denom = ra * rb + glm::dot(a, b);
            const double tanHalf = denom > 0.0 ? cross / denom : 1e12;
            if (ra > 0.0) weights.push_back({i, j, tanHalf / ra});
            if (rb > 0.0) weights.push_back({i, l, tanHalf / rb});
        }
    }
    return weights;
}

std::vector<glm::dvec2> solveFixedBorderMap(const DiskMesh& disk, const DiskTopology& topology,
                                            const std::vector<glm::dvec2>& boundaryUv,
                                            const std::vector<DirectedWeight>& weights, bool symmetric,
                                            bool clampNegative, FixedBorderSolveReport* report, double floor)
{
    const size_t n = disk.mesh.positions.size();
    std::vector<glm::dvec2> uv(n, glm::dvec2(0.0));
    for (size_t k = 0; k < disk.boundaryLoop.size(); ++k) uv[disk.boundaryLoop[k]] = boundaryUv[k];
    std::vector<int32_t> interiorIndex(n, -1);
    int32_t m = 0;
    for (size_t v = 0; v < n; ++v)
        if (topology.boundaryPosition[v] < 0) interiorIndex[v] = m++;
    if (m == 0) return uv;

    // Sum duplicates per directed edge (rows are interior vertices only).
    Eigen::SparseMatrix<double, Eigen::RowMajor> W{long(n), long(n)};
    {
        std::vector<Eigen::Triplet<double>> triplets;
        triplets.reserve(weights.size());
        for (const DirectedWeight& w : weights)
            if (interiorIndex[w.from] >= 0) triplets.emplace_back(long(w.from), long(w.to), w.weight);
        W.setFromTriplets(triplets.begin(), triplets.end());
    }
    FixedBorderSolveReport localReport;
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(size_t(W.nonZeros()) + size_t(m));
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 2);
    for (size_t v = 0; v < n; ++v) {
        const int32_t row = interiorIndex[v];
        if (row < 0) continue;
        double meanAbs = 0.0;
        long count = 0;
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(W, long(v)); it; ++it) {
            meanAbs += std::abs(it.value());
            ++count;
        }
        meanAbs = count > 0 ? meanAbs / double(count) : 1.0;
        if (!(meanAbs > 0.0)) meanAbs = 1.0;
        double diagonal = 0.0;
        for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(W, long(v)); it; ++it) {
            double w = it.value();
            if (w <= 0.0) ++localReport.negativeWeights;
            if (clampNegative && w < floor * meanAbs) {
                w = floor * meanAbs;
                ++localReport.clampedWeights;
            }
            diagonal += w;
            const int32_t col = interiorIndex[size_t(it.col())];
            if (col >= 0) {
                triplets.emplace_back(row, col, -w);
            } else {
                rhs(row, 0) += w * uv[size_t(it.col())].x;
                rhs(row, 1) += w * uv[size_t(it.col())].y;
            }
        }
        triplets.emplace_back(row, row, diagonal);
    }
    Eigen::SparseMatrix<double> A(m, m);
    A.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::MatrixXd x;
    // Clamping scales by a per-row mean, which breaks symmetry: LU then.
    if (symmetric && !clampNegative) {
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(A);
        if (solver.info() != Eigen::Success) throw Error("parameterization: fixed-border LDLT factorization failed");
        x = solver.solve(rhs);
    } else {
        Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
        solver.analyzePattern(A);
        solver.factorize(A);
        if (solver.info() != Eigen::Success)
            throw Error("parameterization: fixed-border LU factorization failed: " + solver.lastErrorMessage());
        x = solver.solve(rhs);
    }
    for (size_t v = 0; v < n; ++v) {
        const int32_t row = interiorIndex[v];
        if (row < 0) continue;
        uv[v] = glm::dvec2(x(row, 0), x(row, 1));
        if (!std::isfinite(uv[v].x) || !std::isfinite(uv[v].y))
            throw Error("parameterization: fixed-border solve produced NaN (singular system)");
    }
    if (report) *report = localReport;
    return uv;
}

size_t countFlippedTriangles(const DiskMesh& disk, const std::vector<glm::dvec2>& uv)
{
    size_t flipped = 0;
    for (const glm::uvec3& tri : disk.mesh.triangles) {
        const glm::dvec2 a = uv[tri[1]] - uv[tri[0]], b = uv[tri[2]] - uv[tri[0]];
        if (a.x * b.y - a.y * b.x <= 0.0) ++flipped;
    }
    return flipped;
}

}  // namespace ngi
