// Integer border lengths for a group of charts sharing curves: the matched boundary of Gu,
// Gortler, Hoppe 2002 ("Geometry Images", section 4) across charts, the rounding repaired by
// augmenting walks (as in Ford and Fulkerson's augmenting paths) in the chart graph; see
// ngi/param/group_lengths.h.
#include "ngi/param/group_lengths.h"

#include "ngi/error.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <tuple>

namespace ngi {
namespace {

// A class as seen from one of its charts.
struct Incidence {
    uint32_t cls = 0;
    uint32_t count = 0;  // uses of the class in this chart
    long other = -1;     // the other chart of a shared curve, -1 for a class of this chart only
};

// One step of a walk: class `cls` changes by `change`.
struct Step {
    long previous = -1;  // the state it came from (-1: the start)
    uint32_t cls = 0;
    long change = 0;
};

}  // namespace

GroupLengths solveGroupLengths(std::span<const BorderLengthClass> classes, std::span<const long> perimeterUnits,
                               uint32_t q)
{
    const size_t charts = perimeterUnits.size();
    if (charts == 0) throw Error("group lengths: no chart");
    if (q == 0) throw Error("group lengths: a unit of 0 samples");
    std::vector<std::vector<Incidence>> incident(charts);
    for (uint32_t k = 0; k < classes.size(); ++k) {
        const auto& uses = classes[k].uses;
        if (uses.empty() || uses.size() > 2)
            throw Error("group lengths: class " + std::to_string(k) + " is used by " + std::to_string(uses.size()) +
                        " charts (1 or 2)");
        for (size_t u = 0; u < uses.size(); ++u) {
            const auto [chart, count] = uses[u];
            if (chart >= charts)
                throw Error("group lengths: class " + std::to_string(k) + " names chart " + std::to_string(chart) +
                            " of " + std::to_string(charts));
            if (count == 0) throw Error("group lengths: class " + std::to_string(k) + " is used 0 times");
            incident[chart].push_back({k, count, uses.size() == 2 ? long(uses[1 - u].first) : -1});
        }
    }

    GroupLengths out;
    std::vector<long>& x = out.units;
    x.resize(classes.size());
    for (size_t k = 0; k < classes.size(); ++k) x[k] = std::max(1L, long(std::llround(classes[k].target / q)));
    auto residuals = [&] {
        std::vector<long> r(perimeterUnits.begin(), perimeterUnits.end());
        for (size_t k = 0; k < classes.size(); ++k)
            for (const auto& [chart, count] : classes[k].uses) r[chart] -= long(count) * x[k];
        return r;
    };
    auto total = [](const std::vector<long>& r) {
        long sum = 0;
        for (long v : r) sum += std::abs(v);
        return sum;
    };
    auto cost = [&](uint32_t k, long change) {
        const double was = double(x[k]) * q - classes[k].target, now = double(x[k] + change) * q - classes[k].target;
        return classes[k].weight * (now * now - was * was);
    };

    std::vector<long> r = residuals();
    const long initial = total(r);
    // Each walk lowers the total error by at least one: this many walks at most.
    for (long walk = 0; walk <= initial && total(r) > 0; ++walk) {
        const size_t start = size_t(
            std::max_element(r.begin(), r.end(), [](long a, long b) { return std::abs(a) < std::abs(b); }) - r.begin());
        const long need0 = r[start] > 0 ? 1 : -1;
        // States: 2 per chart (the chart must receive +1 or -1 more), plus the sink.
        const size_t sink = 2 * charts;
        auto stateOf = [](size_t chart, long need) { return 2 * chart + (need > 0 ? 1 : 0); };
        using Key = std::tuple<long, double>;  // (steps, cost): shortest walks first, then cheapest
        std::vector<Key> best(sink + 1, Key{std::numeric_limits<long>::max(), 0.0});
        std::vector<Step> via(sink + 1);
        std::vector<char> done(sink + 1, 0);
        using Item = std::tuple<long, double, size_t>;
        std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
        const size_t s0 = stateOf(start, need0);
        best[s0] = {0, 0.0};
        queue.emplace(0, 0.0, s0);
        auto relax = [&](size_t from, size_t to, uint32_t k, long change, double add) {
            const auto [steps, c] = best[from];
            const Key key{steps + 1, c + add};
            if (done[to] || !(key < best[to])) return;
            best[to] = key;
            via[to] = {long(from), k, change};
            queue.emplace(std::get<0>(key), std::get<1>(key), to);
        };
        while (!queue.empty()) {
            const auto [steps, c, state] = queue.top();
            queue.pop();
            if (done[state] || Key{steps, c} != best[state]) continue;
            done[state] = 1;
            if (state == sink) break;
            const size_t chart = state / 2;
            const long need = state % 2 ? 1 : -1;
            for (const Incidence& in : incident[chart]) {
                if (x[in.cls] + need < 1) continue;  // a unit change in `need`'s direction must keep x >= 1
                const double add = cost(in.cls, need);
                if (in.other < 0) {
                    // A class of this chart alone: an open segment absorbs the unit; a cut path
                    // gives two: the starting chart keeps both when it misses two or more, any
                    // chart can keep one and pass the other on (it then must lose one: that
                    // turns the unit's sign, which a chain of charts of two colours needs).
                    if (in.count == 1 || (state == s0 && in.count == 2 && std::abs(r[start]) >= 2))
                        relax(state, sink, in.cls, need, add);
                    else if (in.count == 2)
                        relax(state, stateOf(chart, -need), in.cls, need, add);
                    continue;
                }
                if (in.count != 1) continue;
                // A shared curve: `chart` gets the unit, so does the other chart; that ends the
                // walk where it wanted one in that direction, else the other chart must lose it.
                const size_t other = size_t(in.other);
                // The starting chart already has its unit: a second one helps only if it missed two.
                const bool wanted = r[other] * need > 0 && (other != start || std::abs(r[start]) >= 2);
                if (wanted)
                    relax(state, sink, in.cls, need, add);
                else
                    relax(state, stateOf(other, -need), in.cls, need, add);
            }
        }
        if (!done[sink]) {
            out.problem = "chart " + std::to_string(start) + "'s border segments cannot fill its perimeter (off by " +
                std::to_string(r[start]) + " units of " + std::to_string(q) + " samples)";
            return out;
        }
        const std::vector<long> before = x;
        for (long state = long(sink); state != long(s0);) {
            const Step& step = via[size_t(state)];
            x[step.cls] += step.change;
            state = step.previous;
        }
        const std::vector<long> next = residuals();
        if (total(next) >= total(r) || std::any_of(x.begin(), x.end(), [](long v) { return v < 1; })) {
            x = before;  // the walk met itself and undid its own change: give up at this q
            out.problem = "the repair walk from chart " + std::to_string(start) + " does not lower the error";
            return out;
        }
        r = next;
        ++out.repairWalks;
    }
    if (total(r) != 0) {
        out.problem = "the border lengths do not fill every perimeter";
        return out;
    }
    out.solved = true;
    return out;
}

}  // namespace ngi
