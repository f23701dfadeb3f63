// The stored-level vocabulary (ngi/stored_level.h): level <-> resolution <-> size <-> CR,
// at the default 1024 and at other full resolutions (the CR is never against a fixed 1024).
#include "ngi/stored_level.h"

#include <gtest/gtest.h>

namespace {

TEST(StoredLevel, DefaultBakeIsLevelThreeWithCr64)
{
    EXPECT_EQ(ngi::storedLevelOf(1024, 128), 3u);
    EXPECT_EQ(ngi::storedResolutionAt(1024, 3), 128u);
    EXPECT_EQ(ngi::storedSizeAt(1024, 3), 129u);
    EXPECT_EQ(ngi::restoreFactor(3), 8u);
    EXPECT_DOUBLE_EQ(ngi::compressionRatio(1024, 128), 64.0);
    EXPECT_DOUBLE_EQ(ngi::compressionRatioAtLevel(3), 64.0);
}

TEST(StoredLevel, CompressionRatioFollowsTheFullResolution)
{
    // --resolution 32 --store-res 8: CR 16, not 1024^2 / 8^2.
    EXPECT_DOUBLE_EQ(ngi::compressionRatio(32, 8), 16.0);
    EXPECT_DOUBLE_EQ(ngi::compressionRatio(2048, 128), 256.0);
    EXPECT_DOUBLE_EQ(ngi::compressionRatio(512, 512), 1.0);
    for (uint32_t full : {2u, 32u, 1024u, 4096u})
        for (uint32_t level = 0; (full >> level) >= 1; ++level) {
            const uint32_t stored = ngi::storedResolutionAt(full, level);
            EXPECT_EQ(ngi::storedLevelOf(full, stored), level) << full << " level " << level;
            EXPECT_DOUBLE_EQ(ngi::compressionRatio(full, stored), ngi::compressionRatioAtLevel(level));
            EXPECT_EQ(stored * ngi::restoreFactor(level), full);
        }
}

TEST(StoredLevel, RejectsSizesThatAreNotALevel)
{
    EXPECT_THROW(ngi::storedLevelOf(1024, 96), ngi::Error);   // not a power of two
    EXPECT_THROW(ngi::storedLevelOf(1000, 125), ngi::Error);  // full size not a power of two
    EXPECT_THROW(ngi::storedLevelOf(128, 256), ngi::Error);   // finer than the full image
    EXPECT_THROW(ngi::storedLevelOf(128, 0), ngi::Error);
    try {
        ngi::storedLevelOf(1024, 96);
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("96"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("1024"), std::string::npos) << e.what();
    }
    EXPECT_DOUBLE_EQ(ngi::compressionRatio(1024, 0), 0.0);
}

}  // namespace
