// The ngi-bake tool: every bad input gives one clear error, a non-zero exit and no output file;
// a good input writes the asset, the full-resolution PNGs and the JSON summary.
#include "ngi/asset.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/network_catalog.h"
#include "ngi/png_io.h"

#include "../support/tiny_network.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

class BakeCli : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_bake_cli_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path file(const std::string& name) const { return dir_ / name; }
    void writeText(const std::string& name, const std::string& text) const
    {
        std::ofstream(file(name), std::ios::binary) << text;
    }

    // Runs ngi-bake with `arguments` (after the shell commands `shellPrefix`); returns the
    // exit code, stderr in `errors`.
    int bake(const std::string& arguments, std::string& errors, const std::string& shellPrefix = "") const
    {
        const fs::path errFile = dir_ / "stderr.txt";
        const std::string command =
            shellPrefix + "'" + NGI_BAKE_EXE + "' " + arguments + " > /dev/null 2> '" + errFile.string() + "'";
        const int status = std::system(command.c_str());
        std::ifstream in(errFile);
        std::stringstream text;
        text << in.rdbuf();
        errors = text.str();
        fs::remove(errFile);
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    // Expects failure naming `needle`, with nothing written to dir_ but the inputs.
    void expectFailure(const std::string& input, const std::string& needle, int code = 1, const std::string& extra = "")
    {
        SCOPED_TRACE(input);
        std::string errors;
        EXPECT_EQ(bake("'" + file(input).string() + "' -o '" + file("out.ngi").string() +
                           "' --resolution 32 --store-res 8 --json '" + file("out.json").string() + "' " + extra,
                       errors),
                  code);
        EXPECT_NE(errors.find(needle), std::string::npos) << errors;
        EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'),
                  code == 1 ? 1 : std::count(errors.begin(), errors.end(), '\n'))
            << "one message: " << errors;
        EXPECT_FALSE(fs::exists(file("out.ngi")));
        EXPECT_FALSE(fs::exists(file("out.json")));
        for (const auto& entry : fs::directory_iterator(dir_))
            EXPECT_EQ(entry.path().extension() == ".png" ||
                          entry.path().filename().string().find(".tmp") != std::string::npos,
                      false)
                << entry.path();
    }
    fs::path dir_;
};

