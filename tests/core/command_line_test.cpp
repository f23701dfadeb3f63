// The argv number readers shared by the tools (ngi/command_line.h): negative, out-of-range,
// non-finite and malformed values are one UsageError naming the flag and the value.
#include "ngi/command_line.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>

namespace {

std::string usageError(const std::function<void()>& f)
{
    try {
        f();
    } catch (const ngi::UsageError& e) {
        return e.what();
    }
    return "";
}

TEST(CommandLine, IntegersAreDigitsOnlyAndWithinTheirRange)
{
    EXPECT_EQ(ngi::parseIntegerOptionInRange("--steps", "4000", 0, 1000000), 4000u);
    EXPECT_EQ(ngi::parseIntegerOptionInRange("--seed", "18446744073709551615", 0, UINT64_MAX), UINT64_MAX);
    EXPECT_EQ(usageError([] { ngi::parseIntegerOptionInRange("--steps", "-1", 0, 100); }),
              "--steps expects an integer in [0, 100], got '-1'");
    EXPECT_EQ(usageError([] { ngi::parseIntegerOptionInRange("--scale", "4294967304", 2, 1024); }),
              "--scale expects an integer in [2, 1024], got '4294967304'");
    for (const char* bad : {"", " 5", "+5", "5 ", "0x10", "1e3", "18446744073709551616", "99999999999999999999999"})
        EXPECT_NE(usageError([&] { ngi::parseIntegerOptionInRange("--n", bad, 0, UINT64_MAX); }), "") << bad;
    EXPECT_NE(usageError([] { ngi::parseIntegerOptionInRange("--scale", "1", 2, 1024); }), "");
}

TEST(CommandLine, FloatsAreFiniteAndIntegersOfTheOldReaderRefuseNegatives)
{
    EXPECT_EQ(usageError([] { ngi::parseFloatOption("--max-error", "1e999"); }),
              "--max-error expects a number, got '1e999'");
    EXPECT_NE(usageError([] { ngi::parseFloatOption("--lod", "nan"); }), "");
    EXPECT_FLOAT_EQ(ngi::parseFloatOption("--lod", "2.5"), 2.5f);
    EXPECT_NE(usageError([] { ngi::parseUintOption("--size", "-1"); }), "");
    EXPECT_NE(usageError([] { ngi::parseUintOption("--size", "4294967304"); }), "");
}

}  // namespace
