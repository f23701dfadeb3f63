// ngi offline eval, peers at equal bytes (docs/DESIGN.md "Metrics"): meshoptimizer simplification
// (QSlim-style) searched for the triangle count whose Draco bitstream fits a byte budget.
#include "ngi/eval/equal_bytes.h"

#include <algorithm>
#include <optional>

namespace ngi {
namespace {

struct Candidate {
    TriangleMesh mesh;
    std::vector<uint8_t> bytes;  // empty when the simplifier removed every triangle
    uint32_t target = 0;
};

EqualBytesResult toResult(Candidate c, uint32_t evaluations, bool budgetMet)
{
    EqualBytesResult r;
    r.decoded = decodeDraco(c.bytes);
    r.simplified = std::move(c.mesh);
    r.dracoBytes = c.bytes.size();
    r.targetTriangleCount = c.target;
    r.evaluations = evaluations;
    r.budgetMet = budgetMet;
    return r;
}

}  // namespace

EqualBytesResult simplifyToByteBudget(const TriangleMesh& mesh, size_t byteBudget, const EqualBytesOptions& options)
{
    uint32_t evaluations = 0;
    auto evaluate = [&](uint32_t target) {
        ++evaluations;
        Candidate c;
        c.target = target;
        if (target >= mesh.triangles.size()) {
            c.mesh = mesh;  // no simplification at all
        } else {
            SimplifyOptions so;
            so.targetTriangleCount = target;
            so.lockBorder = options.lockBorder;
            c.mesh = simplifyMesh(mesh, so).mesh;
        }
        // On closed meshes a tiny target can collapse everything: no surface, no bytes.
        if (!c.mesh.triangles.empty()) c.bytes = encodeDraco(c.mesh, options.draco);
        return c;
    };
    // An empty result "fits" (0 bytes) so that the bisection stays monotone; it is never
    // returned as a met budget.
    auto fits = [&](const Candidate& c) { return c.bytes.size() <= byteBudget; };

    const uint32_t top = uint32_t(mesh.triangles.size());
    Candidate full = evaluate(top);
    if (fits(full)) return toResult(std::move(full), evaluations, true);

    uint32_t lo = std::min(std::max<uint32_t>(options.minTriangleCount, 1), top);
    Candidate low = evaluate(lo);
    if (!fits(low)) return toResult(std::move(low), evaluations, false);
    // Invariant: target lo fits (best), target hi does not (over).
    Candidate best = std::move(low), over = std::move(full);
    uint32_t hi = top;
    while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        Candidate c = evaluate(mid);
        if (fits(c)) {
            lo = mid;
            best = std::move(c);
        } else {
            hi = mid;
            over = std::move(c);
        }
    }
    if (best.bytes.empty())  // every target that fits collapses to nothing
        return toResult(std::move(over), evaluations, false);
    return toResult(std::move(best), evaluations, true);
}

}  // namespace ngi