TEST_F(BakeCli, BadInputsFailWithOneClearMessageAndNoOutput)
{
    expectFailure("missing.obj", "no such file");
    writeText("mesh.xyz", "0 0 0\n");
    expectFailure("mesh.xyz", "unknown mesh format");
    writeText("corrupt.off", "OFF\nthis is not a number\n");
    expectFailure("corrupt.off", "corrupt.off");
    writeText("empty.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
    expectFailure("empty.off", "no triangles");
    writeText("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
    expectFailure("nan.off", "nan.off");
    writeText("degenerate.obj", "v 0 0 0\nv 1 0 0\nv 1 0 0\nf 1 2 3\n");
    expectFailure("degenerate.obj", "degenerate");
}

// A FIFO (which a plain open waits on forever) or a directory as the mesh: one error naming
// it, under `timeout` so that a hang fails instead of blocking.
TEST_F(BakeCli, AFifoOrADirectoryAsTheMeshIsOneErrorNamingIt)
{
    ASSERT_EQ(::mkfifo(file("pipe.obj").c_str(), 0600), 0);
    fs::create_directories(file("folder.obj"));
    for (const std::string name : {"pipe.obj", "folder.obj"}) {
        std::string errors;
        EXPECT_EQ(bake("'" + file(name).string() + "' -o '" + file("out.ngi").string() + "'", errors, "timeout 120 "),
                  1)
            << errors;
        EXPECT_NE(errors.find(file(name).string() + ": "), std::string::npos) << errors;
        EXPECT_NE(errors.find("not a regular file"), std::string::npos) << errors;
        EXPECT_FALSE(fs::exists(file("out.ngi")));
    }
}

// An empty output path is a usage error naming the flag, not an output silently left out.
TEST_F(BakeCli, AnEmptyOutputPathIsAUsageErrorNamingTheFlag)
{
    ngi::writeMesh(file("torus.obj"), ngi::makeTorus(16, 8));
    for (const std::string flag : {"-o", "--json", "--export-mesh", "--export-full"}) {
        std::string errors;
        EXPECT_EQ(
            bake("'" + file("torus.obj").string() + "' -o '" + file("out.ngi").string() + "' " + flag + " ''", errors),
            2)
            << flag;
        EXPECT_NE(errors.find(flag + ": the output path is empty"), std::string::npos) << errors;
        EXPECT_FALSE(fs::exists(file("out.ngi")));
    }
}

// Repair instead of refusing: three triangles on one edge (a fin) and three disjoint parts
// bake, every part its own chart, and the JSON says what was repaired.
TEST_F(BakeCli, RepairsNonManifoldEdgesAndBakesEveryPart)
{
    std::string mesh;
    // Three disjoint tetrahedra-like closed parts (octahedra), the first with a fin on one edge.
    auto octahedron = [&](double cx, double r, int base) {
        const double v[6][3] = {{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}};
        for (auto& p : v)
            mesh += "v " + std::to_string(cx + p[0]) + " " + std::to_string(p[1]) + " " + std::to_string(p[2]) + "\n";
        const int f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
        for (auto& t : f)
            mesh += "f " + std::to_string(base + t[0]) + " " + std::to_string(base + t[1]) + " " +
                std::to_string(base + t[2]) + "\n";
    };
    octahedron(0.0, 1.0, 1);
    octahedron(3.0, 0.6, 7);
    octahedron(6.0, 0.3, 13);
    mesh += "v 0.5 0.5 1.5\nf 1 3 19\n";  // a fin on the edge between vertices 1 and 3
    writeText("parts.obj", mesh);
    std::string errors;
    ASSERT_EQ(bake("'" + file("parts.obj").string() + "' -o '" + file("parts.ngi").string() +
                       "' --resolution 64 --store-res 16 --json '" + file("parts.json").string() + "'",
                   errors),
              0)
        << errors;
    EXPECT_NE(errors.find("repaired 1 non-manifold edges"), std::string::npos) << errors;
    const ngi::Asset asset = ngi::readAsset(file("parts.ngi"));
    ASSERT_EQ(asset.charts.size(), 4u);  // three parts and the fin, now cut off as its own part
    std::ifstream json(file("parts.json"));
    const nlohmann::json summary = nlohmann::json::parse(json);
    EXPECT_EQ(summary["clean"]["nonManifoldEdges"].get<int>(), 1);
    EXPECT_EQ(summary["charts"].size(), 4u);
    EXPECT_EQ(summary["charts"][0]["resolution"].get<int>(), 64);
}

TEST_F(BakeCli, BadArgumentsAndUnwritableOutputsFail)
{
    ngi::writeMesh(file("torus.obj"), ngi::makeTorus(16, 8));
    std::string errors;
    EXPECT_EQ(bake("'" + file("torus.obj").string() + "'", errors), 2);  // no -o
    EXPECT_NE(errors.find("no output file"), std::string::npos) << errors;
    expectFailure("torus.obj", "--param", 2, "--param magic");
    expectFailure("torus.obj", "unknown option --bogus", 2, "--bogus");
    expectFailure("torus.obj", "--store-res expects a value", 2, "--store-res");
    expectFailure("torus.obj", "power of two", 1, "--resolution 100");
    expectFailure("torus.obj", "--export-full", 1, "--export-full '" + file("nowhere").string() + "'");
    EXPECT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("no/such/dir/out.ngi").string() + "'", errors),
              1);
    EXPECT_NE(errors.find("does not exist"), std::string::npos) << errors;
}

