// ngi offline: integer border lengths for a GROUP of charts whose borders share curves (one
// surface split into several charts, docs/cross-chart-seams.md section 3).
//
// Gu, Gortler, Hoppe 2002 ("Geometry Images", section 4) match the two sides of every cut path
// of one chart: equal integer lengths, nodes on multiples of 2^K. Across charts the same holds
// for a curve two charts share, but each chart's border segments must fill ITS perimeter 4 R_c
// exactly, so the lengths of all charts are one system: for every chart c,
//   sum over classes k of uses(k, c) * x_k = 4 R_c / q,   x_k >= 1 integer (units of q),
// uses(k, c) being 2 for a cut path within c, 1 in each of the two charts of a shared curve
// and 1 for an open segment (the input's own boundary). Within one chart (matchBorder) an
// open segment or any pair of classes can absorb a rounding error; across charts whose
// borders are shared curves only (a disk piece of a closed surface) nothing inside a chart
// can: an error must travel along shared curves to a chart that needs the opposite or has an
// open segment. The repair below does exactly that, as augmenting walks in the chart graph.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace ngi {

struct BorderLengthClass {
    double target = 0.0;  // wanted length in samples (the mean of its sides' natural lengths)
    double weight = 1.0;  // of the squared deviation from the target (matchBorder: sides / target)
    // (chart, count): the charts whose perimeter the class fills and how often. A curve shared
    // by two charts: {(a, 1), (b, 1)}; a cut path within chart c: {(c, 2)}; open: {(c, 1)}.
    std::vector<std::pair<uint32_t, uint32_t>> uses;
};

struct GroupLengths {
    bool solved = false;
    std::vector<long> units;  // per class, in units of q (>= 1)
    size_t repairWalks = 0;   // augmenting walks that fixed the rounding
    std::string problem;      // why not solved: the chart whose perimeter cannot be filled
};

// Integer lengths x_k >= 1 in units of q, each near round(target / q), such that every chart's
// classes fill its perimeter `perimeterUnits[c]` (4 R_c / q) exactly. Starts from the rounded
// targets, then repeatedly fixes the chart with the largest error by the shortest walk of unit
// changes (+1 on one shared class, -1 on the next, ...; among equally short walks the one that
// costs least in weighted squared deviation) that ends in a chart wanting the opposite change or
// in an open segment; a cut path on the way may take two units and pass one on with the other
// sign (the only way to pair errors of one sign between charts of one colour of a bipartite
// chart graph). Not solved when no walk improves (e.g. two disks that share their whole
// border with different perimeters; a bipartite chain of disks whose alternating sums differ).
// ngi::Error on a class that names a chart outside perimeterUnits, no chart or a count of 0.
GroupLengths solveGroupLengths(std::span<const BorderLengthClass> classes, std::span<const long> perimeterUnits,
                               uint32_t q);

}  // namespace ngi
