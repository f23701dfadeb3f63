// ngi offline: ngi-bake stage 4 with cut augmentation, the cut that a map to the square can
// use (Gu, Gortler, Hoppe 2002, "Geometry Images", section 3.2), measured with the paper's own
// conformal start (section 3.1, Eq. 1-2).
#pragma once

#include "ngi/mesh/cut.h"
#include "ngi/mesh/triangle_mesh.h"

#include <functional>
#include <string>
#include <vector>

namespace ngi {

struct ExtremityCutOptions {
    // Stop augmenting once no vertex of the conformal start is shrunk by more than this:
    // max_i log(mean area scale / area scale_i), area scale e^{u_i} of the Ricci flow. At
    // e^12 the OT start's sites are ~e^-6 of the mean spacing apart: the power diagram still
    // separates them and Newton converges in tens of iterations (measured on the CGAL data).
    double maxConformalShrink = 12.0;
    int maxPaths = 12;  // extremity paths at most
    CutOptions cut;     // passed to every cutToDisk (its `extremities` are the start)
    std::function<void(const std::string&)> progress;
};

struct ExtremityCutRound {
    double conformalShrink = 0.0;  // max log shrink of this round's cut (NaN: Ricci flow failed)
    double cutLength = 0.0;
};

struct ExtremityCutResult {
    CutResult cut;                         // the chosen cut (report.extremityPaths paths added)
    std::vector<ExtremityCutRound> rounds; // one per cut tried, in order
    double conformalShrink = 0.0;          // of the chosen cut
};

// Cuts `mesh` to a disk (cutToDisk), then repeatedly maps the disk conformally to the square
// (Ricci flow, the start of the OT map), finds the most shrunk vertex (the tip of a protrusion
// the cut left closed) and adds the shortest path from it to the cut, until the shrink is at
// most options.maxConformalShrink, maxPaths paths were added, or a path no longer reduces the
// shrink. Returns the cut with the smallest shrink seen. Throws what cutToDisk throws; a Ricci
// flow that fails on the first cut is not an error here (that cut is returned as is, and
// parameterization reports the failure).
ExtremityCutResult cutThroughExtremities(const TriangleMesh& mesh, const ExtremityCutOptions& options = {});

} // namespace ngi