TEST_F(BakeCli, WritesAssetPngsAndJson)
{
    ngi::writeMesh(file("torus.obj"), ngi::makeTorus(24, 12));
    std::string errors;
    ASSERT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("torus.ngi").string() +
                       "' --resolution 32 --store-res 8 --remesh-vertices 600 --export-full '" + dir_.string() +
                       "' --json '" + file("torus.json").string() + "'",
                   errors),
              0)
        << errors;
    ngi::Asset asset = ngi::readAsset(file("torus.ngi"));
    ASSERT_EQ(asset.charts.size(), 1u);
    EXPECT_EQ(asset.charts[0].storedSize(), 9u);
    EXPECT_EQ(asset.fullResolution(), 32u);
    EXPECT_EQ(asset.sourceName, "torus.obj");
    EXPECT_NE(asset.sourceHash, 0u);
    ngi::PngImage positions = ngi::readPng(file("torus_position.png"));
    EXPECT_EQ(positions.width, 33u);
    EXPECT_EQ(positions.bitDepth, 16u);
    EXPECT_TRUE(fs::exists(file("torus_normal.png")));
    std::ifstream json(file("torus.json"));
    nlohmann::json summary = nlohmann::json::parse(json);
    for (const char* key : {"input", "clean", "charts", "genus", "boundaries", "parameterization", "seconds",
                            "peakMemoryBytes", "assetBytes", "compressionRatio"})
        EXPECT_TRUE(summary.contains(key)) << key;
    ASSERT_EQ(summary["charts"].size(), 1u);
    for (const char* key : {"remesh", "cut", "parameterization", "resolution", "areaFraction"})
        EXPECT_TRUE(summary["charts"][0].contains(key)) << key;
    EXPECT_EQ(summary["genus"].get<int>(), 1);
    EXPECT_EQ(summary["parameterization"]["flippedTriangles"].get<int>(), 0);
    EXPECT_TRUE(summary["seconds"].contains("remesh"));
}

// The asset names (HEAD networkId/networkHash) the shipped network whose
// factor restores its stored level, found by --networks DIR; the JSON says which; --no-network
// and a directory without one of that factor name none.
TEST_F(BakeCli, NamesTheShippedNetworkOfItsStoredLevelsFactor)
{
    ngi::writeMesh(file("torus.obj"), ngi::makeTorus(24, 12));
    fs::create_directories(dir_ / "nets");
    const ngi::NetworkWeights x4 = ngi::test::tinyNetwork(4, 0.0f);
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(8, 0.0f), dir_ / "nets" / "a_x8.ngiw");
    ngi::writeNetworkWeights(x4, dir_ / "nets" / "b_x4.ngiw");
    const std::string common = "'" + file("torus.obj").string() + "' -o '" + file("torus.ngi").string() +
        "' --resolution 32 --store-res 8 --remesh-vertices 600 --quiet ";  // stores x4
    std::string errors;
    ASSERT_EQ(
        bake(common + "--networks '" + (dir_ / "nets").string() + "' --json '" + file("torus.json").string() + "'",
             errors),
        0)
        << errors;
    ngi::Asset asset = ngi::readAsset(file("torus.ngi"));
    EXPECT_EQ(asset.networkId, "tiny-x4");
    EXPECT_EQ(asset.networkHash, ngi::networkHash(x4));
    std::ifstream json(file("torus.json"));
    const nlohmann::json summary = nlohmann::json::parse(json);
    EXPECT_EQ(summary["network"]["id"], "tiny-x4");
    EXPECT_EQ(summary["network"]["hash"], ngi::networkHashText(ngi::networkHash(x4)));
    EXPECT_EQ(summary["network"]["chartsRestored"], nlohmann::json::array({true}));
    // The chart's residual gain (its blend of the bicubic and the network, fitted by least
    // squares): in the asset and the JSON, never worse than either end in image RMS.
    const float gain = summary["charts"][0]["residualGain"].get<float>();
    EXPECT_EQ(asset.charts[0].residualGain, gain);
    EXPECT_GE(gain, 0.0f);
    EXPECT_LE(gain, 1.0f);
    const nlohmann::json& fit = summary["charts"][0]["residualGainFit"];
    EXPECT_LE(fit["rmsGained"].get<double>(), fit["rmsCubic"].get<double>() * (1.0 + 1e-9));
    EXPECT_LE(fit["rmsGained"].get<double>(), fit["rmsNetwork"].get<double>() * (1.0 + 1e-9));

    // A directory that is not there is one usage error naming it; the asset already written stays.
    const std::vector<uint8_t> before = ngi::readFileBytes(file("torus.ngi"));
    EXPECT_EQ(bake(common + "--networks '" + (dir_ / "no-such-dir").string() + "'", errors), 2);
    EXPECT_NE(errors.find("--networks " + (dir_ / "no-such-dir").string() + ": not a directory"), std::string::npos)
        << errors;
    EXPECT_EQ(ngi::readFileBytes(file("torus.ngi")), before);
    ASSERT_EQ(bake(common + "--networks '" + (dir_ / "nets").string() + "' --no-network", errors), 0) << errors;
    EXPECT_EQ(ngi::readAsset(file("torus.ngi")).networkId, "");
    fs::remove(dir_ / "nets" / "b_x4.ngiw");
    ASSERT_EQ(bake(common + "--networks '" + (dir_ / "nets").string() + "'", errors), 0) << errors;
    asset = ngi::readAsset(file("torus.ngi"));
    EXPECT_EQ(asset.networkId, "");
    EXPECT_EQ(asset.networkHash, 0u);
}

