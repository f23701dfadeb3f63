// `ngi-eval report` end to end on two tiny procedural meshes at resolution 32: the page has
// Table 1, Table 4 and the peers with a row per parameterization / stored resolution and
// finite numbers, the plots and contact sheets exist, --reuse reuses the bakes, and bad
// input is one clear error (library and tool).
#include "ngi/error.h"
#include "ngi/eval/report.h"
#include "ngi/eval/report_picture.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/png_io.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p)
{
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

class Report : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_report_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "meshes");
        ngi::writeMesh(dir_ / "meshes" / "sphere.off", ngi::makeSphere(2));
        ngi::writeMesh(dir_ / "meshes" / "patch.off", ngi::makePlanePatch(12, 1.0, 0.3));
    }
    void TearDown() override { fs::remove_all(dir_); }

    ngi::ReportOptions tinyOptions() const
    {
        ngi::ReportOptions o;
        o.meshes = ngi::resolveMeshList((dir_ / "meshes").string());
        o.outDir = dir_ / "out";
        o.resolution = 32;
        o.storedResolutions = {8, 16};
        o.parameterizations = {ngi::ParameterizationMethod::Tutte, ngi::ParameterizationMethod::OptimalTransport};
        o.pictureStoredResolution = 16;
        o.sampleCount = 4000;
        o.pictureSize = 48;
        o.command = "test";
        return o;
    }

    fs::path dir_;
};

// The cells of the Markdown row starting with `head` ("| tutte |"), split at '|'.
std::vector<std::string> rowCells(const std::string& page, const std::string& head)
{
    const size_t at = page.find("\n" + head);
    if (at == std::string::npos) return {};
    const std::string line = page.substr(at + 1, page.find('\n', at + 1) - at - 1);
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, '|')) cells.push_back(cell);
    return cells;
}

// "CD / HD" cells: both numbers finite and >= 0.
int finitePairs(const std::vector<std::string>& cells)
{
    int pairs = 0;
    const std::regex pair(R"re(^\s*([0-9.e+-]+) / ([0-9.e+-]+)\s*)re");
    for (const std::string& c : cells) {
        std::smatch m;
        if (std::regex_search(c, m, pair) && std::isfinite(std::stod(m[1])) && std::isfinite(std::stod(m[2]))) ++pairs;
    }
    return pairs;
}

