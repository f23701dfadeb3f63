// ngi-render as a user runs it: good runs write a PNG of the requested size; every bad
// input (missing or corrupt asset, bad option, no Vulkan driver) exits non-zero with one
// clear message and writes nothing.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/network_weights.h"
#include "ngi/png_io.h"
#include "run_tool.h"
#include "tiny_network.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <sys/wait.h>

namespace {

namespace fs = std::filesystem;

using ngi::test::ToolRun;

ToolRun run(const std::string& args, const std::string& env = "")
{
    return ngi::test::runShell(env + " " NGI_RENDER_BIN " " + args);
}

class RenderCli : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() / ("ngi_render_cli_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        asset_ = (dir_ / "sphere.ngi").string();
        ngi::writeAsset(ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(65), 2), asset_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
    std::string asset_;
};

TEST_F(RenderCli, WritesAPngOfTheRequestedSize)
{
    const std::string out = (dir_ / "frame.png").string();
    const ToolRun r = run(asset_ + " -o " + out + " --lod 1.5 --size 96x64 --samples 1", "NGI_VALIDATION=1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ngi::PngImage png = ngi::readPng(out);
    EXPECT_EQ(png.width, 96u);
    EXPECT_EQ(png.height, 64u);
    EXPECT_NE(r.output.find("level 1, 33x33 grid, morph 0.50, 2048 triangles"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("validation"), std::string::npos) << r.output;
}

TEST_F(RenderCli, ContactSheetShowsEveryLevel)
{
    const std::string out = (dir_ / "sheet.png").string();
    const ToolRun r = run(asset_ + " -o " + out + " --contact-sheet --size 64x64 --samples 1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const ngi::PngImage png = ngi::readPng(out);
    EXPECT_EQ(png.width, 4u * 64u);  // 7 levels (65 .. 2) in rows of 4
    EXPECT_EQ(png.height, 2u * (64u + 40u));
}

TEST_F(RenderCli, SuperResolutionRestoresWithTheGivenNetwork)
{
    // The asset stores level 2 of 65 samples (17^2): a x4 network restores level 0.
    const std::string net = (dir_ / "x4.ngiw").string(), wrong = (dir_ / "x8.ngiw").string();
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(4, 0.0f), net);
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(8, 0.0f), wrong);
    const std::string sr = (dir_ / "sr.png").string(), bilinear = (dir_ / "bilinear.png").string();
    ToolRun r = run(asset_ + " -o " + sr + " --lod 0 --size 64x64 --samples 1 --sr --weights " + net, "NGI_VALIDATION=1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("super-resolution"), std::string::npos) << r.output;
    r = run(asset_ + " -o " + bilinear + " --lod 0 --size 64x64 --samples 1 --no-sr");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("bilinear"), std::string::npos) << r.output;
    // A zero network adds nothing to the bilinear skip: the same silhouette (normals are
    // derived from positions on the SR path, so shading may differ slightly).
    const ngi::PngImage a = ngi::readPng(sr), b = ngi::readPng(bilinear);
    size_t coverageA = 0, coverageB = 0;
    for (size_t i = 0; i < a.samples.size(); i += 4) {  // pixel (0, 0) is background
        coverageA += a.samples[i] != a.samples[0] || a.samples[i + 1] != a.samples[1];
        coverageB += b.samples[i] != b.samples[0] || b.samples[i + 1] != b.samples[1];
    }
    EXPECT_GT(coverageB, 64u * 64u / 10);
    EXPECT_NEAR(double(coverageA), double(coverageB), 0.01 * coverageB);
    r = run(asset_ + " -o " + sr + " --sr --weights " + wrong);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    r = run(asset_ + " -o " + sr + " --sr");
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.output.find("this asset carries no weights"), std::string::npos) << r.output;
    r = run(asset_ + " -o " + sr + " --weights " + net);
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(r.output.find("--weights needs --sr"), std::string::npos) << r.output;
}

TEST_F(RenderCli, BadInputsFailClearlyAndWriteNothing)
{
    const std::string out = (dir_ / "never.png").string();
    struct Case {
        std::string args, env, message;
        int code;
    };
    std::ofstream(dir_ / "truncated.ngi", std::ios::binary)
        << std::string(reinterpret_cast<const char*>(ngi::serializeAsset(ngi::makeAnalyticAsset("s", ngi::sphereGeometryImage(33), 1)).data()), 100);
    const std::string missing = (dir_ / "missing.ngi").string(), truncated = (dir_ / "truncated.ngi").string();
    const Case cases[] = {
        {missing + " -o " + out, "", missing + ": cannot open file", 1},
        {truncated + " -o " + out, "", truncated + ": file is truncated", 1},
        {asset_ + " -o " + out + " --lod 99", "", "--lod 99", 1},
        {asset_ + " -o " + out + " --grid 1", "", "--grid 1 is outside [2, 65]", 1},
        {asset_ + " -o " + out + " --mode phong", "", "unknown shading mode 'phong'", 1},
        {asset_ + " -o " + out + " --size 0x5", "", "--size must be positive", 2},
        {asset_ + " -o " + out + " --lod abc", "", "--lod expects a number", 2},
        {asset_, "", "no output given", 2},
        {asset_ + " -o " + out + " --device nonexistent-gpu", "", "Vulkan device 'nonexistent-gpu' not found", 1},
        {asset_ + " -o " + out, "VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json", "Vulkan", 1},
        {asset_ + " -o " + (dir_ / "no_such_dir" / "x.png").string(), "", "no_such_dir/x.png: cannot create file", 1},
    };
    for (const Case& c : cases) {
        const ToolRun r = run(c.args, c.env);
        EXPECT_EQ(r.exitCode, c.code) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.args;
    }
    // No temporary files left behind either.
    for (const auto& e : fs::directory_iterator(dir_))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

std::string slurp(const fs::path& p)
{
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

// Regression (issue 11): `ngi-render A.ngi -o A.ngi` overwrote the asset with a PNG. An
// output equal to an input (the asset, the weights, also through a link) or a directory is
// refused before any work, and a run that fails late leaves an existing -o as it was.
TEST_F(RenderCli, NeverOverwritesAnInputOrAnExistingFileOnFailure)
{
    const std::string net = (dir_ / "x4.ngiw").string(), link = (dir_ / "link.png").string();
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(4, 0.0f), net);
    fs::create_symlink(asset_, link);
    const std::string assetBytes = slurp(asset_), netBytes = slurp(net);
    const struct {
        std::string args, message;
    } refused[] = {
        {asset_ + " -o " + asset_, asset_ + ": this output is the input"},
        {asset_ + " -o " + (dir_ / "." / "sphere.ngi").string(), "this output is the input"},
        {asset_ + " -o " + link, "this output is the input"},
        {asset_ + " -o " + net + " --sr --weights " + net, net + ": this output is the input"},
        {asset_ + " -o " + dir_.string(), "is a directory"},
    };
    for (const auto& c : refused) {
        // No Vulkan driver: the refusal must come before any GPU work to be seen at all.
        const ToolRun r = run(c.args + " --size 32x32 --samples 1",
                              "VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json");
        EXPECT_EQ(r.exitCode, 1) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_EQ(slurp(asset_), assetBytes);
        EXPECT_EQ(slurp(net), netBytes);
    }
    // A failure after the render started (the LoD is checked against the built surface).
    const fs::path out = dir_ / "frame.png";
    std::ofstream(out, std::ios::binary) << "an existing frame";
    const ToolRun r = run(asset_ + " -o " + out.string() + " --lod 99 --size 32x32 --samples 1");
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_EQ(slurp(out), "an existing frame");
    for (const auto& e : fs::directory_iterator(dir_))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

} // namespace