// Every file in `dir` with its bytes: a failed run must leave this exactly as it was.
std::map<std::string, std::string> snapshot(const fs::path& dir)
{
    std::map<std::string, std::string> files;
    for (const auto& entry : fs::recursive_directory_iterator(dir)) {
        if (!entry.is_regular_file()) {
            files[fs::relative(entry.path(), dir).string()] = "<directory>";
            continue;
        }
        std::ifstream in(entry.path(), std::ios::binary);
        std::stringstream bytes;
        bytes << in.rdbuf();
        files[fs::relative(entry.path(), dir).string()] = bytes.str();
    }
    return files;
}

// Expects `dir` to hold exactly `before`: the same names, each with the same bytes.
void expectUnchanged(const fs::path& dir, const std::map<std::string, std::string>& before)
{
    const std::map<std::string, std::string> after = snapshot(dir);
    for (const auto& [name, bytes] : after)
        EXPECT_TRUE(before.count(name) && before.at(name) == bytes) << name << " is new or changed";
    for (const auto& [name, bytes] : before) EXPECT_TRUE(after.count(name)) << name << " is gone";
}

// Regression: a bake that failed after writing the asset removed the EXISTING
// asset and exports. Now every output is staged and renamed only when the whole run
// succeeded: a failure, early or late, leaves every file byte-identical and no temporary.
TEST_F(BakeCli, AFailedBakeLeavesExistingOutputsByteIdentical)
{
    ngi::writeMesh(file("torus.obj"), ngi::makeTorus(16, 8));
    writeText("empty.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
    writeText("out.ngi", "the existing asset");
    writeText("out.json", "{\"existing\": true}");
    writeText("out_position.png", "existing position export");
    writeText("out.obj", "existing mesh export");
    fs::create_directories(file("jsondir"));
    fs::create_directories(file("clash/out_normal.png"));  // --export-full's file name is a directory
    const std::string in = "'" + file("torus.obj").string() + "'", out = " -o '" + file("out.ngi").string() + "'";
    const std::string common =
        " --resolution 32 --store-res 8 --remesh-vertices 300 --json '" + file("out.json").string() + "'";
    const std::map<std::string, std::string> before = snapshot(dir_);
    const struct {
        std::string arguments, needle, shellPrefix;
    } cases[] = {
        {in + out + common + " --export-mesh '" + file("out.xyz").string() + "'", "cannot write mesh format"},
        {in + out + " --json '" + file("jsondir").string() + "'", "is a directory"},
        {in + out + common + " --export-full '" + file("clash").string() + "'", "out_normal.png: is a directory"},
        {in + out + common + " --export-full '" + dir_.string() + "' --export-mesh '" +
             file("out_position.png").string() + "'",
         "every output needs its own path"},
        // Fails reading the mesh, after the outputs are declared (and the --export-mesh format checked).
        {"'" + file("empty.off").string() + "'" + out + common + " --export-mesh '" + file("out.obj").string() +
             "' --export-full '" + dir_.string() + "'",
         "no triangles"},
        // Fails writing the --export-mesh OBJ (~95 KB) after the asset, PNGs (~6 KB each) and
        // JSON are written: a file-size limit of 32 KB, SIGXFSZ ignored so that write() fails.
        {in + out + common + " --export-mesh '" + file("out.obj").string() + "' --export-full '" + dir_.string() + "'",
         "out.obj: write failed (File too large)", "trap '' XFSZ; ulimit -f 64; "},
    };
    for (const auto& c : cases) {
        SCOPED_TRACE(c.arguments);
        std::string errors;
        EXPECT_EQ(bake(c.arguments, errors, c.shellPrefix), 1);
        EXPECT_NE(errors.find(c.needle), std::string::npos) << errors;
        EXPECT_EQ(errors.find(".tmp"), std::string::npos) << "names the temporary file: " << errors;
        expectUnchanged(dir_, before);  // byte-identical, and no temporary file left behind
    }
}

// Regression: `ngi-bake IN.off -o IN.off` replaced the input mesh with the asset.
TEST_F(BakeCli, AnOutputEqualToTheInputIsRefused)
{
    ngi::writeMesh(file("torus.off"), ngi::makeTorus(16, 8));
    fs::create_symlink(file("torus.off"), file("link.ngi"));
    const std::map<std::string, std::string> before = snapshot(dir_);
    const std::string in = "'" + file("torus.off").string() + "'";
    for (const std::string& outputs :
         {" -o '" + file("torus.off").string() + "'", " -o '" + (dir_ / "." / "torus.off").string() + "'",
          " -o '" + file("link.ngi").string() + "'",
          " -o '" + file("a.ngi").string() + "' --export-mesh '" + file("torus.off").string() + "'",
          " -o '" + file("a.ngi").string() + "' --json '" + file("torus.off").string() + "'"}) {
        SCOPED_TRACE(outputs);
        std::string errors;
        EXPECT_EQ(bake(in + outputs + " --resolution 32 --store-res 8", errors), 1);
        EXPECT_NE(errors.find("is the input"), std::string::npos) << errors;
        expectUnchanged(dir_, before);
    }
    std::string errors;
    EXPECT_EQ(bake(in + " -o '" + file("a.ngi").string() + "' --json '" + file("a.ngi").string() + "'", errors), 1);
    EXPECT_NE(errors.find("every output needs its own path"), std::string::npos) << errors;
    expectUnchanged(dir_, before);
}

// Regression: --feature-angle -5 and -inf were accepted. The range is [0, 180].
TEST_F(BakeCli, FeatureAngleOutsideItsRangeIsAUsageError)
{
    for (const char* angle : {"-5", "-inf", "inf", "nan", "180.5", "1e9", "sixty", ""}) {
        SCOPED_TRACE(angle);
        std::string errors;
        EXPECT_EQ(bake("'" + file("missing.obj").string() + "' -o '" + file("out.ngi").string() +
                           "' --feature-angle '" + angle + "'",
                       errors),
                  2);
        EXPECT_NE(errors.find("--feature-angle"), std::string::npos) << errors;
    }
    for (const char* angle : {"0", "60", "180"}) {  // accepted: the run goes on to fail on the missing mesh
        SCOPED_TRACE(angle);
        std::string errors;
        EXPECT_EQ(bake("'" + file("missing.obj").string() + "' -o '" + file("out.ngi").string() + "' --feature-angle " +
                           angle,
                       errors),
                  1);
        EXPECT_NE(errors.find("missing.obj"), std::string::npos) << errors;
    }
}

// --detail-density S bakes the OT to a measure that follows curvature. The
// JSON records S; the map is then deliberately not area-preserving (a torus's mean curvature
// differs between its outer and inner side: its mean |log area ratio| grows), and out-of-range strengths are usage errors.
TEST_F(BakeCli, DetailDensityMovesSamplesAndIsRecorded)
{
    ngi::writeMesh(file("torus.obj"), ngi::makeTorus(24, 12));
    auto bakeAt = [&](const std::string& strength) {
        std::string errors;
        const std::string json = file("torus_" + strength + ".json").string();
        EXPECT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("torus_" + strength + ".ngi").string() +
                           "' --resolution 32 --store-res 8 --remesh-vertices 600 --detail-density " + strength +
                           " --json '" + json + "'",
                       errors),
                  0)
            << errors;
        std::ifstream in(json);
        return nlohmann::json::parse(in);
    };
    const nlohmann::json area = bakeAt("0"), detail = bakeAt("4");
    EXPECT_EQ(area["parameterization"]["detailDensity"].get<double>(), 0.0);
    EXPECT_EQ(detail["parameterization"]["detailDensity"].get<double>(), 4.0);
    EXPECT_EQ(detail["parameterization"]["flippedTriangles"].get<int>(), 0);
    const double areaMean = area["parameterization"]["areaDistortionMean"].get<double>(),
                 detailMean = detail["parameterization"]["areaDistortionMean"].get<double>();
    // Measured 0.040 -> 0.054 (the 600-vertex remesh's curvature is smoothed over two rings);
    // the spike test of detail_density_test.cpp measures the effect itself.
    EXPECT_GT(detailMean, 1.2 * areaMean) << "area measure " << areaMean << ", S 4 " << detailMean;
    for (const char* strength : {"-1", "nan", "inf", "65", "lots", ""}) {
        SCOPED_TRACE(strength);
        std::string errors;
        EXPECT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("bad.ngi").string() + "' --detail-density '" +
                           strength + "'",
                       errors),
                  2);
        EXPECT_NE(errors.find("--detail-density"), std::string::npos) << errors;
    }
}

