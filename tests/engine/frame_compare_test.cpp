// ngi-render --compare's metric (engine/tools/frame_compare.h) on small synthetic images:
// the threshold and the allowed fraction are exact boundaries, the statistics are the
// definitions', every PNG layout is read as the same RGBA8, a bad file is named.
#include "frame_compare.h"

#include "ngi/error.h"
#include "ngi/png_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

// A 10 x 10 RGBA8 gradient (every pixel distinct, opaque).
std::vector<uint8_t> gradient()
{
    std::vector<uint8_t> p(10 * 10 * 4);
    for (int i = 0; i < 100; ++i) {
        p[i * 4 + 0] = uint8_t(20 + 2 * i);
        p[i * 4 + 1] = uint8_t(200 - i);
        p[i * 4 + 2] = uint8_t(100 + (i % 10) * 5);
        p[i * 4 + 3] = 255;
    }
    return p;
}

TEST(FrameCompare, IdenticalFramesMatchWithZeroStatistics)
{
    const std::vector<uint8_t> a = gradient();
    const ngi::FrameComparison c = ngi::compareFrames(a.data(), a.data(), 10, 10);
    EXPECT_TRUE(c.matches);
    EXPECT_EQ(c.pixels, 100u);
    EXPECT_EQ(c.differingPixels, 0u);
    EXPECT_EQ(c.maxDifference, 0u);
    EXPECT_EQ(c.rmsDifference, 0.0);
}

TEST(FrameCompare, ThePixelThresholdIsExclusiveOnTheLargestChannel)
{
    const std::vector<uint8_t> a = gradient();
    std::vector<uint8_t> b = a;
    b[0 * 4 + 1] += 16;  // pixel 0: green by exactly the threshold -> tolerated
    b[1 * 4 + 2] += 17;  // pixel 1: blue by one more -> differs
    b[2 * 4 + 0] -= 5;   // pixel 2: red -5 and alpha -17: the max channel decides -> differs
    b[2 * 4 + 3] -= 17;
    const ngi::FrameCompareOptions options{.pixelThreshold = 16, .maxDifferingFraction = 0.02};
    const ngi::FrameComparison c = ngi::compareFrames(a.data(), b.data(), 10, 10, options);
    EXPECT_EQ(c.differingPixels, 2u);
    EXPECT_DOUBLE_EQ(c.differingFraction, 0.02);
    EXPECT_TRUE(c.matches);  // 2% allowed, 2% differ
    EXPECT_EQ(c.maxDifference, 17u);
    // RMS over 400 channel values of (16^2 + 17^2 + 5^2 + 17^2).
    EXPECT_NEAR(c.rmsDifference, std::sqrt((256.0 + 289.0 + 25.0 + 289.0) / 400.0), 1e-12);
    const ngi::FrameComparison strict =
        ngi::compareFrames(a.data(), b.data(), 10, 10, {.pixelThreshold = 16, .maxDifferingFraction = 0.019});
    EXPECT_FALSE(strict.matches);
    // Threshold 0: any change differs; threshold 255: nothing can.
    EXPECT_EQ(ngi::compareFrames(a.data(), b.data(), 10, 10, {.pixelThreshold = 0}).differingPixels, 3u);
    EXPECT_EQ(ngi::compareFrames(a.data(), b.data(), 10, 10, {.pixelThreshold = 255}).differingPixels, 0u);
}

TEST(FrameCompare, TheDefaultsRefuseAVisibleRegionAndAcceptNoise)
{
    const std::vector<uint8_t> a = gradient();
    std::vector<uint8_t> noisy = a, block = a;
    for (size_t i = 0; i < noisy.size(); i += 4) noisy[i] = uint8_t(noisy[i] + (i / 4) % 7);  // +0..6: shading noise
    block[0] = 255 - block[0];  // one pixel of 100 changed by 215: 1% > 0.5%
    EXPECT_TRUE(ngi::compareFrames(a.data(), noisy.data(), 10, 10).matches);
    const ngi::FrameComparison c = ngi::compareFrames(a.data(), block.data(), 10, 10);
    EXPECT_FALSE(c.matches);
    EXPECT_EQ(c.differingPixels, 1u);
    EXPECT_EQ(ngi::describe(c, {}),
              "1 of 100 pixels (1.000%) differ by more than 16/255 (allowed 0.500%); "
              "max difference 215/255, RMS 10.75/255");
}

