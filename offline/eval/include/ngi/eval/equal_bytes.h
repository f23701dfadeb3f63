// ngi offline eval, peers at EQUAL BYTES (docs/DESIGN.md "Metrics"): the mesh a user would ship
// instead of an .ngi asset of the same size, i.e. the input simplified by meshoptimizer
// (QSlim-style) to the largest triangle count whose Draco encoding (14-bit positions) fits
// the byte budget.
#pragma once

#include "ngi/eval/draco_codec.h"
#include "ngi/eval/simplify.h"

#include <cstddef>
#include <cstdint>

namespace ngi {

struct EqualBytesOptions {
    DracoOptions draco;             // 14-bit positions by default
    bool lockBorder = false;        // passed to the simplifier
    uint32_t minTriangleCount = 4;  // the search's lower end
};

struct EqualBytesResult {
    TriangleMesh simplified;           // the simplifier's output (original double positions)
    TriangleMesh decoded;              // what a user gets back from the Draco bytes (quantized):
                                       //   measure CD/HD on this one
    size_t dracoBytes = 0;             // size of the Draco bitstream of `simplified`
    uint32_t targetTriangleCount = 0;  // the simplifier's target that produced it
    uint32_t evaluations = 0;          // simplify + encode runs the search made
    bool budgetMet = false;            // false: no non-empty simplification fits; the smallest
                                       //   non-empty one evaluated is given instead
};

// Finds, by bisection on the simplifier's target triangle count in [minTriangleCount,
// triangles of `mesh`], the largest target whose Draco bytes are <= `byteBudget`, and
// returns that mesh. If the whole mesh fits it is returned unsimplified. A target so small
// that the simplifier removes every triangle (closed meshes) never counts as meeting the
// budget. Draco's size grows
// with the triangle count but not strictly (bisection assumes it does; the result always
// fits the budget when budgetMet). Throws ngi::Error like simplifyMesh and encodeDraco.
EqualBytesResult simplifyToByteBudget(const TriangleMesh& mesh, size_t byteBudget,
                                      const EqualBytesOptions& options = {});

}  // namespace ngi