// At a byte budget a split for thin parts is checked against one chart per component and the
// one closer to the input kept (the rate control's measure), both reported; --no-split bakes
// one chart without the comparison.
TEST_F(BakeCli, AtAByteBudgetTheThinPartSplitIsCheckedAgainstOneChart)
{
    ngi::writeMesh(file("arms.obj"), ngi::makeTwoArmedBody(3));
    std::string errors;
    ASSERT_EQ(bake("'" + file("arms.obj").string() + "' -o '" + file("arms.ngi").string() +
                       "' --resolution 128 --store-res 16 --target-bytes 6000 --json '" + file("arms.json").string() +
                       "'",
                   errors),
              0)
        << errors;
    std::ifstream in(file("arms.json"));
    const nlohmann::json json = nlohmann::json::parse(in);
    ASSERT_TRUE(json.contains("splitChoice")) << json.dump();
    const nlohmann::json& choice = json["splitChoice"];
    const double split = choice["splitRmsToInput"].get<double>(), whole = choice["oneChartRmsToInput"].get<double>();
    EXPECT_GT(split, 0.0);
    EXPECT_GT(whole, 0.0);
    EXPECT_EQ(choice["kept"].get<std::string>(), split <= whole ? "split" : "one chart per component") << choice.dump();
    EXPECT_EQ(json["chartCount"].get<size_t>() > 1, split <= whole) << json.dump();
    EXPECT_LE(json["assetBytes"].get<size_t>(), 6000u);
    EXPECT_NE(errors.find("thin parts at 6000 bytes"), std::string::npos) << errors;
    ASSERT_EQ(bake("'" + file("arms.obj").string() + "' -o '" + file("whole.ngi").string() +
                       "' --resolution 128 --store-res 16 --target-bytes 6000 --no-split --json '" +
                       file("whole.json").string() + "'",
                   errors),
              0)
        << errors;
    std::ifstream wholeIn(file("whole.json"));
    const nlohmann::json one = nlohmann::json::parse(wholeIn);
    EXPECT_FALSE(one.contains("splitChoice"));
    EXPECT_EQ(one["chartCount"].get<int>(), 1);
}

