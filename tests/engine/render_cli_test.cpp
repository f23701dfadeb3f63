// ngi-render as a user runs it: good runs write a PNG of the requested size; every bad
// input (missing or corrupt asset, bad option, no Vulkan driver) exits non-zero with one
// clear message and writes nothing.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/network_catalog.h"
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
#include <sys/stat.h>
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

// An input that is not a regular file, a FIFO (which a plain open waits on forever) or a
// directory, as the asset, the --weights or the --compare reference: one error naming it, a
// non-zero exit, no output; run under `timeout` so that a hang fails instead of blocking.
TEST_F(RenderCli, AFifoOrADirectoryAsAnInputIsOneErrorNamingIt)
{
    const fs::path fifo = dir_ / "pipe.ngi", folder = dir_ / "folder.ngi";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    fs::create_directories(folder);
    const std::string out = (dir_ / "hostile.png").string();
    for (const fs::path& bad : {fifo, folder}) {
        const std::string expected =
            bad.string() + (bad == fifo ? ": is a FIFO" : ": is a directory") + ", not a regular file";
        for (const std::string& args :
             {bad.string() + " -o " + out, asset_ + " -o " + out + " --sr --weights " + bad.string(),
              asset_ + " -o " + out + " --compare " + bad.string()}) {
            SCOPED_TRACE(args);
            const ToolRun r =
                ngi::test::runShell("timeout 120 " NGI_RENDER_BIN " " + args + " --size 32x32 --samples 1");
            EXPECT_EQ(r.exitCode, 1) << r.output;  // 124: it hung
            EXPECT_NE(r.output.find(expected), std::string::npos) << r.output;
            EXPECT_FALSE(fs::exists(out));
        }
    }
    EXPECT_TRUE(fs::is_fifo(fifo));
}

