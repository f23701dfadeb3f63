// Integer border lengths across charts (group_lengths.h): every chart's perimeter filled
// exactly, lengths near their targets, and the systems that have no solution refused.
#include "ngi/error.h"
#include "ngi/param/group_lengths.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using ngi::BorderLengthClass;

BorderLengthClass shared(uint32_t a, uint32_t b, double target) { return {target, 1.0 / target, {{a, 1}, {b, 1}}}; }
BorderLengthClass cutPath(uint32_t c, double target) { return {target, 2.0 / target, {{c, 2}}}; }
BorderLengthClass open(uint32_t c, double target) { return {target, 1.0 / target, {{c, 1}}}; }

// Every chart's classes sum to its perimeter, every length >= 1.
void expectFilled(const std::vector<BorderLengthClass>& classes, const std::vector<long>& perimeters,
                  const ngi::GroupLengths& g)
{
    ASSERT_TRUE(g.solved) << g.problem;
    ASSERT_EQ(g.units.size(), classes.size());
    std::vector<long> sum(perimeters.size(), 0);
    for (size_t k = 0; k < classes.size(); ++k) {
        EXPECT_GE(g.units[k], 1);
        for (const auto& [chart, count] : classes[k].uses) sum[chart] += long(count) * g.units[k];
    }
    for (size_t c = 0; c < perimeters.size(); ++c) EXPECT_EQ(sum[c], perimeters[c]) << "chart " << c;
}

TEST(GroupLengths, OneChartIsFilledByItsOpenSegmentNearTheTargets)
{
    // Two cut paths and an open segment of one 64-cell chart (perimeter 256), targets off by
    // fractions: rounding leaves an error the open segment takes.
    const std::vector<BorderLengthClass> classes{cutPath(0, 40.4), cutPath(0, 30.3), open(0, 114.2)};
    const std::vector<long> perimeters{256};
    const ngi::GroupLengths g = ngi::solveGroupLengths(classes, perimeters, 1);
    expectFilled(classes, perimeters, g);
    EXPECT_EQ(g.units[0], 40);
    EXPECT_EQ(g.units[1], 30);
    EXPECT_EQ(g.units[2], 116);
}

TEST(GroupLengths, ThreeDisksInATriangleGetTheirOnlySolution)
{
    // Three pieces of a closed surface, each a disk bounded by its two shared curves: the
    // lengths are fixed by the perimeters (n_ab = (P_a + P_b - P_c) / 2, ...), whatever the
    // targets say.
    const std::vector<BorderLengthClass> classes{shared(0, 1, 150.0), shared(1, 2, 90.0), shared(0, 2, 40.0)};
    const std::vector<long> perimeters{256, 256, 128};
    const ngi::GroupLengths g = ngi::solveGroupLengths(classes, perimeters, 1);
    expectFilled(classes, perimeters, g);
    EXPECT_EQ(g.units[0], 192);
    EXPECT_EQ(g.units[1], 64);
    EXPECT_EQ(g.units[2], 64);
    EXPECT_GT(g.repairWalks, 0u);
}

TEST(GroupLengths, AnErrorTravelsAlongSharedCurvesToAnOpenSegment)
{
    // A chain of disks 0 - 1 - 2 - 3, chart 3 with an open segment (the input's boundary): chart
    // 0's rounding error can only be absorbed three curves away.
    const std::vector<BorderLengthClass> classes{shared(0, 1, 100.0), cutPath(0, 78.0),    shared(1, 2, 100.0),
                                                 cutPath(1, 28.0),    shared(2, 3, 100.0), cutPath(2, 28.0),
                                                 open(3, 156.0)};
    const std::vector<long> perimeters{256, 256, 256, 256};  // the rounded targets fill them exactly
    ngi::GroupLengths g = ngi::solveGroupLengths(classes, perimeters, 1);
    expectFilled(classes, perimeters, g);
    EXPECT_EQ(g.repairWalks, 0u);
    // Curve 0-1 rounds to 99 and chart 1's cut path to 29: chart 0 misses a unit and chart 1
    // has one too many. Chart 0 can only gain through curve 0-1, which gives chart 1 a second
    // unit too many; that one leaves through curve 1-2, comes back into chart 2 through curve
    // 2-3 and ends in chart 3's open segment.
    std::vector<BorderLengthClass> skewed = classes;
    skewed[0].target = 98.6;
    skewed[3].target = 28.5;
    g = ngi::solveGroupLengths(skewed, perimeters, 1);
    expectFilled(skewed, perimeters, g);
    EXPECT_GT(g.repairWalks, 0u);
}

