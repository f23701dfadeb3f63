// ngi-train's --init (transfer learning), --normal-l1 and number flags: a bad donor file, weight
// or number is one clear error naming it, exit 1, before the training set loads, and the
// --export file already there is left untouched.
#include "run_tool.h"
#include "tiny_network.h"

#include "ngi/network_weights.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
}

}  // namespace

TEST(TrainCli, ABadInitFileIsOneErrorNamingItAndKeepsTheExport)
{
    const fs::path dir = fs::temp_directory_path() / "ngi_train_cli_test";
    fs::remove_all(dir);
    fs::create_directories(dir / "data");  // empty: the error must come before it is read
    const fs::path exported = dir / "out.ngiw";
    {
        std::ofstream(exported) << "previous network";
    }

    // A weights file cut in half.
    const fs::path whole = dir / "donor.ngiw", cut = dir / "cut.ngiw";
    ngi::writeNetworkWeights(ngi::test::smallDefaultNetwork("donor", 3, 0.5f), whole);
    const std::string bytes = slurp(whole);
    {
        std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    }

    for (const fs::path& bad : {dir / "missing.ngiw", cut}) {
        const ngi::test::ToolRun r =
            ngi::test::runShell(std::string(NGI_TRAIN_BIN) + " --data " + (dir / "data").string() +
                                " --scale 4 --steps 1 --init " + bad.string() + " --export " + exported.string());
        EXPECT_EQ(r.exitCode, 1) << r.output;
        EXPECT_NE(r.output.find(bad.string()), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("training geometry images"), std::string::npos) << r.output;  // nothing loaded
        EXPECT_EQ(slurp(exported), "previous network");
    }
    fs::remove_all(dir);
}

TEST(TrainCli, ABadNormalL1WeightIsOneErrorNamingTheFlagAndKeepsTheExport)
{
    // --normal-l1 W (the point-to-plane term's weight): a number in [0, 1000], refused before
    // the training set loads.
    const fs::path dir = fs::temp_directory_path() / "ngi_train_cli_normal_l1";
    fs::remove_all(dir);
    fs::create_directories(dir / "data");
    const fs::path exported = dir / "out.ngiw";
    {
        std::ofstream(exported) << "previous network";
    }
    for (const char* bad : {"abc", "", "2x", "-1", "nan", "1e9"}) {
        SCOPED_TRACE(bad);
        const ngi::test::ToolRun r =
            ngi::test::runShell(std::string(NGI_TRAIN_BIN) + " --data " + (dir / "data").string() +
                                " --scale 4 --steps 1 --normal-l1 '" + bad + "' --export " + exported.string());
        EXPECT_EQ(r.exitCode, 1) << r.output;
        EXPECT_NE(r.output.find("--normal-l1"), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("training geometry images"), std::string::npos) << r.output;  // nothing loaded
        EXPECT_EQ(slurp(exported), "previous network");
    }
    fs::remove_all(dir);
}

TEST(TrainCli, NegativeAndOutOfRangeNumbersAreOneErrorNamingTheFlag)
{
    // --steps -1 used to wrap to 2^64-1 (a run that never ends, with a negative ETA) and
    // --scale 4294967304 to be truncated to x8: both refused before the training set loads.
    const fs::path dir = fs::temp_directory_path() / "ngi_train_cli_numbers";
    fs::remove_all(dir);
    fs::create_directories(dir / "data");
    const fs::path exported = dir / "out.ngiw";
    {
        std::ofstream(exported) << "previous network";
    }
    const struct {
        std::string flags, message;
    } cases[] = {
        {"--scale 4 --steps -1", "--steps expects an integer in [0, 1099511627776], got '-1'"},
        {"--scale 4294967304 --steps 1", "--scale expects an integer in [2, 1024], got '4294967304'"},
        {"--scale -4 --steps 1", "--scale expects an integer in [2, 1024], got '-4'"},
        {"--scale 4 --steps 1 --batch 4294967297", "--batch expects an integer in [0, 1048576], got '4294967297'"},
        {"--scale 4 --steps 1 --seed 18446744073709551616", "--seed expects an integer"},
        {"--scale 4 --steps 1 --decoded-steps 4,-8", "--decoded-steps expects an integer in [0, 1048576], got '-8'"},
        {"--scale 4 --steps 1 --lr 1e999", "--lr expects a number, got '1e999'"},
        {"--scale 4 --steps 1 --export ''", "--export: the output path is empty"},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.flags);
        const ngi::test::ToolRun r =
            ngi::test::runShell(std::string(NGI_TRAIN_BIN) + " --data " + (dir / "data").string() + " " + c.flags +
                                " --export " + exported.string());
        EXPECT_EQ(r.exitCode, 1) << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
        EXPECT_EQ(r.output.find("training geometry images"), std::string::npos) << r.output;  // nothing loaded
        EXPECT_EQ(slurp(exported), "previous network");
    }
    fs::remove_all(dir);
}