// The source name an asset carries comes from a file: printed, its control bytes are escaped
// (\xNN), so that a crafted asset cannot send escape sequences to the terminal.
TEST_F(RenderCli, TheSourceNameIsPrintedEscaped)
{
    ngi::Asset asset = ngi::readAsset(asset_);
    asset.sourceName = "evil\x1b]0;owned\x07\x1b[2J.obj";
    const std::string crafted = (dir_ / "crafted.ngi").string();
    ngi::writeAsset(asset, crafted);
    const ToolRun r = run(crafted + " -o " + (dir_ / "crafted.png").string() + " --size 32x32 --samples 1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("evil\\x1b]0;owned\\x07\\x1b[2J.obj"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find('\x1b'), std::string::npos);
    EXPECT_EQ(r.output.find('\x07'), std::string::npos);
}

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

TEST_F(RenderCli, MaxErrorPxDrawsAdaptivelyAndRejectsBadBudgets)
{
    const std::string out = (dir_ / "adaptive.png").string();
    const ToolRun fine =
        run(asset_ + " -o " + out + " --max-error-px 0.5 --size 96x64 --samples 1", "NGI_VALIDATION=1");
    ASSERT_EQ(fine.exitCode, 0) << fine.output;
    EXPECT_NE(fine.output.find("adaptive within 0.5 px"), std::string::npos) << fine.output;
    EXPECT_EQ(fine.output.find("validation"), std::string::npos) << fine.output;
    EXPECT_EQ(ngi::readPng(out).width, 96u);
    const ToolRun coarse = run(asset_ + " -o " + out + " --max-error-px 20 --size 96x64 --samples 1 --mode lod");
    ASSERT_EQ(coarse.exitCode, 0) << coarse.output;
    auto triangles = [](const std::string& text) {
        const size_t at = text.find(" triangles in ");
        const size_t start = text.rfind(' ', at - 1);
        return std::stoull(text.substr(start + 1, at - start - 1));
    };
    EXPECT_LT(triangles(coarse.output), triangles(fine.output)) << fine.output << coarse.output;
    for (const std::string bad : {"0", "-1", "nan", "inf", "1e999", "x", "1e9"}) {
        const ToolRun r = run(asset_ + " -o " + out + " --max-error-px " + bad);
        EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.output;
        EXPECT_NE(r.output.find("--max-error-px"), std::string::npos) << bad << ": " << r.output;
    }
    EXPECT_EQ(run(asset_ + " -o " + out + " --max-error-px 1 --lod 2").exitCode, 2);
    EXPECT_EQ(run(asset_ + " -o " + out + " --max-error-px 1 --contact-sheet").exitCode, 2);
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
    ToolRun r =
        run(asset_ + " -o " + sr + " --lod 0 --size 64x64 --samples 1 --sr --weights " + net, "NGI_VALIDATION=1");
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

// --sr without --weights restores with the shipped network the asset names
// (here found by --networks DIR): the same frame as --weights of that file; a network of that
// name with another hash is one error naming both hashes; none found names the directory.
TEST_F(RenderCli, SrAloneRestoresWithTheNetworkTheAssetNames)
{
    const fs::path shipped = dir_ / "shipped";
    fs::create_directories(shipped);
    const ngi::NetworkWeights x4 = ngi::test::tinyNetwork(4, 0.002f);
    ngi::writeNetworkWeights(x4, shipped / "x4.ngiw");
    ngi::Asset asset = ngi::readAsset(asset_);
    asset.networkId = x4.name;
    asset.networkHash = ngi::networkHash(x4);
    const std::string named = (dir_ / "named.ngi").string();
    ngi::writeAsset(asset, named);
    const std::string a = (dir_ / "a.png").string(), b = (dir_ / "b.png").string(),
                      options = " --lod 0 --size 64x64 --samples 1 --sr ";
    ToolRun r = run(named + " -o " + a + options + "--networks " + shipped.string(), "NGI_VALIDATION=1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("network " + (shipped / "x4.ngiw").string() + " (x4)"), std::string::npos) << r.output;
    r = run(named + " -o " + b + options + "--weights " + (shipped / "x4.ngiw").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(ngi::readPng(a).samples, ngi::readPng(b).samples);

    const ngi::NetworkWeights retrained = ngi::test::tinyNetwork(4, 0.004f);
    ngi::writeNetworkWeights(retrained, shipped / "x4.ngiw");
    const std::string out = (dir_ / "out.png").string();
    r = run(named + " -o " + out + options + "--networks " + shipped.string());
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find(ngi::networkHashText(asset.networkHash)), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(ngi::networkHashText(ngi::networkHash(retrained))), std::string::npos) << r.output;
    fs::create_directories(dir_ / "empty");
    r = run(named + " -o " + out + options + "--networks " + (dir_ / "empty").string());
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("not found in " + (dir_ / "empty").string()), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(out));
}

// "every tool restoring with the matching network by default": with neither
// --sr nor --no-sr, an asset whose named network is found is drawn by it (the --sr frame); one
// whose network is missing is drawn bicubically (the --bicubic frame) with a warning naming
// why, and exit 0; an asset naming none is drawn bicubically without a word.
TEST_F(RenderCli, DefaultRestoreIsTheNamedNetworkWhenFound)
{
    const fs::path shipped = dir_ / "shipped";
    fs::create_directories(shipped);
    const ngi::NetworkWeights x4 = ngi::test::tinyNetwork(4, 0.02f);
    ngi::writeNetworkWeights(x4, shipped / "x4.ngiw");
    ngi::Asset asset = ngi::readAsset(asset_);
    asset.networkId = x4.name;
    asset.networkHash = ngi::networkHash(x4);
    const std::string named = (dir_ / "named.ngi").string();
    ngi::writeAsset(asset, named);
    const std::string options = " --lod 0 --size 64x64 --samples 1";
    const std::string def = (dir_ / "default.png").string(), sr = (dir_ / "sr.png").string(),
                      bilinear = (dir_ / "bilinear.png").string(), missing = (dir_ / "missing.png").string();
    ToolRun r = run(named + " -o " + def + options + " --networks " + shipped.string(), "NGI_VALIDATION=1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("super-resolution: network " + (shipped / "x4.ngiw").string() + " (x4)"), std::string::npos)
        << r.output;
    ASSERT_EQ(run(named + " -o " + sr + options + " --sr --networks " + shipped.string()).exitCode, 0);
    ASSERT_EQ(run(named + " -o " + bilinear + options + " --no-sr").exitCode, 0);
    EXPECT_EQ(ngi::readPng(def).samples, ngi::readPng(sr).samples);
    EXPECT_NE(ngi::readPng(def).samples, ngi::readPng(bilinear).samples)
        << "a network that changes nothing tests nothing";

    fs::create_directories(dir_ / "empty");
    r = run(named + " -o " + missing + options + " --networks " + (dir_ / "empty").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("warning: " + named), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("not found in " + (dir_ / "empty").string()), std::string::npos) << r.output;
    const std::string bicubic = (dir_ / "bicubic.png").string();
    ASSERT_EQ(run(named + " -o " + bicubic + options + " --bicubic").exitCode, 0);
    EXPECT_EQ(ngi::readPng(missing).samples, ngi::readPng(bicubic).samples);
    EXPECT_NE(ngi::readPng(bicubic).samples, ngi::readPng(bilinear).samples) << "bicubic and bilinear frames coincide";

    const std::string plain = (dir_ / "plain.png").string();
    r = run(asset_ + " -o " + plain + options);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("super-resolution: network"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("bicubic restore"), std::string::npos) << r.output;
    r = run(named + " -o " + plain + options + " --no-sr --networks " + shipped.string());
    EXPECT_EQ(r.exitCode, 2) << r.output;
}

TEST_F(RenderCli, BadInputsFailClearlyAndWriteNothing)
{
    const std::string out = (dir_ / "never.png").string();
    struct Case {
        std::string args, env, message;
        int code;
    };
    std::ofstream(dir_ / "truncated.ngi", std::ios::binary)
        << std::string(reinterpret_cast<const char*>(
                           ngi::serializeAsset(ngi::makeAnalyticAsset("s", ngi::sphereGeometryImage(33), 1)).data()),
                       100);
    const std::string missing = (dir_ / "missing.ngi").string(), truncated = (dir_ / "truncated.ngi").string();
    const Case cases[] = {
        {missing + " -o " + out, "", missing + ": cannot open file", 1},
        {truncated + " -o " + out, "", truncated + ": file is truncated", 1},
        {asset_ + " -o " + out + " --lod 99", "", "--lod 99", 1},
        {asset_ + " -o " + out + " --grid 1", "", "--grid 1 is outside [2, 65]", 1},
        {asset_ + " -o " + out + " --mode phong", "", "unknown shading mode 'phong'", 1},
        {asset_ + " -o " + out + " --size 0x5", "", "--size must be positive", 2},
        {asset_ + " -o " + out + " --lod abc", "", "--lod expects a number", 2},
        {asset_ + " -o " + out + " --bogus", "", "unknown option --bogus", 2},
        {asset_ + " -o " + out + " --size", "", "--size expects a value", 2},
        {asset_ + " -o " + out + " extra.ngi", "", "unexpected argument extra.ngi", 2},
        {asset_, "", "no output given", 2},
        {asset_ + " -o ''", "", "-o: the output path is empty", 2},
        {asset_ + " -o " + out + " --compare " + asset_ + " --diff ''", "", "--diff: the output path is empty", 2},
        {asset_ + " -o " + out + " --device nonexistent-gpu", "", "Vulkan device 'nonexistent-gpu' not found", 1},
        {asset_ + " -o " + out, "VK_ICD_FILENAMES=/nonexistent/icd.json VK_DRIVER_FILES=/nonexistent/icd.json",
         "Vulkan", 1},
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

// Regression: `ngi-render A.ngi -o A.ngi` overwrote the asset with a PNG. An
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

// --compare: a frame against a reference PNG. Exit 0 within the tolerance,
// 4 when it differs (with the difference image of --diff), 1 on a bad reference (named),
// and the reference is never written.
TEST_F(RenderCli, CompareMatchesItsOwnFrameAndFlagsAChangedReference)
{
    const std::string args = asset_ + " --size 48x48 --samples 1 --lod 1";
    const std::string ref = (dir_ / "ref.png").string(), out = (dir_ / "out.png").string();
    ToolRun r = run(args + " -o " + ref, "NGI_VALIDATION=1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string refBytes = slurp(ref);

    const std::string diff = (dir_ / "diff.png").string();
    r = run(args + " -o " + out + " --compare " + ref + " --diff " + diff, "NGI_VALIDATION=1");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("compare " + ref + ": 0 of 2304 pixels"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("matches"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("validation"), std::string::npos) << r.output;
    EXPECT_EQ(ngi::readPng(diff).width, 48u);
    EXPECT_EQ(slurp(ref), refBytes);

    // The reference with a 6 x 6 magenta block in the middle of the sphere: 36 of 2304
    // pixels (1.6%) differ, above the default 0.5%, below a --max-diff of 2%.
    ngi::PngImage perturbed = ngi::readPng(ref);
    ASSERT_EQ(perturbed.channels, 4u);
    for (uint32_t y = 21; y < 27; ++y)
        for (uint32_t x = 21; x < 27; ++x) {
            uint16_t* px = &perturbed.samples[(size_t(y) * 48 + x) * 4];
            px[0] = 255, px[1] = 0, px[2] = 255;
        }
    const std::string changed = (dir_ / "changed.png").string(), diff2 = (dir_ / "diff2.png").string();
    ngi::writePng(changed, perturbed);
    const std::string changedBytes = slurp(changed);
    fs::remove(out);
    r = run(args + " -o " + out + " --compare " + changed + " --diff " + diff2, "NGI_VALIDATION=1");
    EXPECT_EQ(r.exitCode, 4) << r.output;
    EXPECT_NE(r.output.find("36 of 2304 pixels (1.562%) differ by more than 16/255 (allowed 0.500%)"),
              std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("DIFFERS"), std::string::npos) << r.output;
    EXPECT_EQ(slurp(changed), changedBytes);
    EXPECT_TRUE(fs::exists(out)) << "the frame that differs is kept for inspection";
    const ngi::PngImage d = ngi::readPng(diff2);
    ASSERT_EQ(d.width, 48u);
    ASSERT_EQ(d.height, 48u);
    size_t red = 0;  // differing pixels: red, no blue; exactly the block
    for (uint32_t y = 0; y < 48; ++y)
        for (uint32_t x = 0; x < 48; ++x) {
            const uint16_t* px = &d.samples[(size_t(y) * 48 + x) * d.channels];
            const bool isRed = px[0] > 120 && px[2] == 0;
            red += isRed;
            if (x >= 21 && x < 27 && y >= 21 && y < 27) {
                EXPECT_TRUE(isRed) << x << "," << y;
            }
        }
    EXPECT_EQ(red, 36u);
    r = run(args + " -o " + out + " --compare " + changed + " --max-diff 0.02");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    r = run(args + " -o " + out + " --compare " + changed + " --pixel-threshold 255");
    EXPECT_EQ(r.exitCode, 0) << r.output;
}

// A contact sheet is compared as one image; its size is known only after the build.
TEST_F(RenderCli, CompareChecksAContactSheet)
{
    const std::string args = asset_ + " --contact-sheet --size 32x32 --samples 1";
    const std::string ref = (dir_ / "sheet.png").string(), out = (dir_ / "out.png").string();
    ToolRun r = run(args + " -o " + ref);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    r = run(args + " -o " + out + " --compare " + ref, "NGI_VALIDATION=1");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("0 of 18432 pixels"), std::string::npos) << r.output;  // 4 x 32 by 2 x (32 + 40)
    fs::remove(out);
    r = run(asset_ + " --contact-sheet --size 40x32 --samples 1 -o " + out + " --compare " + ref);
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find(ref + ": the reference is 128x144 pixels, the frame 160x144"), std::string::npos)
        << r.output;
    EXPECT_FALSE(fs::exists(out));
}

TEST_F(RenderCli, CompareRefusesABadReferenceAndNamesIt)
{
    const std::string args = asset_ + " --size 32x32 --samples 1";
    const std::string ref = (dir_ / "ref48.png").string(), out = (dir_ / "never.png").string();
    ToolRun r = run(asset_ + " --size 48x48 --samples 1 -o " + ref);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const std::string refBytes = slurp(ref);
    const std::string missing = (dir_ / "missing.png").string(), truncated = (dir_ / "truncated.png").string();
    std::ofstream(truncated, std::ios::binary) << refBytes.substr(0, refBytes.size() / 2);
    const struct {
        std::string args, message;
        int code;
    } cases[] = {
        {args + " -o " + out + " --compare " + missing, missing + ": cannot open", 1},
        {args + " -o " + out + " --compare " + truncated, truncated + ":", 1},
        {args + " -o " + out + " --compare " + ref, ref + ": the reference is 48x48 pixels, the frame 32x32", 1},
        {args + " -o " + ref + " --compare " + ref, ref + ": this output is the input", 1},
        {args + " -o " + out + " --compare " + ref + " --diff " + ref, "this output is the input", 1},
        {args + " -o " + out + " --diff " + (dir_ / "d.png").string(), "need --compare", 2},
        {args + " -o " + out + " --compare " + ref + " --max-diff 2", "--max-diff is a fraction", 2},
        {args + " -o " + out + " --compare " + ref + " --max-diff nan", "--max-diff expects a number", 2},
        {args + " -o " + out + " --compare " + ref + " --pixel-threshold 300", "--pixel-threshold is at most 255", 2},
    };
    for (const auto& c : cases) {
        r = run(c.args);
        EXPECT_EQ(r.exitCode, c.code) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.args;
        EXPECT_FALSE(fs::exists(dir_ / "d.png")) << c.args;
        EXPECT_EQ(slurp(ref), refBytes) << c.args;
    }
    for (const auto& e : fs::directory_iterator(dir_))
        EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

// Pixels that are not the magenta --background; `meanX`: their mean column.
size_t coverage(const std::string& png, double* meanX = nullptr)
{
    const ngi::PngImage image = ngi::readPng(png);
    size_t covered = 0;
    double sumX = 0.0;
    for (size_t p = 0; p < size_t(image.width) * image.height; ++p) {
        const uint16_t* s = &image.samples[p * image.channels];
        const bool surface = !(s[0] == 255 && s[1] == 0 && s[2] == 255);
        covered += surface;
        sumX += surface ? double(p % image.width) : 0.0;
    }
    if (meanX) *meanX = covered ? sumX / double(covered) : -1.0;
    return covered;
}

// "eye X,Y,Z look-at X,Y,Z distance D" of the run's camera line.
struct CameraLine {
    float eye[3], at[3], distance;
};
CameraLine cameraLine(const std::string& output)
{
    CameraLine c{};
    const size_t at = output.find("camera (object space): eye ");
    EXPECT_NE(at, std::string::npos) << output;
    if (at == std::string::npos) return c;
    EXPECT_EQ(std::sscanf(output.c_str() + at, "camera (object space): eye %f,%f,%f look-at %f,%f,%f distance %f",
                          &c.eye[0], &c.eye[1], &c.eye[2], &c.at[0], &c.at[1], &c.at[2], &c.distance),
              7)
        << output;
    return c;
}

std::string vec3(const float* v)
{
    char s[96];
    std::snprintf(s, sizeof s, "%.9g,%.9g,%.9g", v[0], v[1], v[2]);
    return s;
}

// Close-ups: the camera options move the camera in object space; bad values are refused.
TEST_F(RenderCli, CameraOptionsFrameACloseUpAndRefuseBadValues)
{
    // Object space differs from the normalized space: the sphere (centre 0.5, radius 0.5
    // normalized) is centred at (12, -3, 4) with radius 2.
    const std::string moved = (dir_ / "moved.ngi").string();
    ngi::Asset movedAsset = ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(65), 2);
    movedAsset.offset = glm::vec3(10.0f, -5.0f, 2.0f);
    movedAsset.scale = glm::vec3(4.0f);
    ngi::writeAsset(movedAsset, moved);
    const std::string args = moved + " --size 48x48 --samples 1 --background 1,0,1";
    const std::string framed = (dir_ / "framed.png").string(), shot = (dir_ / "shot.png").string();
    ToolRun r = run(args + " -o " + framed, "NGI_VALIDATION=1");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    const CameraLine camera = cameraLine(r.output);
    EXPECT_NEAR(camera.at[0], 12.0f, 0.01f);
    EXPECT_NEAR(camera.at[1], -3.0f, 0.01f);
    EXPECT_NEAR(camera.at[2], 4.0f, 0.01f);
    const size_t framedCoverage = coverage(framed);
    EXPECT_GT(framedCoverage, 48u * 48u / 5);
    EXPECT_LT(framedCoverage, 48u * 48u * 3 / 4);

    // The same camera given as --eye/--look-at draws the same frame.
    r = run(args + " -o " + shot + " --eye " + vec3(camera.eye) + " --look-at " + vec3(camera.at) + " --compare " +
                framed,
            "NGI_VALIDATION=1");
    EXPECT_EQ(r.exitCode, 0) << r.output;
    // Zoomed in: the sphere fills the view, and the frame differs from the framed one.
    r = run(args + " -o " + shot + " --zoom 3 --compare " + framed, "NGI_VALIDATION=1");
    EXPECT_EQ(r.exitCode, 4) << r.output;
    EXPECT_EQ(coverage(shot), 48u * 48u);
    EXPECT_NEAR(cameraLine(r.output).distance, camera.distance / 3, 1e-4 * camera.distance);
    // Half the distance: bigger, but not filling the view; a wider lens: smaller.
    r = run(args + " -o " + shot + " --distance " + std::to_string(camera.distance * 0.75f));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_GT(coverage(shot), framedCoverage * 3 / 2);
    r = run(args + " -o " + shot + " --fov 60");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_LT(coverage(shot), framedCoverage * 2 / 3);
    // Looking from +z at a point 0.3 distances to the right (+x) of the centre: about the
    // view's half-width there (tan 17.5 deg = 0.315), so the sphere sits at the left border.
    const float beside[3] = {camera.at[0] + 0.3f * camera.distance, camera.at[1], camera.at[2]};
    r = run(args + " -o " + shot + " --look-at " + vec3(beside) + " --yaw 0 --pitch 0");
    ASSERT_EQ(r.exitCode, 0) << r.output;
    double meanX = 0.0;
    const size_t besideCoverage = coverage(shot, &meanX);
    EXPECT_GT(besideCoverage, framedCoverage / 10);
    EXPECT_LT(besideCoverage, framedCoverage * 3 / 4);
    EXPECT_LT(meanX, 12.0);

    const std::string out = (dir_ / "never.png").string(), base = moved + " --size 32x32 --samples 1 -o " + out;
    const struct {
        std::string args, message;
    } refused[] = {
        {" --look-at 1,2", "--look-at expects three numbers X,Y,Z, got '1,2'"},
        {" --look-at 1,2,3,4", "--look-at expects three numbers X,Y,Z, got '1,2,3,4'"},
        {" --look-at nan,0,0", "--look-at expects a number, got 'nan'"},
        {" --eye 0,inf,0", "--eye expects a number, got 'inf'"},
        {" --distance 0", "--distance must be positive"},
        {" --distance -1", "--distance must be positive"},
        {" --zoom 0", "--zoom must be positive"},
        {" --zoom 2 --distance 1", "--distance and --zoom are exclusive"},
        {" --fov 0", "--fov must be in [1, 170]"},
        {" --fov 180", "--fov must be in [1, 170]"},
        {" --eye 1,2,3 --look-at 1,2,3", "--eye and --look-at are the same point"},
        {" --eye 1,2,3 --yaw 10", "--eye places the camera"},
        {" --background 2,0,0", "--background components must be in [0, 1]"},
        {" --eye " + vec3(camera.at), "--eye is the camera's target"},
    };
    for (const auto& c : refused) {
        r = run(base + c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_FALSE(fs::exists(out)) << c.args;
    }
}

}  // namespace
