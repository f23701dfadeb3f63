// ngi-view as CI runs it: under Xvfb with the validation layer, a scripted LoD sequence and a
// screenshot of the last frame. Checks what a person would see: the surface covers a
// plausible part of the 3D view, the ImGui panel is drawn, the LoD readout follows the
// sequence; the window survives a resize; a bad file keeps the previous asset; the flat
// geometry image is drawn; with no display at all, one clear message and a non-zero exit.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/network_weights.h"
#include "ngi/png_io.h"

#include "run_tool.h"
#include "tiny_network.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <csignal>
#include <string>
#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

const std::string kDefaultAsset = NGI_SOURCE_DIR "/assets/default.ngi";
constexpr int kClear[3] = {28, 31, 36};  // the viewer's clear colour (0.11, 0.12, 0.14) in 8 bits

using ngi::test::runShell;
using ngi::test::ToolRun;

// A private Xvfb server. `-displayfd` lets the server pick a free display number itself and
// report it, so tests running in parallel (ctest -j) never race for the same display.
class XvfbServer {
public:
    // Empty on success, else why the server could not start.
    std::string start()
    {
        int fds[2];
        if (pipe(fds) != 0) return "pipe() failed";
        pid_ = fork();
        if (pid_ == 0) {
            close(fds[0]);
            const int devnull = open("/dev/null", O_WRONLY);
            dup2(devnull, STDOUT_FILENO);
            dup2(devnull, STDERR_FILENO);
            const std::string fd = std::to_string(fds[1]);
            execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", "1280x1024x24", "-nolisten", "tcp",
                   static_cast<char*>(nullptr));
            _exit(127);
        }
        close(fds[1]);
        std::string number;
        pollfd p{fds[0], POLLIN, 0};
        char c;
        while (poll(&p, 1, 20000) > 0 && read(fds[0], &c, 1) == 1 && c != '\n') number.push_back(c);
        close(fds[0]);
        if (number.empty())
            return "cannot start Xvfb: the ngi-view tests need it. Install the Debian package xvfb "
                   "(listed in tools/debian-packages.txt)";
        display_ = ":" + number;
        return "";
    }
    ~XvfbServer()
    {
        if (pid_ > 0) {
            kill(pid_, SIGTERM);
            waitpid(pid_, nullptr, 0);
        }
    }
    const std::string& display() const { return display_; }

private:
    pid_t pid_ = -1;
    std::string display_;
};

bool differsFromClear(const ngi::PngImage& png, uint32_t x, uint32_t y, int threshold = 12)
{
    const size_t i = (size_t(y) * png.width + x) * png.channels;
    for (int c = 0; c < 3; ++c)
        if (std::abs(int(png.samples[i + c]) - kClear[c]) > threshold) return true;
    return false;
}

// Fraction of pixels of the rectangle [x0, x1) x [0, height) that differ from the clear colour.
double coverage(const ngi::PngImage& png, uint32_t x0, uint32_t x1)
{
    size_t hits = 0, total = 0;
    for (uint32_t y = 0; y < png.height; ++y)
        for (uint32_t x = x0; x < x1; ++x, ++total) hits += differsFromClear(png, x, y);
    return total ? double(hits) / double(total) : 0.0;
}

size_t brightPixels(const ngi::PngImage& png, uint32_t x0, uint32_t x1)
{
    size_t n = 0;
    for (uint32_t y = 0; y < png.height; ++y)
        for (uint32_t x = x0; x < x1; ++x) {
            const size_t i = (size_t(y) * png.width + x) * png.channels;
            n += png.samples[i] > 180 && png.samples[i + 1] > 180 && png.samples[i + 2] > 180;
        }
    return n;
}

// The panel's right edge as the viewer reports it ("panel at x 0..W").
uint32_t panelRight(const std::string& output)
{
    const auto at = output.find("panel at x 0..");
    return at == std::string::npos ? 0 : uint32_t(std::stoul(output.substr(at + 14)));
}

