// ngi offline eval, peers at equal bytes (DESIGN.md "Metrics"): meshoptimizer simplification
// (QSlim-style) searched for the triangle count whose Draco bitstream fits a byte budget.
#include "ngi/eval/equal_bytes.h"

#include <algorithm>
#include <optional>

namespace ngi {

EqualBytesResult simplifyToByteBudget(const TriangleMesh& mesh, size_t byteBudget,
                                      const EqualBytesOptions& options)
{
    struct Candidate {
        SimplifyResult simplified;
        std::vector<uint8_t> bytes;
        uint32_t target = 0;
    };
    uint32_t evaluations = 0;
    auto evaluate = [&](uint32_t target) {
        ++evaluations;
        Candidate c;
        c.target = target;
        if (target >= mesh.triangles.size()) {
            c.simplified.mesh = mesh; // no simplification at all
            c.simplified.reachedTarget = true;
        } else {
            SimplifyOptions so;
            so.targetTriangleCount = target;
            so.lockBorder = options.lockBorder;
            c.simplified = simplifyMesh(mesh, so);
        }
        c.bytes = encodeDraco(c.simplified.mesh, options.draco);
        return c;
    };

    const uint32_t top = uint32_t(mesh.triangles.size());
    uint32_t lo = std::min(std::max<uint32_t>(options.minTriangleCount, 1), top);
    std::optional<Candidate> best;
    Candidate full = evaluate(top);
    if (full.bytes.size() <= byteBudget) {
        best = std::move(full);
    } else {
        Candidate low = evaluate(lo);
        if (low.bytes.size() > byteBudget) {
            EqualBytesResult r;
            r.simplified = std::move(low.simplified.mesh);
            r.decoded = decodeDraco(low.bytes);
            r.dracoBytes = low.bytes.size();
            r.targetTriangleCount = lo;
            r.evaluations = evaluations;
            r.budgetMet = false;
            return r;
        }
        best = std::move(low);
        // Invariant: bytes(lo) <= budget < bytes(hi).
        uint32_t hi = top;
        while (hi - lo > 1) {
            const uint32_t mid = lo + (hi - lo) / 2;
            Candidate c = evaluate(mid);
            if (c.bytes.size() <= byteBudget) {
                lo = mid;
                best = std::move(c);
            } else {
                hi = mid;
            }
        }
    }
    EqualBytesResult r;
    r.decoded = decodeDraco(best->bytes);
    r.simplified = std::move(best->simplified.mesh);
    r.dracoBytes = best->bytes.size();
    r.targetTriangleCount = best->target;
    r.evaluations = evaluations;
    r.budgetMet = true;
    return r;
}

} // namespace ngi