TEST_F(Report, RunsEndToEndOnTinyMeshes)
{
    std::vector<ngi::ReportProgress> steps;
    ngi::ReportOptions o = tinyOptions();
    o.progress = [&](const ngi::ReportProgress& p) { steps.push_back(p); };
    const ngi::ReportResult r = ngi::runReport(o);
    EXPECT_EQ(r.meshCount, 2u);
    EXPECT_EQ(r.failedBakes, 0u);
    ASSERT_TRUE(fs::exists(r.reportPath));
    const std::string page = slurp(r.reportPath);

    EXPECT_NE(page.find("## Table 1"), std::string::npos);
    EXPECT_NE(page.find("## Table 4"), std::string::npos);
    EXPECT_NE(page.find("## Peers at equal bytes"), std::string::npos);
    EXPECT_NE(page.find("CD x1e-4"), std::string::npos);
    // Table 1: a row per parameterization, a finite CD / HD per mesh plus the mean.
    EXPECT_EQ(finitePairs(rowCells(page, "| tutte |")), 3);
    EXPECT_EQ(finitePairs(rowCells(page, "| ot |")), 3);
    // Table 4: a row per stored resolution with CR (32/8)^2 = 16 and (32/16)^2 = 4 (against the
    // full resolution, not a fixed 1024), no-SR numbers, SR pending.
    const std::vector<std::string> s8 = rowCells(page, "| 8 x 8 |");
    ASSERT_FALSE(s8.empty());
    EXPECT_EQ(s8[2], " 16 ");
    EXPECT_EQ(finitePairs(s8), 3);
    EXPECT_EQ(finitePairs(rowCells(page, "| 16 x 16 |")), 3);
    EXPECT_NE(page.find("no trained network"), std::string::npos);
    // Peers: per mesh, one row per stored resolution with ngi, meshopt+Draco, Loop, Butterfly.
    for (const std::string name : {"### patch", "### sphere"}) {
        const size_t section = page.find(name);
        ASSERT_NE(section, std::string::npos) << name;
        const std::string rest = page.substr(section);
        EXPECT_EQ(finitePairs(rowCells(rest, "| 8 | 16 |")), 4) << name;
        EXPECT_EQ(finitePairs(rowCells(rest, "| 16 | 4 |")), 4) << name;
    }
    // Plots and pictures.
    for (const char* file : {"plots/rd_cd_patch.svg", "plots/rd_hd_sphere.svg", "plots/lod_patch.svg",
                             "pictures/patch.png", "pictures/sphere.png", "assets/sphere.ot.s8.ngi"})
        EXPECT_TRUE(fs::exists(o.outDir / file)) << file;
    const ngi::PngImage sheet = ngi::readPng(o.outDir / "pictures" / "sphere.png");
    EXPECT_GT(sheet.width, 48u * 4);
    // The heat map: two 512-pixel views of the input, coloured (not only grey and white).
    const ngi::PngImage heat = ngi::readPng(o.outDir / "pictures" / "sphere.heat.png");
    EXPECT_EQ(heat.width, 2 * 512u + 3 * 4);  // two tiles and three gaps
    size_t coloured = 0;
    const int scale = heat.bitDepth == 16 ? 257 : 1;
    for (size_t i = 0; i + 2 < heat.samples.size(); i += heat.channels)
        coloured += std::abs(int(heat.samples[i]) - int(heat.samples[i + 2])) > 60 * scale;
    EXPECT_GT(coloured, 1000u);
    EXPECT_NE(page.find("sphere distance heat map](pictures/sphere.heat.png)"), std::string::npos);
    // Progress: increasing, ending at the total.
    ASSERT_FALSE(steps.empty());
    for (size_t i = 1; i < steps.size(); ++i) EXPECT_GE(steps[i].done, steps[i - 1].done);
    EXPECT_DOUBLE_EQ(steps.back().done, steps.back().total);
    // No temporary files left behind.
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(o.outDir))
        EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();

    // --reuse: the full images are read back, not baked again; the numbers are the same.
    ngi::ReportOptions again = tinyOptions();
    again.reuse = true;
    ngi::runReport(again);
    const std::string reused = slurp(again.outDir / "report.md");
    EXPECT_NE(reused.find("(reused) |"), std::string::npos);  // the bake time from the asset's report
    EXPECT_EQ(reused.find("| patch | ot | reused |"), std::string::npos);
    EXPECT_EQ(rowCells(reused, "| patch | ot |")[4], rowCells(page, "| patch | ot |")[4]);  // area distortion
    EXPECT_EQ(rowCells(reused, "| ot |"), rowCells(page, "| ot |"));
}

