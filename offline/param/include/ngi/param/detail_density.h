// ngi offline: a target measure for the optimal transport that follows detail. The
// paper's OT (section 3.1, Eq. 2-4) gives each site p_i the image area nu_i; with
// nu_i its share of the surface area the map is area-preserving, so a fixed sample budget is
// spread evenly. Semi-discrete OT takes any nu: nu_i proportional to area_i * rho_i puts
// rho_i times more samples per unit area where rho is large. Here rho grows with the surface's
// mean curvature, where piecewise-smooth interpolation of the image errs most.
#pragma once

#include "ngi/param/disk_topology.h"

#include <vector>

namespace ngi {

// Largest curvature ratio kept (pointwise |H| over its area-weighted mean): a few sharp
// vertices (creases, spikes) must not take the whole budget.
inline constexpr double kMaxDetailRatio = 8.0;
// The strengths the tools accept (ngi-bake --detail-density): past it the cap decides alone.
inline constexpr double kMaxDetailDensity = 64.0;

// Per vertex of `disk.mesh`: the OT target nu_i = area_i * (1 + strength * k_i) / sum, k_i the
// vertex's mean-curvature magnitude over its area-weighted mean on the surface (smoothed over
// two rings, clamped to kMaxDetailRatio). Curvature is measured on the uncut surface: edges of
// the cut are joined through `disk.originalVertex` (when it is set), so the seam does not read
// as a crease. strength 0 returns the area measure exactly (vertexAreas, normalized); a flat
// surface returns it for any strength. Throws ngi::Error when strength is negative or not finite.
std::vector<double> detailDensityTargets(const DiskMesh& disk, double strength);

}  // namespace ngi