class ViewCli : public ::testing::Test {
protected:
    void SetUp() override
    {
        const std::string error = xvfb_.start();
        ASSERT_TRUE(error.empty()) << error;
        dir_ = fs::temp_directory_path() / ("ngi_view_cli_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    // ngi-view on this test's Xvfb display.
    ToolRun runUnderXvfb(const std::string& args, const std::string& prefix = "")
    {
        return runShell(prefix + "env DISPLAY=" + xvfb_.display() + " " NGI_VIEW_BIN " " + args);
    }
    XvfbServer xvfb_;
    fs::path dir_;
};

TEST_F(ViewCli, ScriptedLodSequenceDrawsTheSurfaceAndThePanel)
{
    const std::string out = (dir_ / "sequence.png").string();
    const ToolRun r = runUnderXvfb(kDefaultAsset +
                                   " --validation --samples 1 --size 900x600 --frames 6"
                                   " --lod-sequence 0,2.5,5 --screenshot " +
                                   out);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("validation"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("LoD 0.00 -> level 0, 1025x1025 grid, morph 0.00, 2097152 triangles"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("LoD 2.50 -> level 2, 257x257 grid, morph 0.50, 131072 triangles"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("LoD 5.00 -> level 5, 33x33 grid, morph 0.00, 2048 triangles"), std::string::npos)
        << r.output;

    const ngi::PngImage png = ngi::readPng(out);
    ASSERT_EQ(png.width, 900u);
    ASSERT_EQ(png.height, 600u);
    const uint32_t panel = panelRight(r.output);
    ASSERT_GT(panel, 100u) << r.output;
    ASSERT_LT(panel, 600u) << r.output;
    // The surface: a torus framed in the view right of the panel.
    const double surface = coverage(png, panel, png.width);
    EXPECT_GT(surface, 0.10) << "the surface covers too little of the view";
    EXPECT_LT(surface, 0.90) << "the surface covers nearly all of the view (no background?)";
    // The panel: its background differs from the clear colour, and it has (bright) text.
    EXPECT_GT(coverage(png, 0, panel), 0.5) << "the ImGui panel is not drawn";
    EXPECT_GT(brightPixels(png, 0, panel), 500u) << "the ImGui panel has no text";
}

TEST_F(ViewCli, SurvivesAResizeAndABadFileKeepsThePreviousAsset)
{
    const std::string out = (dir_ / "resized.png").string();
    const std::string bad = (dir_ / "bad.ngi").string(), sphere = (dir_ / "sphere.ngi").string();
    std::ofstream(bad, std::ios::binary) << "this is not an ngi asset";
    ngi::writeAsset(ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(65), 2), sphere);
    const ToolRun r = runUnderXvfb(kDefaultAsset +
                                   " --validation --samples 4 --size 800x600 --lod 3 --frames 8"
                                   " --resize-at 2:640x480 --open-at 4:" +
                                   bad + " --open-at 5:" + sphere + " --open-at 6:" + bad + " --screenshot " + out);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("validation"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("cannot open: " + bad), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("(kept the previous asset)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("opened " + sphere), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("1 swapchain(s)"), std::string::npos) << "the resize did not recreate the swapchain\n"
                                                                  << r.output;

    const ngi::PngImage png = ngi::readPng(out);
    EXPECT_EQ(png.width, 640u);
    EXPECT_EQ(png.height, 480u);
    const uint32_t panel = panelRight(r.output);
    ASSERT_GT(panel, 0u) << r.output;
    // The sphere (opened after the bad file, kept after the second one) is still drawn.
    const double surface = coverage(png, panel, png.width);
    EXPECT_GT(surface, 0.10) << r.output;
    EXPECT_LT(surface, 0.90) << r.output;
}

// A FIFO (which a plain open waits on forever) or a directory as the asset: one error naming
// it and a non-zero exit, under `timeout` so that a hang fails instead of blocking.
TEST_F(ViewCli, AFifoOrADirectoryAsTheAssetIsOneErrorNamingIt)
{
    const fs::path fifo = dir_ / "pipe.ngi", folder = dir_ / "folder.ngi";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    fs::create_directories(folder);
    for (const fs::path& bad : {fifo, folder}) {
        const ToolRun r = runUnderXvfb(bad.string() + " --samples 1 --size 320x240 --frames 2", "timeout 120 ");
        EXPECT_EQ(r.exitCode, 1) << r.output;  // 124: it hung
        EXPECT_NE(
            r.output.find(bad.string() + (bad == fifo ? ": is a FIFO" : ": is a directory") + ", not a regular file"),
            std::string::npos)
            << r.output;
        EXPECT_EQ(r.output.find("bad_alloc"), std::string::npos) << r.output;
    }
}

TEST_F(ViewCli, GeometryImageModeShowsTheImageFlat)
{
    const std::string out = (dir_ / "flat.png").string();
    const ToolRun r = runUnderXvfb(kDefaultAsset +
                                   " --validation --samples 1 --size 800x500 --mode image --lod 4"
                                   " --hide-panel --frames 3 --screenshot " +
                                   out);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("validation"), std::string::npos) << r.output;
    const ngi::PngImage png = ngi::readPng(out);
    ASSERT_EQ(png.width, 800u);
    // A 0.9 * 500 px square centred in the window: covered; the margins left and right: clear.
    const double centre = coverage(png, 400 - 200, 400 + 200);
    EXPECT_GT(centre, 0.85) << "the flat geometry image is not drawn";
    EXPECT_LT(coverage(png, 0, 100), 0.01);
    // Positions as colours: the picture is not one flat colour.
    const size_t a = (size_t(150) * png.width + 250) * png.channels, b = (size_t(350) * png.width + 550) * png.channels;
    EXPECT_NE(png.samples[a] + 256 * png.samples[a + 1], png.samples[b] + 256 * png.samples[b + 1]);
}

TEST_F(ViewCli, SuperResolutionSwitchDrawsTheNetworksRestoration)
{
    // The factor the shipped asset's stored level needs (x4 for a 257^2 level of 1025^2), and
    // another one.
    const uint32_t factor = 1u << ngi::readAsset(kDefaultAsset).charts[0].storedLevel;
    const uint32_t other = factor == 4 ? 8 : 4;
    const std::string net = (dir_ / "tiny.ngiw").string(), wrong = (dir_ / "wrong.ngiw").string();
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(factor, 0.0f), net);
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(other, 0.0f), wrong);
    const std::string out = (dir_ / "sr.png").string();
    const ToolRun r = runUnderXvfb(kDefaultAsset + " --validation --samples 1 --size 800x500 --weights " + net +
                                   " --sr --frames 3 --lod 1 --screenshot " + out);
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("validation"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("super-resolution: forward pass"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("513x513 grid, morph 0.00, 524288 triangles (super-resolution)"), std::string::npos)
        << r.output;
    const ngi::PngImage png = ngi::readPng(out);
    const double surface = coverage(png, panelRight(r.output), png.width);
    EXPECT_GT(surface, 0.10) << r.output;
    EXPECT_LT(surface, 0.90) << r.output;

    // A network of the wrong scale: --sr says why and fails; without --sr the viewer runs.
    const ToolRun bad = runUnderXvfb(kDefaultAsset + " --samples 1 --weights " + wrong + " --sr --frames 2");
    EXPECT_EQ(bad.exitCode, 1) << bad.output;
    EXPECT_NE(bad.output.find("upsamples x" + std::to_string(other) + "; this asset needs x" + std::to_string(factor)),
              std::string::npos)
        << bad.output;
    EXPECT_EQ(runUnderXvfb(kDefaultAsset + " --samples 1 --weights " + wrong + " --frames 2").exitCode, 0);
}

// An asset naming a shipped network that is found (--networks DIR) opens
// with super-resolution on; --no-sr opens it restored bicubically (what ngi-render draws
// without a network); one naming a missing network opens bicubic (SR off, nothing to fail) and
// --sr then says why.
TEST_F(ViewCli, SuperResolutionIsOnByDefaultWhenTheNamedNetworkIsFound)
{
    const fs::path shipped = dir_ / "shipped";
    fs::create_directories(shipped);
    ngi::Asset asset = ngi::readAsset(kDefaultAsset);
    const ngi::NetworkWeights net = ngi::test::tinyNetwork(1u << asset.charts[0].storedLevel, 0.0f);
    ngi::writeNetworkWeights(net, shipped / "net.ngiw");
    asset.networkId = net.name;
    asset.networkHash = ngi::networkHash(net);
    const std::string named = (dir_ / "named.ngi").string();
    ngi::writeAsset(asset, named);
    const std::string common = named + " --validation --samples 1 --size 800x500 --frames 2 --lod 1 ";
    ToolRun r = runUnderXvfb(common + "--networks " + shipped.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("super-resolution on: network " + (shipped / "net.ngiw").string()), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find("(super-resolution)"), std::string::npos) << r.output;
    r = runUnderXvfb(common + "--no-sr --networks " + shipped.string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("super-resolution available (off)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("finer levels restored by bicubic upsampling (super-resolution off)"), std::string::npos)
        << r.output;
    EXPECT_EQ(r.output.find("(super-resolution)"), std::string::npos) << r.output;
    fs::create_directories(dir_ / "empty");
    r = runUnderXvfb(common + "--networks " + (dir_ / "empty").string());
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_EQ(r.output.find("(super-resolution)"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("finer levels restored by bicubic upsampling (no network restores this asset)"),
              std::string::npos)
        << r.output;
    r = runUnderXvfb(common + "--sr --networks " + (dir_ / "empty").string());
    EXPECT_EQ(r.exitCode, 1) << r.output;
    EXPECT_NE(r.output.find("not found in " + (dir_ / "empty").string()), std::string::npos) << r.output;
}

TEST(ViewNoDisplay, ExitsWithOneClearMessage)
{
    const ToolRun r = runShell("env -u DISPLAY -u WAYLAND_DISPLAY " NGI_VIEW_BIN " " + kDefaultAsset);
    EXPECT_NE(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("no display"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("ngi-render"), std::string::npos) << r.output;
}

TEST(ViewOptions, BadOptionsExitWithUsage)
{
    for (const std::string args :
         {"--screenshot x.png", "--frames 3 --lod 1 --lod-sequence 0,1", "--size 10", "--samples 3", "--frames abc",
          "--resize-at 3", "--frames 2 --screenshot ''", "--bogus", "--frames"}) {
        const ToolRun r = runShell("env -u DISPLAY " NGI_VIEW_BIN " " + kDefaultAsset + " " + args);
        EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.output;
        EXPECT_NE(r.output.find("usage: ngi-view"), std::string::npos) << args << "\n" << r.output;
    }
}

}  // namespace