// --split-pieces K (docs/splitting.md) bakes about K geodesic Voronoi pieces of the one torus as
// K matched charts, nothing dropped, and says so; K outside [2, 256] is a usage error.
TEST_F(BakeCli, SplitPiecesBakesEveryPieceAsAChartAndSaysSo)
{
    const ngi::TriangleMesh torus = ngi::makeTorus(24, 12);
    ngi::writeMesh(file("torus.obj"), torus);
    std::string errors;
    ASSERT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("split.ngi").string() +
                       "' --resolution 32 --store-res 8 --remesh-vertices 600 --split-pieces 3 --json '" +
                       file("split.json").string() + "'",
                   errors),
              0)
        << errors;
    std::ifstream in(file("split.json"));
    const nlohmann::json json = nlohmann::json::parse(in);
    EXPECT_GE(json["chartCount"].get<int>(), 3) << json.dump();
    double area = 0.0;
    for (const nlohmann::json& chart : json["charts"]) area += chart["areaFraction"].get<double>();
    EXPECT_NEAR(area, 1.0, 1e-9) << "every piece is a chart";
    bool warned = false;
    for (const nlohmann::json& w : json["warnings"])
        warned |= w.get<std::string>().find("matched Voronoi pieces (--split-pieces") != std::string::npos;
    EXPECT_TRUE(warned) << json["warnings"].dump();
    EXPECT_NE(errors.find("matched Voronoi pieces"), std::string::npos) << errors;
    // A bad value is refused before anything is written: the outputs there stay as they were.
    {
        std::ofstream(file("bad.ngi")) << "an earlier asset";
    }
    const std::map<std::string, std::string> before = snapshot(dir_);
    for (const char* pieces : {"0", "1", "257", "-3", "many", ""}) {
        SCOPED_TRACE(pieces);
        EXPECT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("bad.ngi").string() + "' --split-pieces '" +
                           pieces + "'",
                       errors),
                  2);
        EXPECT_NE(errors.find("--split-pieces"), std::string::npos) << errors;
    }
    expectUnchanged(dir_, before);
    // auto: both bakes fitted to the budget, the one closer to the input kept and reported.
    ASSERT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("auto.ngi").string() +
                       "' --resolution 64 --store-res 16 --target-bytes 6000 --remesh-vertices 600 "
                       "--split-pieces auto --json '" +
                       file("auto.json").string() + "'",
                   errors),
              0)
        << errors;
    std::ifstream autoIn(file("auto.json"));
    const nlohmann::json chosen = nlohmann::json::parse(autoIn);
    ASSERT_TRUE(chosen.contains("splitChoice")) << chosen.dump();
    const nlohmann::json& choice = chosen["splitChoice"];
    const bool split = choice["splitRmsToInput"].get<double>() < choice["oneChartRmsToInput"].get<double>();
    EXPECT_EQ(choice["kept"].get<std::string>(), split ? "split" : "one chart per component") << choice.dump();
    EXPECT_EQ(chosen["chartCount"].get<int>() > 1, split) << chosen.dump();
    EXPECT_NE(errors.find("split auto:"), std::string::npos) << errors;
    EXPECT_EQ(
        bake("'" + file("torus.obj").string() + "' -o '" + file("bad.ngi").string() + "' --split-pieces auto", errors),
        2);
    EXPECT_NE(errors.find("give --target-bytes"), std::string::npos) << errors;
}

}  // namespace

