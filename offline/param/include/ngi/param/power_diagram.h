// ngi offline: the power diagram of weighted sites clipped to the unit square (paper
// Algorithm 1, lines 4-6: D(h), T(h), w(h)), built on CGAL's Regular_triangulation_2.
#pragma once

#include <glm/vec2.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace ngi {

// The facet W_i n W_j n Omega between two cells, for the Hessian of Eq. 6.
struct PowerFacet {
    uint32_t i, j;    // i < j
    double length;    // |e_ij|, the length of the common facet inside the square
    double distance;  // |p_i - p_j|
};

struct PowerCells {
    std::vector<double> area;          // |W_i n Omega| per site
    std::vector<glm::dvec2> centroid;  // centroid of W_i n Omega (the site itself if empty)
    std::vector<PowerFacet> facets;    // every facet with positive length (only if requested)
    size_t emptyCells = 0;             // sites whose clipped cell has zero area (hidden or clipped away)
};

// Power cells W_i = { x : |x - p_i|^2 - h_i <= |x - p_j|^2 - h_j for all j } (CGAL's
// convention: weight = h) intersected with [0,1]^2. Each cell is the square clipped by the
// power bisectors of its regular-triangulation neighbours, in coordinates centred on the site
// (no infinite faces; cells are clipped in parallel on `threads` threads).
// Sites must be distinct and inside the square; `heights` has one entry per site.
PowerCells computePowerCells(std::span<const glm::dvec2> sites, std::span<const double> heights, bool withFacets,
                             unsigned threads = 2);

}  // namespace ngi
