// The one union-find of the mesh stages (offline/mesh/src/union_find.h).
#include "union_find.h"

#include <gtest/gtest.h>

namespace {

using ngi::detail::UnionFind;

TEST(UnionFind, StartsAsSingletons)
{
    UnionFind sets(5);
    for (uint32_t i = 0; i < 5; ++i) EXPECT_EQ(sets.find(i), i);
}

TEST(UnionFind, UniteMergesAndReportsWhetherItDid)
{
    UnionFind sets(6);
    EXPECT_TRUE(sets.unite(0, 1));
    EXPECT_TRUE(sets.unite(2, 3));
    EXPECT_TRUE(sets.unite(1, 3));
    EXPECT_FALSE(sets.unite(0, 2));  // already one set: cut.cpp's cycle test relies on this
    EXPECT_FALSE(sets.unite(4, 4));
    const uint32_t root = sets.find(0);
    for (uint32_t i : {1u, 2u, 3u}) EXPECT_EQ(sets.find(i), root);
    EXPECT_NE(sets.find(4), root);
    EXPECT_EQ(sets.find(5), 5u);
    EXPECT_EQ(sets.find(3), sets.find(2));  // the merged set's representative is b's
}

TEST(UnionFind, LongChainsAreFoundAndShortened)
{
    // A chain 0 -> 1 -> ... -> n-1 built by unite(i, i + 1): every element finds n - 1, and
    // path halving leaves a shorter path behind than the one it walked.
    const uint32_t n = 1000;
    UnionFind sets(n);
    for (uint32_t i = 0; i + 1 < n; ++i) EXPECT_TRUE(sets.unite(i, i + 1));
    EXPECT_EQ(sets.find(0), n - 1);
    uint32_t steps = 0;
    for (uint32_t x = 0; sets.parent[x] != x; x = sets.parent[x]) ++steps;
    EXPECT_LT(steps, n - 1);
    for (uint32_t i = 0; i < n; ++i) EXPECT_EQ(sets.find(i), n - 1);
}

}  // namespace