namespace {

// A cube as OBJ + MTL whose faces map onto the four quadrants of a 2 x 2 PNG (red, green,
// blue, white), so every face has one known colour.
void writeTexturedCube(const fs::path& dir, bool withTexture)
{
    std::ofstream obj(dir / "cube.obj");
    obj << "mtllib cube.mtl\nusemtl painted\n";
    for (int z = 0; z < 2; ++z)
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) obj << "v " << x << " " << y << " " << z << "\n";
    // Texture coordinates at the centres of the four texels (OBJ: v up).
    obj << "vt 0.25 0.75\nvt 0.75 0.75\nvt 0.25 0.25\nvt 0.75 0.25\n";
    // Faces (1-based corners), counter-clockwise from outside, with their texel.
    const int faces[6][5] = {{1, 3, 4, 2, 1}, {5, 6, 8, 7, 2}, {1, 2, 6, 5, 3},
                             {3, 7, 8, 4, 4}, {1, 5, 7, 3, 1}, {2, 4, 8, 6, 2}};
    for (const auto& f : faces)
        obj << "f " << f[0] << "/" << f[4] << " " << f[1] << "/" << f[4] << " " << f[2] << "/" << f[4] << " " << f[3]
            << "/" << f[4] << "\n";
    std::ofstream(dir / "cube.mtl") << "newmtl painted\nKd 1 1 1\n"
                                    << (withTexture ? "map_Kd cube.png\n" : "map_Kd missing.png\n");
    const uint8_t texels[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
    if (withTexture) ngi::writePng8(dir / "cube.png", 2, 2, 4, texels);
}

}  // namespace

