// ngi offline: maps a disk mesh bijectively onto the unit square (paper section 3.1).
// Methods: Tutte (uniform weights), harmonic (cotangent weights), discrete Ricci flow
// (conformal, paper Eq. 1-2), authalic, and the paper's optimal-transport refinement of the
// Ricci start (Algorithm 1, Eq. 4-6). Interface fixed for the baker; see parameterize.cpp
// and the per-method files for the algorithms.
#pragma once

#include "ngi/mesh/triangle_mesh.h"
#include "ngi/param/ricci_flow.h"

#include <glm/vec2.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ngi {

enum class ParameterizationMethod { Tutte, Harmonic, RicciConformal, Authalic, OptimalTransport };

// "tutte", "harmonic", "ricci", "authalic", "ot" <-> method. Parsing throws ngi::Error
// naming the bad value and listing the valid ones.
ParameterizationMethod parseParameterizationMethod(const std::string& name);
const char* parameterizationName(ParameterizationMethod method);

struct ParameterizeOptions {
    ParameterizationMethod method = ParameterizationMethod::OptimalTransport;
    // Called with one line of progress per major step (the tools print it; library code never does).
    std::function<void(const std::string&)> progress;
    // Method-specific tolerances (all defaulted).
    double ricciTolerance = 1e-9;  // Ricci flow: max |Kbar - K| in radians
    int ricciMaxIterations = 100;  // Ricci flow: Newton iterations
    double otTolerance = 1e-3;     // OT: max |w_i - nu_i| / nu_i
    int otMaxIterations = 100;     // OT: Newton iterations
    unsigned threads = 2;          // worker threads (power-cell clipping)
    // OT: the target measure's detail strength (detail_density.h); 0 = area-preserving (the paper).
    double detailDensity = 0.0;
    // Ricci/OT: the disk's Ricci flow, already computed with these tolerances and the corners
    // of chooseCornerPositions (cutThroughExtremities measures it); used instead of running
    // the flow again. Null: run it.
    const RicciFlowResult* conformalStart = nullptr;
    // Ricci/OT: that flow was run on this disk with these options and failed (the cut stage
    // saw it): OT starts from its fixed-border fallback at once.
    bool conformalStartFailed = false;
};

struct ParameterizeReport {
    int ricciIterations = 0;
    double ricciResidual = 0.0;  // max |target - actual| curvature after the flow
    int otIterations = 0;
    double otResidual = 0.0;          // max |area_i - target_i| / target_i
    double areaDistortionMax = 0.0;   // max over triangles of |log(uv area / 3D area)| (areas normalized to total 1)
    double areaDistortionMean = 0.0;  // area-weighted mean of the same
    double angleDistortionMax = 0.0;  // max |uv angle - 3D angle| in radians
    double angleDistortionMean = 0.0;
    size_t flippedTriangles = 0;  // triangles with non-positive uv area (must be 0)
    double secondsConformal = 0.0;
    double secondsTransport = 0.0;
    // Added by the implementation:
    double rectangleAspect = 1.0;         // Ricci/OT: width / height of the flat rectangle before the squash
    size_t ricciDegenerateTriangles = 0;  // Ricci/OT: triangles degenerate in the flat metric (see ricci_flow.h)
    size_t ricciLayoutFlips = 0;          // Ricci/OT: flipped triangles of the flat layout before untangling
    std::string otStart;  // OT: the start map, "ricci", "harmonic" (when the conformal one clusters too much),
                          // or "stretch-minimizing (OT from the ... map did not converge)" (the fallback)
    double otStartAreaDistortionMax = 0.0;  // OT: max |log(uv area / 3D area)| of that start
    int otHalvings = 0;                     // OT: total Newton step halvings
    size_t otCentroidFlips = 0;             // OT: flipped triangles of the raw centroid map (before untangling)
    bool otRelaxed = false;                 // OT: the mean-value relaxation ran (see untangle.h)
    double otRelaxDisplacement = 0.0;       // OT: largest uv move made by that relaxation
    size_t negativeWeights = 0;             // harmonic/authalic: non-positive weights of interior rows
    size_t clampedWeights = 0;              // harmonic/authalic: weights clamped positive to remove flips
    double secondsTotal = 0.0;
};

struct SquareMap {
    std::vector<glm::dvec2> uv;         // per vertex of the disk mesh, inside [0,1]^2
    std::array<uint32_t, 4> corners{};  // the boundary vertices mapped to (0,0), (1,0), (1,1), (0,1)
    ParameterizeReport report;
};

// Maps `disk` onto the unit square: boundary loop onto the square's border (four boundary
// vertices onto its corners), interior inside, no flipped triangle. Throws ngi::Error if the
// mesh is not a disk or a solver fails to converge (message says which and how far it got).
SquareMap parameterizeToSquare(const DiskMesh& disk, const ParameterizeOptions& options = {});

}  // namespace ngi