TEST_F(Report, BadInputIsOneClearError)
{
    try {
        ngi::resolveMeshList((dir_ / "missing").string());
        FAIL() << "no error for a missing directory";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("missing"), std::string::npos) << e.what();
    }
    EXPECT_THROW(ngi::resolveMeshList((dir_ / "meshes" / "sphere.off").string() + ",nope.off"), ngi::Error);
    fs::create_directories(dir_ / "empty");
    EXPECT_THROW(ngi::resolveMeshList((dir_ / "empty").string()), ngi::Error);

    // An unreadable mesh fails before any work is done.
    std::ofstream(dir_ / "meshes" / "broken.off") << "OFF\n3 1 0\n0 0 0\n1 0\n";
    ngi::ReportOptions o = tinyOptions();
    o.meshes = ngi::resolveMeshList((dir_ / "meshes").string());
    try {
        ngi::runReport(o);
        FAIL() << "no error for a broken mesh";
    } catch (const ngi::Error& e) {
        EXPECT_NE(std::string(e.what()).find("broken.off"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(o.outDir / "report.md"));

    ngi::ReportOptions bad = tinyOptions();
    bad.resolution = 48;
    EXPECT_THROW(ngi::runReport(bad), ngi::Error);
    bad = tinyOptions();
    bad.storedResolutions = {64};
    EXPECT_THROW(ngi::runReport(bad), ngi::Error);
    bad = tinyOptions();
    bad.jobs = 0;
    EXPECT_THROW(ngi::runReport(bad), ngi::Error);
}

TEST(ReportPicture, DrawsTheMeshInsideTheFrame)
{
    const ngi::TriangleMesh sphere = ngi::makeSphere(2);
    const ngi::PictureView view = ngi::pictureViewFor(sphere);
    const ngi::RgbImage image = ngi::renderMeshPicture(sphere, view, 40);
    ASSERT_EQ(image.width, 40u);
    ASSERT_EQ(image.rgb.size(), 40u * 40 * 3);
    auto white = [&](uint32_t x, uint32_t y) {
        const uint8_t* p = &image.rgb[(size_t(y) * 40 + x) * 3];
        return p[0] == 255 && p[1] == 255 && p[2] == 255;
    };
    EXPECT_FALSE(white(20, 20));  // the centre is covered
    EXPECT_TRUE(white(0, 0));     // corners of a sphere's frame are background
    EXPECT_TRUE(white(39, 39));
    const ngi::RgbImage sheet = ngi::contactSheet({image, image, image}, 2, 4);
    EXPECT_EQ(sheet.width, 2u * 40 + 3 * 4);
    EXPECT_EQ(sheet.height, 2u * 40 + 3 * 4);
    EXPECT_THROW(ngi::contactSheet({}, 2), ngi::Error);
}

// A square facing the camera, split into two triangles of one colour each: each triangle's
// pixels take its colour (shaded by the same light), about half the square each.
TEST(ReportPicture, TrianglesTakeTheirOwnColours)
{
    ngi::TriangleMesh square;
    square.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    square.triangles = {{0, 1, 2}, {0, 2, 3}};
    const ngi::PictureView view = ngi::pictureViewFor(square, 0.0, 0.0);
    const std::vector<glm::vec3> colours = {{0.9f, 0.1f, 0.1f}, {0.1f, 0.1f, 0.9f}};
    const ngi::RgbImage image = ngi::renderMeshPicture(square, view, 64, colours);
    size_t red = 0, blue = 0, other = 0;
    for (size_t i = 0; i < image.rgb.size(); i += 3) {
        const int r = image.rgb[i], g = image.rgb[i + 1], b = image.rgb[i + 2];
        if (r == 255 && g == 255 && b == 255) continue;  // background
        if (r > 3 * b && r > 3 * g)
            ++red;
        else if (b > 3 * r && b > 3 * g)
            ++blue;
        else
            ++other;  // the diagonal's blended pixels
    }
    EXPECT_GT(red, 1000u);
    EXPECT_NEAR(double(red) / double(blue), 1.0, 0.1);
    EXPECT_LT(other, (red + blue) / 20);
    EXPECT_THROW(ngi::renderMeshPicture(square, view, 64, std::vector<glm::vec3>(3)), ngi::Error);
}

// The heat ramp: blue at 0, red at 1, green in the middle, clamped outside [0, 1], NaN red.
TEST(ReportPicture, HeatColourRunsFromBlueToRed)
{
    const glm::vec3 cold = ngi::heatColour(0.0), mid = ngi::heatColour(0.5), hot = ngi::heatColour(1.0);
    EXPECT_GT(cold.b, 2.0f * cold.r);
    EXPECT_GT(hot.r, 2.0f * hot.b);
    EXPECT_GT(mid.g, mid.r);
    EXPECT_GT(mid.g, mid.b);
    EXPECT_EQ(ngi::heatColour(-3.0), cold);
    EXPECT_EQ(ngi::heatColour(7.0), hot);
    EXPECT_EQ(ngi::heatColour(std::nan("")), hot);
}

#ifdef NGI_EVAL_EXE
int runTool(const std::string& arguments, std::string& err)
{
    const fs::path errPath = fs::temp_directory_path() / "ngi_report_cli_err.txt";
    const int status =
        std::system((std::string(NGI_EVAL_EXE) + " " + arguments + " >/dev/null 2>" + errPath.string()).c_str());
    err = slurp(errPath);
    fs::remove(errPath);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(ReportCli, BadInputExitsNonZeroWithOneMessage)
{
    std::string err;
    EXPECT_EQ(runTool("report --meshes /nonexistent/meshes --out /tmp/ngi_report_cli_out", err), 1);
    EXPECT_NE(err.find("ngi-eval: /nonexistent/meshes: no such mesh file or directory"), std::string::npos) << err;
    EXPECT_EQ(runTool("report --out /tmp/ngi_report_cli_out", err), 2);
    EXPECT_NE(err.find("--meshes"), std::string::npos) << err;
    EXPECT_EQ(runTool("report --meshes a.off --out x --params nope", err), 2);
    EXPECT_FALSE(fs::exists("/tmp/ngi_report_cli_out"));
}
#endif

}  // namespace
