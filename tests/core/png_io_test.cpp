// PNG input/output: 16-bit samples survive exactly; bad files give clear errors.
#include "ngi/error.h"
#include "ngi/png_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace {

TEST(PngIo, SixteenBitRoundTripIsExact)
{
    ngi::PngImage img;
    img.width = 7;
    img.height = 5;
    img.channels = 3;
    img.bitDepth = 16;
    for (uint32_t i = 0; i < 7 * 5 * 3; ++i) img.samples.push_back(uint16_t(i * 617 + 3));
    const auto path = std::filesystem::temp_directory_path() / "ngi_png16.png";
    ngi::writePng(path, img);
    const ngi::PngImage back = ngi::readPng(path);
    EXPECT_EQ(back.width, 7u);
    EXPECT_EQ(back.height, 5u);
    EXPECT_EQ(back.channels, 3u);
    EXPECT_EQ(back.bitDepth, 16u);
    EXPECT_EQ(back.samples, img.samples);
    std::filesystem::remove(path);
}

TEST(PngIo, TruncatedAndMissingFilesAreRejected)
{
    ngi::PngImage img;
    img.width = img.height = 16;
    img.channels = 4;
    img.bitDepth = 8;
    img.samples.assign(16 * 16 * 4, 200);
    const auto path = std::filesystem::temp_directory_path() / "ngi_png_trunc.png";
    ngi::writePng(path, img);
    const auto size = std::filesystem::file_size(path);
    std::filesystem::resize_file(path, size / 2);
    EXPECT_THROW(ngi::readPng(path), ngi::Error);
    std::filesystem::remove(path);
    EXPECT_THROW(ngi::readPng(path), ngi::Error);
}

}  // namespace
