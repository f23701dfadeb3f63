// The argv reader and number readers shared by the tools (ngi/command_line.h): a missing value
// or an unknown option is one UsageError naming the flag; negative, out-of-range, non-finite
// and malformed values are one UsageError naming the flag and the value.
#include "ngi/command_line.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

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

TEST(CommandLine, FloatsAreFiniteAndCountsRefuseNegatives)
{
    EXPECT_EQ(usageError([] { ngi::parseFloatOption("--max-error", "1e999"); }),
              "--max-error expects a number, got '1e999'");
    EXPECT_NE(usageError([] { ngi::parseFloatOption("--lod", "nan"); }), "");
    EXPECT_FLOAT_EQ(ngi::parseFloatOption("--lod", "2.5"), 2.5f);
    EXPECT_NE(usageError([] { ngi::parseUintOption("--size", "-1"); }), "");
    EXPECT_EQ(usageError([] { ngi::parseUintOption("--frames", "4294967304"); }),
              "--frames expects an integer in [0, 1048576], got '4294967304'");
    EXPECT_EQ(ngi::parseUintOption("--frames", "1048576"), 1048576u);
}

// The arguments read by a tool with options --size VALUE and --json, and positional paths:
// "option=value" per option, "path" per positional argument; the UsageError's text if any.
std::string readArguments(const std::vector<std::string>& arguments)
{
    std::string read;
    try {
        ngi::ArgReader args(arguments);
        while (args.next()) {
            if (args.is("--size", "-s"))
                read += args.flag() + "=" + args.value() + " ";
            else if (args.is("--json"))
                read += "--json ";
            else if (args.positional())
                read += args.flag() + " ";
            else
                throw args.unknown();
        }
    } catch (const ngi::UsageError& e) {
        return e.what();
    }
    return read;
}

TEST(ArgReader, ReadsOptionsValuesAndPositionalArgumentsInOrder)
{
    EXPECT_EQ(readArguments({}), "");
    EXPECT_EQ(readArguments({"a.ngi", "--size", "64x64", "--json", "b.ngi", "-s", "8x8"}),
              "a.ngi --size=64x64 --json b.ngi -s=8x8 ");
    // "-" alone and "" are positional arguments, not options.
    EXPECT_EQ(readArguments({"-", ""}), "-  ");
}

TEST(ArgReader, AValueIsTheNextArgumentWhateverItLooksLike)
{
    EXPECT_EQ(readArguments({"--size", "-1,0,0", "--size", "--json", "--size", "--"}),
              "--size=-1,0,0 --size=--json --size=-- ");
    // flag() names the option before and after value() (arguments evaluate in any order).
    ngi::ArgReader args(std::vector<std::string>{"--size", "8x8", "a"});
    ASSERT_TRUE(args.next());
    EXPECT_EQ(args.value(), "8x8");
    EXPECT_EQ(args.flag(), "--size");
    EXPECT_EQ(args.value(), "8x8");
    ASSERT_TRUE(args.next());
    EXPECT_TRUE(args.positional());
    EXPECT_EQ(args.flag(), "a");
    EXPECT_FALSE(args.next());
}

TEST(ArgReader, AMissingValueIsOneErrorNamingTheFlag)
{
    EXPECT_EQ(readArguments({"a.ngi", "--size"}), "--size expects a value");
    EXPECT_EQ(readArguments({"-s"}), "-s expects a value");
}

TEST(ArgReader, AnUnknownOptionIsOneErrorNamingIt)
{
    EXPECT_EQ(readArguments({"a.ngi", "--sise", "64x64"}), "unknown option --sise");
    EXPECT_EQ(readArguments({"-x"}), "unknown option -x");
    // A tool that takes no positional argument refuses one by the same call.
    ngi::ArgReader args(std::vector<std::string>{"extra"});
    ASSERT_TRUE(args.next());
    EXPECT_EQ(std::string(args.unknown().what()), "unexpected argument extra");
}

TEST(ArgReader, DoubleDashMakesTheRestPositional)
{
    EXPECT_EQ(readArguments({"--json", "--", "--size", "-x", "--"}), "--json --size -x -- ");
}

TEST(ArgReader, ReadsArgvFromTheFirstArgumentAfterTheProgram)
{
    const char* argv[] = {"tool", "sub", "--json", "a"};
    std::vector<std::string> read;
    ngi::ArgReader all(4, argv);
    while (all.next()) read.push_back(all.flag());
    EXPECT_EQ(read, (std::vector<std::string>{"sub", "--json", "a"}));
    ngi::ArgReader afterCommand(4, argv, 2);
    ASSERT_TRUE(afterCommand.next());
    EXPECT_TRUE(afterCommand.is("--json"));
    ngi::ArgReader none(1, argv);
    EXPECT_FALSE(none.next());
    EXPECT_FALSE(none.next());
}

}  // namespace