TEST_F(BakeCli, BakesTheTexturesColoursIntoTheAssetAndGeometryOnlyOnRequest)
{
    writeTexturedCube(file(""), true);
    std::string errors;
    ASSERT_EQ(
        bake("'" + file("cube.obj").string() + "' -o '" + file("cube.ngi").string() + "' --resolution 32 --store-res 8",
             errors),
        0)
        << errors;
    const ngi::Asset asset = ngi::readAsset(file("cube.ngi"));
    size_t red = 0, green = 0, blue = 0, white = 0, texels = 0;
    for (const ngi::AssetChart& chart : asset.charts) {
        ASSERT_FALSE(chart.baseColor.empty());
        for (size_t i = 0; i < chart.baseColor.size(); i += 4, ++texels) {
            const uint8_t* t = &chart.baseColor[i];
            red += t[0] > 200 && t[1] < 60 && t[2] < 60;
            green += t[1] > 200 && t[0] < 60 && t[2] < 60;
            blue += t[2] > 200 && t[0] < 60 && t[1] < 60;
            white += t[0] > 200 && t[1] > 200 && t[2] > 200;
        }
    }
    // Each colour covers two faces of six: a third of the surface (texels along the cube's
    // edges mix two faces' colours).
    for (size_t count : {red, green, blue, white})
        EXPECT_GT(double(count) / double(texels), 0.10) << red << " " << green << " " << blue << " " << white;
    EXPECT_GT(double(red + green + blue + white) / double(texels), 0.75);
    ASSERT_EQ(bake("'" + file("cube.obj").string() + "' -o '" + file("plain.ngi").string() +
                       "' --resolution 32 --store-res 8 --no-appearance",
                   errors),
              0)
        << errors;
    for (const ngi::AssetChart& chart : ngi::readAsset(file("plain.ngi")).charts) EXPECT_TRUE(chart.baseColor.empty());
}

TEST_F(BakeCli, AMissingTextureIsOneErrorNamingItAndNoOutput)
{
    writeTexturedCube(file(""), false);
    expectFailure("cube.obj", "missing.png");
}
