// ngi offline: ngi-bake stage 4 with cut augmentation, the cut that a map to the square can
// use (Gu, Gortler, Hoppe 2002, "Geometry Images", section 3.2), measured with the paper's own
// conformal start (section 3.1, Eq. 1-2).
#pragma once

#include "ngi/mesh/cut.h"
#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/ricci_flow.h"

#include <glm/vec3.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ngi {

struct ExtremityCutOptions {
    // Stop augmenting once no vertex of the conformal start is shrunk by more than this:
    // max_i log(mean area scale / area scale_i), area scale e^{u_i} of the Ricci flow. At
    // e^12 the OT start's sites are ~e^-6 of the mean spacing apart, which the power diagram
    // separates (OT converged from every start up to e^26 on the CGAL data, with the
    // homotopy; parameterize.cpp).
    double maxConformalShrink = 12.0;
    // Where the Ricci flow fails, the cut is measured by the Tutte map's shrink of interior
    // vertices (larger than the conformal one: camel e^15.9 for e^14.4 on the same cut) and
    // augmented while it exceeds this. Camel, dino and man have closed limbs at e^16.2-e^53;
    // elephant's flows fail at e^13.8 for other reasons (degenerate triangles at a crease).
    double maxTutteShrink = 15.0;
    int maxPaths = 12;  // extremity paths at most
    CutOptions cut;     // passed to every cutToDisk (its `extremities` are the start)
    // 2 or more: where both cut graphs are augmented, they are augmented side by side (the
    // result, the rounds and the progress lines are the same as on 1 thread).
    unsigned threads = 2;
    std::function<void(const std::string&)> progress;
};

struct ExtremityCutRound {
    double conformalShrink = 0.0;  // max log shrink of this round's cut (NaN: Ricci flow failed)
    double cutLength = 0.0;
    double tutteShrink = 0.0;  // max log shrink of an interior vertex under a Tutte map (the fallback measure)
};

// The cut a search chose, in a form that applies to another mesh of the same surface (a
// denser remesh of the same input part): the cut graph and the extremity tips in 3D.
struct ExtremityCutPlan {
    CutGraph graph = CutGraph::TreeCotree;
    std::vector<glm::dvec3> tips;  // in the order the paths were added
};

struct ExtremityCutResult {
    CutResult cut;                          // the chosen cut (report.extremityPaths paths added)
    ExtremityCutPlan plan;                  // how to make the same cut on another mesh of the surface
    std::vector<ExtremityCutRound> rounds;  // one per cut tried, in order
    double conformalShrink = 0.0;           // of the chosen cut
    // The chosen cut's Ricci flow (default RicciFlowOptions, corners by chooseCornerPositions),
    // if it converged: pass it as ParameterizeOptions::conformalStart instead of running it again.
    std::optional<RicciFlowResult> conformalStart;
    // The chosen cut's Ricci flow (same options) was run and failed: pass it as
    // ParameterizeOptions::conformalStartFailed so the flow is not run again to fail again.
    bool conformalStartFailed = false;
};

// Cuts `mesh` to a disk (cutToDisk). Then, while the conformal start shrinks some vertex by
// more than e^maxConformalShrink, it adds the shortest path from the interior vertex a Tutte
// map shrinks most (the tip of a protrusion the cut left closed) to the cut, until the shrink
// is small enough, maxPaths paths were added, or a path makes it worse. A cut whose Ricci flow
// fails is measured by its Tutte map's shrink and augmented the same way while that exceeds
// maxTutteShrink (until a cut's flow converges). For genus >= 1 or several boundary loops this
// runs from both cut graphs: if both end at most e^maxConformalShrink the shorter cut is kept,
// else the one with the smaller shrink (a converged flow before a failed one). `rounds` lists
// every cut measured. Throws what cutToDisk throws; a Ricci flow that fails is not an error
// here (parameterization then starts OT from a fixed-border map).
ExtremityCutResult cutThroughExtremities(const TriangleMesh& mesh, const ExtremityCutOptions& options = {});

// Makes the cut `plan` describes on `mesh` (each tip snapped to mesh's nearest vertex, then
// cutToDisk with the plan's graph and those extremities; options.cut.extremities are not
// used: the plan's tips include them) and measures its conformal start once, as
// cutThroughExtremities measures a round. Only if a planned tip fell on the base cut here
// (fewer extremity paths than tips) does it augment on `mesh` as cutThroughExtremities does
// (maxPaths, maxConformalShrink, maxTutteShrink). Why: the search costs one Ricci flow per
// candidate cut (femur at 1024: 5 candidates at 32k vertices in 116 s, then 6 more at 64k in
// 204 s); on a coarse remesh of the same part it finds the same protrusions in a fraction of
// that. The conformal shrink is measured on `mesh`. Throws what cutToDisk throws.
ExtremityCutResult cutByPlan(const TriangleMesh& mesh, const ExtremityCutPlan& plan,
                             const ExtremityCutOptions& options = {});

}  // namespace ngi