TEST(FrameCompare, RefusesOptionsOutsideTheirRange)
{
    const std::vector<uint8_t> a = gradient();
    EXPECT_THROW(ngi::compareFrames(a.data(), a.data(), 10, 10, {.pixelThreshold = 256}), std::invalid_argument);
    EXPECT_THROW(ngi::compareFrames(a.data(), a.data(), 10, 10, {.maxDifferingFraction = 1.5}), std::invalid_argument);
    EXPECT_THROW(ngi::compareFrames(a.data(), a.data(), 10, 10, {.maxDifferingFraction = std::nan("")}),
                 std::invalid_argument);
}

TEST(FrameCompare, TheDifferenceImageColoursEachClass)
{
    const std::vector<uint8_t> a = gradient();
    std::vector<uint8_t> b = a;
    b[1 * 4 + 0] += 8;    // tolerated
    b[2 * 4 + 1] += 100;  // differs
    const std::vector<uint8_t> d = ngi::differenceImage(a.data(), b.data(), 10, 10, 16);
    ASSERT_EQ(d.size(), 400u);
    auto at = [&](int i, int c) { return int(d[i * 4 + c]); };
    // Unchanged: grey context (R = G = B), light (a quarter of the contrast under white).
    EXPECT_EQ(at(0, 0), at(0, 1));
    EXPECT_EQ(at(0, 1), at(0, 2));
    EXPECT_GE(at(0, 0), 191);
    // Tolerated: blue dominates.
    EXPECT_GT(at(1, 2), at(1, 0) + 40);
    // Differing: red and no blue.
    EXPECT_GT(at(2, 0), 150);
    EXPECT_EQ(at(2, 2), 0);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(at(i, 3), 255);
}

class FrameComparePng : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() / ("ngi_frame_compare_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

TEST_F(FrameComparePng, EveryLayoutReadsAsTheSameRgba8)
{
    // One 2 x 1 image, gray 8 / gray+alpha 8 / RGB 16 / RGBA 8.
    const fs::path gray = dir_ / "g.png", grayAlpha = dir_ / "ga.png", rgb16 = dir_ / "rgb16.png",
                   rgba = dir_ / "rgba.png";
    ngi::writePng(gray, {.width = 2, .height = 1, .channels = 1, .bitDepth = 8, .samples = {10, 250}});
    ngi::writePng(grayAlpha, {.width = 2, .height = 1, .channels = 2, .bitDepth = 8, .samples = {10, 128, 250, 255}});
    ngi::writePng(rgb16,
                  {.width = 2,
                   .height = 1,
                   .channels = 3,
                   .bitDepth = 16,
                   .samples = {10 * 257, 10 * 257, 10 * 257, 65535, 128, 0}});
    const uint8_t pixels[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    ngi::writePng8(rgba, 2, 1, 4, pixels);
    EXPECT_EQ(ngi::readRgba8Png(gray).pixels, (std::vector<uint8_t>{10, 10, 10, 255, 250, 250, 250, 255}));
    EXPECT_EQ(ngi::readRgba8Png(grayAlpha).pixels, (std::vector<uint8_t>{10, 10, 10, 128, 250, 250, 250, 255}));
    EXPECT_EQ(ngi::readRgba8Png(rgb16).pixels, (std::vector<uint8_t>{10, 10, 10, 255, 255, 0, 0, 255}));
    const ngi::Rgba8Image image = ngi::readRgba8Png(rgba);
    EXPECT_EQ(image.width, 2u);
    EXPECT_EQ(image.height, 1u);
    EXPECT_EQ(image.pixels, std::vector<uint8_t>(pixels, pixels + 8));
}

TEST_F(FrameComparePng, AMissingOrTruncatedFileIsNamed)
{
    const fs::path missing = dir_ / "missing.png", truncated = dir_ / "truncated.png", full = dir_ / "full.png";
    std::vector<uint8_t> pixels(64 * 64 * 4, 77);
    ngi::writePng8(full, 64, 64, 4, pixels.data());
    const auto size = fs::file_size(full);
    fs::copy_file(full, truncated);
    fs::resize_file(truncated, size / 2);
    for (const fs::path& p : {missing, truncated}) {
        try {
            ngi::readRgba8Png(p);
            ADD_FAILURE() << p << " was read";
        } catch (const ngi::Error& e) {
            EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
        }
    }
}

}  // namespace