TEST(GroupLengths, RefusesWhatHasNoSolution)
{
    // Two disks sharing their whole border cannot have perimeters 256 and 128.
    {
        const std::vector<BorderLengthClass> classes{shared(0, 1, 200.0)};
        const ngi::GroupLengths g = ngi::solveGroupLengths(classes, std::vector<long>{256, 128}, 1);
        EXPECT_FALSE(g.solved);
        EXPECT_NE(g.problem.find("cannot fill its perimeter"), std::string::npos) << g.problem;
    }
    // A bipartite cycle of four disks needs P_0 + P_2 = P_1 + P_3.
    {
        const std::vector<BorderLengthClass> classes{shared(0, 1, 128.0), shared(1, 2, 64.0), shared(2, 3, 128.0),
                                                     shared(3, 0, 64.0)};
        EXPECT_TRUE(ngi::solveGroupLengths(classes, std::vector<long>{256, 256, 128, 128}, 1).solved);
        EXPECT_FALSE(ngi::solveGroupLengths(classes, std::vector<long>{256, 128, 256, 256}, 1).solved);
    }
    EXPECT_THROW(ngi::solveGroupLengths(std::vector<BorderLengthClass>{shared(0, 5, 10.0)}, std::vector<long>{8, 8}, 1),
                 ngi::Error);
    EXPECT_THROW(ngi::solveGroupLengths(std::vector<BorderLengthClass>{}, std::vector<long>{}, 1), ngi::Error);
    EXPECT_THROW(ngi::solveGroupLengths(std::vector<BorderLengthClass>{{10.0, 1.0, {{0, 0}}}}, std::vector<long>{8}, 1),
                 ngi::Error);
}

TEST(GroupLengths, RandomChartGraphsWithCutPathsAreFilledCloseToTheirTargets)
{
    // Charts on a ring (bipartite for an even count: errors of one sign on charts of one colour
    // pair only through a cut path), each with one cut path; targets are a real-valued layout
    // plus noise, so the integer solution stays within a few units of them.
    std::mt19937 random(7);
    for (int trial = 0; trial < 50; ++trial) {
        const uint32_t charts = 3 + uint32_t(random() % 14);
        std::vector<long> perimeters(charts);
        for (long& p : perimeters) p = 4L * (16L << (random() % 3));  // R 16, 32 or 64 (q = 1)
        std::vector<BorderLengthClass> classes;
        std::uniform_real_distribution<double> noise(-3.0, 3.0);
        std::vector<double> budget(perimeters.begin(), perimeters.end());
        for (uint32_t c = 0; c < charts; ++c) {
            const uint32_t next = (c + 1) % charts;
            const double t = 0.25 * std::min(budget[c], budget[next]);
            classes.push_back(shared(c, next, std::max(1.0, t + noise(random))));
            budget[c] -= t, budget[next] -= t;
        }
        for (uint32_t c = 0; c < charts; ++c)
            classes.push_back(cutPath(c, std::max(1.0, 0.5 * budget[c] + noise(random))));
        const ngi::GroupLengths g = ngi::solveGroupLengths(classes, perimeters, 1);
        SCOPED_TRACE("trial " + std::to_string(trial) + ", " + std::to_string(charts) + " charts");
        expectFilled(classes, perimeters, g);
        double worst = 0.0;
        for (size_t k = 0; k < classes.size(); ++k)
            worst = std::max(worst, std::abs(double(g.units[k]) - classes[k].target));
        EXPECT_LT(worst, 12.0);
    }
}

TEST(GroupLengths, DisksOfAClosedSurfaceFindASolutionWhereOneExists)
{
    // Pieces of a closed surface that are all disks (every class a shared curve): a random graph
    // of triangles and chords, perimeters made from a known integer solution, targets that
    // solution plus noise of up to 3 units: the repair finds a filling near the targets.
    std::mt19937 random(11);
    for (int trial = 0; trial < 50; ++trial) {
        const uint32_t charts = 4 + uint32_t(random() % 12);
        std::vector<BorderLengthClass> classes;
        std::vector<long> truth;
        auto add = [&](uint32_t a, uint32_t b) {
            truth.push_back(4 + long(random() % 60));
            classes.push_back(shared(a, b, 0.0));
        };
        for (uint32_t c = 0; c < charts; ++c) add(c, (c + 1) % charts);
        for (uint32_t c = 0; c + 2 < charts; c += 2) add(c, c + 2);  // chords: triangles
        for (int extra = 0; extra < 3; ++extra) {
            const uint32_t a = uint32_t(random() % charts), b = uint32_t(random() % charts);
            if (a != b) add(a, b);
        }
        std::vector<long> perimeters(charts, 0);
        std::uniform_real_distribution<double> noise(-3.0, 3.0);
        for (size_t k = 0; k < classes.size(); ++k) {
            for (const auto& [chart, count] : classes[k].uses) perimeters[chart] += truth[k];
            classes[k].target = std::max(1.0, double(truth[k]) + noise(random));
            classes[k].weight = 1.0 / classes[k].target;
        }
        const ngi::GroupLengths g = ngi::solveGroupLengths(classes, perimeters, 1);
        SCOPED_TRACE("trial " + std::to_string(trial) + ", " + std::to_string(charts) + " charts");
        expectFilled(classes, perimeters, g);
    }
}

}  // namespace
