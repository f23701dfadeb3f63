// ngi-eval as a user runs it: the mesh command's export, the distance command's text and
// JSON output, and one clear error with a non-zero exit on bad input.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/eval/surface_distance.h"
#include "ngi/lod_grid.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/network_catalog.h"
#include "ngi/png_io.h"

#include "test_meshes.h"

#include "../support/tiny_network.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace {

namespace fs = std::filesystem;
namespace t = ngi::test;

struct ToolRun {
    int exitCode = -1;
    std::string out, err;
};

class NgiEvalCli : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_eval_cli_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    ToolRun run(const std::string& arguments, const std::string& prefix = "")
    {
        const fs::path out = dir_ / "stdout.txt", err = dir_ / "stderr.txt";
        const std::string command =
            prefix + std::string(NGI_EVAL_EXE) + " " + arguments + " >" + out.string() + " 2>" + err.string();
        const int status = std::system(command.c_str());
        ToolRun r;
        r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
        r.out = slurp(out);
        r.err = slurp(err);
        return r;
    }
    static std::string slurp(const fs::path& p)
    {
        std::ifstream in(p);
        std::stringstream s;
        s << in.rdbuf();
        return s.str();
    }
    std::string write(const std::string& name, const ngi::TriangleMesh& mesh)
    {
        const fs::path p = dir_ / name;
        ngi::writeMesh(p, mesh);
        return p.string();
    }
    fs::path dir_;
};

TEST_F(NgiEvalCli, distancePrintsChamferAndHausdorffWithUnits)
{
    const std::string a = write("a.off", t::octaSphere(16));
    const std::string b = write("b.obj", t::scaled(t::octaSphere(16), 1.1));
    const ToolRun r = run("distance " + a + " " + b + " --samples 20000");
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("CD = "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" x1e-4"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("HD = "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" x1e-2"), std::string::npos) << r.out;
}

// --heat-map shows where the distance is: a candidate that moved only the reference's upper half
// outwards is red on top and blue below, red at the HD unless --heat-max says otherwise; the
// picture is the reference from two sides.
TEST_F(NgiEvalCli, heatMapShowsWhereTheDistanceIs)
{
    const ngi::TriangleMesh sphere = t::octaSphere(16);
    const ngi::TriangleMesh moved =
        t::radiallyDisplaced(sphere, [](glm::dvec3 p) { return p.y > 0.0 ? 1.0 + 0.1 * p.y : 1.0; });
    const std::string a = write("a.off", sphere), b = write("b.off", moved);
    const fs::path map = dir_ / "heat.png", json = dir_ / "d.json";
    const ToolRun r =
        run("distance " + a + " " + b + " --samples 20000 --heat-map " + map.string() + " --json=" + json.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("heat map"), std::string::npos) << r.out;
    const ngi::PngImage png = ngi::readPng(map);
    ASSERT_EQ(png.width, 2u * 512 + 3 * 4);
    ASSERT_EQ(png.height, 512u + 2 * 4);
    const nlohmann::json j = nlohmann::json::parse(slurp(json));
    EXPECT_DOUBLE_EQ(j.at("heat_map").at("red_at_x1e-2").get<double>(), j.at("hausdorff_x1e-2").get<double>());
    // Red minus blue, averaged over the covered pixels of the top and the bottom third.
    auto warmth = [&](uint32_t y0, uint32_t y1) {
        double sum = 0.0;
        size_t n = 0;
        for (uint32_t y = y0; y < y1; ++y)
            for (uint32_t x = 0; x < png.width; ++x) {
                const size_t i = (size_t(y) * png.width + x) * png.channels;
                const int full = (1 << png.bitDepth) - 1;
                const int red = png.samples[i] * 255 / full, green = png.samples[i + 1] * 255 / full,
                          blue = png.samples[i + 2] * 255 / full;
                if (red == 255 && green == 255 && blue == 255) continue;
                sum += red - blue;
                ++n;
            }
        return n ? sum / double(n) : 0.0;
    };
    const double top = warmth(0, png.height / 3), bottom = warmth(2 * png.height / 3, png.height);
    EXPECT_GT(top, 30.0);
    EXPECT_LT(bottom, -30.0);
    EXPECT_GT(top - bottom, 100.0);

    const ToolRun fixed =
        run("distance " + a + " " + b + " --samples 2000 --heat-map " + map.string() + " --heat-max 2.5 --json");
    ASSERT_EQ(fixed.exitCode, 0) << fixed.err;
    EXPECT_DOUBLE_EQ(nlohmann::json::parse(fixed.out).at("heat_map").at("red_at_x1e-2").get<double>(), 2.5);
}

// Bad --heat-map and --heat-max values: one error naming the flag, exit 2, nothing written.
TEST_F(NgiEvalCli, heatMapBadValuesAreOneClearError)
{
    const std::string a = write("a.off", t::octaSphere(8));
    const fs::path map = dir_ / "heat.png";
    for (const std::string value : {"-1", "0", "nan", "inf", "1e9", "x", ""}) {
        const ToolRun r =
            run("distance " + a + " " + a + " --heat-map " + map.string() + " --heat-max '" + value + "'");
        EXPECT_EQ(r.exitCode, 2) << value;
        EXPECT_NE(r.err.find("--heat-max"), std::string::npos) << value << ": " << r.err;
    }
    const ToolRun alone = run("distance " + a + " " + a + " --heat-max 1");
    EXPECT_EQ(alone.exitCode, 2);
    EXPECT_NE(alone.err.find("--heat-max needs --heat-map"), std::string::npos) << alone.err;
    const ToolRun missing = run("distance " + a + " " + a + " --heat-map");
    EXPECT_EQ(missing.exitCode, 2);
    EXPECT_NE(missing.err.find("--heat-map"), std::string::npos) << missing.err;
    const ToolRun directory = run("distance " + a + " " + a + " --heat-map " + dir_.string());
    EXPECT_NE(directory.exitCode, 0);
    EXPECT_TRUE(fs::is_directory(dir_));
    EXPECT_FALSE(fs::exists(map));
}

TEST_F(NgiEvalCli, jsonMatchesTheLibrary)
{
    const ngi::TriangleMesh ma = t::octaSphere(16), mb = t::uvSphere(12, 24, 1.05);
    const std::string a = write("a.ply", ma), b = write("b.off", mb);
    const fs::path jsonFile = dir_ / "out.json";
    const ToolRun r = run("distance " + a + " " + b +
                          " --samples 5000 --seed 42 --threads 1 --json"
                          " --json=" +
                          jsonFile.string());
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const nlohmann::json j = nlohmann::json::parse(r.out);
    EXPECT_EQ(nlohmann::json::parse(slurp(jsonFile)), j);  // the same document, twice
    ngi::SurfaceDistanceOptions o;
    o.sampleCount = 5000;
    o.seed = 42;
    // The files hold the same surfaces up to the writers' decimal precision.
    const ngi::SurfaceDistance lib = ngi::surfaceDistance(ngi::readMesh(a), ngi::readMesh(b), o);
    EXPECT_DOUBLE_EQ(j.at("chamfer").get<double>(), lib.chamfer);
    EXPECT_DOUBLE_EQ(j.at("hausdorff").get<double>(), lib.hausdorff);
    EXPECT_DOUBLE_EQ(j.at("chamfer_x1e-4").get<double>(), lib.chamfer * 1e4);
    EXPECT_DOUBLE_EQ(j.at("hausdorff_x1e-2").get<double>(), lib.hausdorff * 1e2);
    EXPECT_EQ(j.at("samples_per_surface").get<uint32_t>(), 5000u);
    EXPECT_EQ(j.at("reference").at("triangles").get<size_t>(), ma.triangles.size());
    EXPECT_EQ(j.at("candidate").at("triangles").get<size_t>(), mb.triangles.size());
    // The seed as the text report prints it (0x and 16 hex digits) is the same seed.
    const ToolRun hex = run("distance " + a + " " + b + " --samples 5000 --seed 0x000000000000002a --threads 1 --json");
    ASSERT_EQ(hex.exitCode, 0) << hex.err;
    EXPECT_EQ(nlohmann::json::parse(hex.out).at("chamfer"), j.at("chamfer"));
}

TEST_F(NgiEvalCli, badInputGivesOneClearErrorAndNonZeroExit)
{
    const std::string good = write("good.off", t::octaSphere(4));
    {
        const ToolRun r = run("distance " + good + " " + (dir_ / "missing.off").string());
        EXPECT_EQ(r.exitCode, 1);
        EXPECT_NE(r.err.find("missing.off"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_EQ(r.out, "");
    }
    {
        std::ofstream(dir_ / "garbage.off") << "OFF\n3 1 0\n0 0 0\n1 0\n";
        const ToolRun r = run("distance " + (dir_ / "garbage.off").string() + " " + good);
        EXPECT_EQ(r.exitCode, 1);
        EXPECT_NE(r.err.find("garbage.off"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    for (const std::string& args :
         {std::string("distance ") + good, "distance " + good + " " + good + " --samples x",
          "distance " + good + " " + good + " --bogus", std::string("frobnicate"), std::string("")}) {
        const ToolRun r = run(args);
        EXPECT_EQ(r.exitCode, 2) << args;
        EXPECT_NE(r.err.find("usage: ngi-eval"), std::string::npos) << args;
    }
}

TEST_F(NgiEvalCli, meshWritesTheDrawnTriangleCountInOriginalCoordinates)
{
    const ngi::Asset asset = t::rippleAsset();  // 65^2 full, 7 levels
    const fs::path assetPath = dir_ / "ripple.ngi";
    ngi::writeAsset(asset, assetPath);
    for (const auto& [lod, grid] : {std::pair{"0", 65u}, {"1", 33u}, {"2.5", 17u}, {"6", 2u}}) {
        const fs::path out = dir_ / (std::string("lod") + lod + ".obj");
        const ToolRun r = run("mesh " + assetPath.string() + " --lod " + lod + " --no-sr -o " + out.string());
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const ngi::TriangleMesh m = ngi::readMesh(out);
        EXPECT_EQ(m.triangles.size(), ngi::gridTriangleCount(grid)) << lod;
        EXPECT_NE(r.out.find(std::to_string(ngi::gridTriangleCount(grid)) + " triangles"), std::string::npos) << r.out;
    }
    // Original coordinates: x spans offset.x + scale.x * [0, 1] = [-1, 3].
    const ngi::TriangleMesh full = ngi::readMesh(dir_ / "lod0.obj");
    double lo = 1e9, hi = -1e9;
    for (const glm::dvec3& p : full.positions) {
        lo = std::min(lo, p.x);
        hi = std::max(hi, p.x);
    }
    EXPECT_NEAR(lo, -1.0, 1e-4);
    EXPECT_NEAR(hi, 3.0, 1e-4);
    const ToolRun g = run("mesh " + assetPath.string() + " --grid 10 -o " + (dir_ / "g.ply").string());
    ASSERT_EQ(g.exitCode, 0) << g.err;
    EXPECT_EQ(ngi::readMesh(dir_ / "g.ply").triangles.size(), ngi::gridTriangleCount(10));
}

// A coloured asset exports as glTF with its chart image as the base colour texture; distance
// then measures colour between two meshes with appearance (inf for the same file), and says
// why it does not for a mesh without one (CD/HD still measured).
TEST_F(NgiEvalCli, meshWritesGlbWithTheChartTextureAndDistanceMeasuresItsColour)
{
    ngi::Asset asset = t::rippleAsset();
    ngi::AssetChart& chart = asset.charts[0];
    chart.baseColorLevel = 2;
    asset.coding.colorQuality = 101;  // lossless: the texels come back exactly
    for (uint32_t i = 0; i < chart.baseColorSize() * chart.baseColorSize(); ++i)
        chart.baseColor.insert(chart.baseColor.end(), {uint8_t(i * 7), uint8_t(i * 3), uint8_t(i), 255});
    const fs::path assetPath = dir_ / "coloured.ngi", glb = dir_ / "drawn.glb", gltf = dir_ / "drawn.gltf";
    ngi::writeAsset(asset, assetPath);
    for (const fs::path& out : {glb, gltf}) {
        const ToolRun r = run("mesh " + assetPath.string() + " --lod 1 --no-sr -o " + out.string());
        ASSERT_EQ(r.exitCode, 0) << r.err;
        EXPECT_NE(r.out.find("1 of 1 chart(s) with a base colour texture"), std::string::npos) << r.out;
        ngi::MeshAppearance appearance;
        const ngi::TriangleMesh m = ngi::readMesh(out, appearance);
        EXPECT_EQ(m.triangles.size(), ngi::gridTriangleCount(33));
        ASSERT_EQ(appearance.images.size(), 1u);
        EXPECT_EQ(appearance.images[0].rgba, chart.baseColor);
        EXPECT_EQ(appearance.cornerUVs.size(), m.triangles.size() * 3);
    }
    const ToolRun same = run("distance " + glb.string() + " " + gltf.string() + " --samples 3000 --json");
    ASSERT_EQ(same.exitCode, 0) << same.err;
    const nlohmann::json j = nlohmann::json::parse(same.out);
    EXPECT_EQ(j.at("colour").at("psnr_y"), "inf") << same.out;
    EXPECT_EQ(j.at("colour").at("mse_cr").get<double>(), 0.0);
    const ToolRun text = run("distance " + glb.string() + " " + glb.string() + " --samples 3000");
    EXPECT_NE(text.out.find("colour     PSNR Y inf dB"), std::string::npos) << text.out;

    const std::string grey = write("grey.off", t::heightField(8, true, [](double, double) { return 0.0; }));
    const ToolRun without = run("distance " + glb.string() + " " + grey + " --samples 3000 --json");
    ASSERT_EQ(without.exitCode, 0) << without.err;
    const nlohmann::json k = nlohmann::json::parse(without.out);
    EXPECT_TRUE(k.at("colour").is_null());
    EXPECT_NE(k.at("colour_not_measured").get<std::string>().find("grey.off has no appearance"), std::string::npos);
    EXPECT_TRUE(k.contains("chamfer"));
    const ToolRun off = run("distance " + glb.string() + " " + glb.string() + " --samples 3000 --no-colour");
    EXPECT_NE(off.out.find("colour     not measured (--no-colour)"), std::string::npos) << off.out;
}

TEST_F(NgiEvalCli, meshRestoresByBicubicAndByTheNetwork)
{
    // --bicubic, and --sr with a tiny x4 network whose residual is zero (bilinear skip): both
    // write the drawn mesh; the zero-residual network gives the --no-sr mesh.
    const fs::path assetPath = dir_ / "ripple.ngi", zero = dir_ / "zero.ngiw";
    ngi::writeAsset(t::rippleAsset(), assetPath);
    ngi::writeNetworkWeights(t::tinyNetwork(4, 0.0f), zero);
    const std::string mesh = "mesh " + assetPath.string() + " --lod 0 ";
    const ToolRun b = run(mesh + "--bicubic -o " + (dir_ / "b.obj").string());
    ASSERT_EQ(b.exitCode, 0) << b.err;
    EXPECT_NE(b.out.find("bicubic restore"), std::string::npos) << b.out;
    const ToolRun n = run(mesh + "--sr --weights " + zero.string() + " -o " + (dir_ / "n.obj").string());
    ASSERT_EQ(n.exitCode, 0) << n.err;
    EXPECT_NE(n.out.find("super-resolution restore"), std::string::npos) << n.out;
    ASSERT_EQ(run(mesh + "--no-sr -o " + (dir_ / "l.obj").string()).exitCode, 0);
    const ngi::TriangleMesh net = ngi::readMesh(dir_ / "n.obj"), lin = ngi::readMesh(dir_ / "l.obj");
    ASSERT_EQ(net.positions.size(), lin.positions.size());
    double largest = 0.0;
    for (size_t i = 0; i < net.positions.size(); ++i)
        largest = std::max(largest, glm::length(net.positions[i] - lin.positions[i]));
    EXPECT_LT(largest, 1e-4);  // OBJ text precision
    EXPECT_EQ(ngi::readMesh(dir_ / "b.obj").triangles.size(), ngi::gridTriangleCount(65));
}

// --sr alone restores with the shipped network the asset names (found by
// --networks DIR); a chart of another factor is restored bicubically and the output says so; a
// network of that name with another hash, or none in the search path, is one clear error.
TEST_F(NgiEvalCli, meshSrAloneUsesTheNetworkTheAssetNames)
{
    const fs::path shipped = dir_ / "shipped", assetPath = dir_ / "named.ngi";
    fs::create_directories(shipped);
    const ngi::NetworkWeights x4 = t::tinyNetwork(4, 0.01f);
    ngi::writeNetworkWeights(x4, shipped / "x4.ngiw");
    ngi::Asset asset = t::rippleAsset();
    ngi::AssetChart small = asset.charts[0];  // chart 1: the same 17^2 samples as a x2 chart
    small.fullResolution = 32;
    small.storedLevel = 1;
    asset.charts.push_back(small);
    asset.networkId = x4.name;
    asset.networkHash = ngi::networkHash(x4);
    ngi::writeAsset(asset, assetPath);
    const std::string mesh = "mesh " + assetPath.string() + " --lod 0 ";

    const ToolRun named = run(mesh + "--sr --networks " + shipped.string() + " -o " + (dir_ / "named.obj").string());
    ASSERT_EQ(named.exitCode, 0) << named.err;
    EXPECT_NE(named.out.find("network " + (shipped / "x4.ngiw").string()), std::string::npos) << named.out;
    EXPECT_NE(named.out.find("chart 1 (x2) is not restored by the x4 network: bicubic"), std::string::npos)
        << named.out;
    ASSERT_EQ(run(mesh + "--sr --weights " + (shipped / "x4.ngiw").string() + " -o " + (dir_ / "given.obj").string())
                  .exitCode,
              0);
    ASSERT_EQ(run(mesh + "--bicubic -o " + (dir_ / "bicubic.obj").string()).exitCode, 0);
    const ngi::TriangleMesh a = ngi::readMesh(dir_ / "named.obj"), b = ngi::readMesh(dir_ / "given.obj"),
                            cubic = ngi::readMesh(dir_ / "bicubic.obj");
    ASSERT_EQ(a.positions.size(), b.positions.size());
    ASSERT_EQ(a.positions.size(), cubic.positions.size());
    const size_t chart0 = 65 * 65;  // chart 0's vertices come first
    ASSERT_EQ(a.positions.size(), chart0 + 33 * 33);
    double sameAsGiven = 0.0, chart1FromCubic = 0.0, chart0FromCubic = 0.0;
    for (size_t i = 0; i < a.positions.size(); ++i) {
        sameAsGiven = std::max(sameAsGiven, double(glm::length(a.positions[i] - b.positions[i])));
        const double d = glm::length(a.positions[i] - cubic.positions[i]);
        (i < chart0 ? chart0FromCubic : chart1FromCubic) = std::max(i < chart0 ? chart0FromCubic : chart1FromCubic, d);
    }
    EXPECT_EQ(sameAsGiven, 0.0);
    EXPECT_LT(chart1FromCubic, 1e-4);  // OBJ text precision
    EXPECT_GT(chart0FromCubic, 1e-2);  // the network's residual (0.01 x 4 x the position sums)

    // A retrained network of the same name: one error naming both hashes, nothing written.
    const ngi::NetworkWeights retrained = t::tinyNetwork(4, 0.02f);
    ngi::writeNetworkWeights(retrained, shipped / "x4.ngiw");
    const fs::path out = dir_ / "out.obj";
    ToolRun r = run(mesh + "--sr --networks " + shipped.string() + " -o " + out.string());
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find(ngi::networkHashText(asset.networkHash)), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(ngi::networkHashText(ngi::networkHash(retrained))), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    // --weights overrides it with a warning naming both.
    r = run(mesh + "--sr --weights " + (shipped / "x4.ngiw").string() + " -o " + out.string());
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.err.find("warning"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(ngi::networkHashText(ngi::networkHash(retrained))), std::string::npos) << r.err;
    // No network of that name in the search path.
    fs::remove(out);
    fs::create_directories(dir_ / "empty");
    r = run(mesh + "--sr --networks " + (dir_ / "empty").string() + " -o " + out.string());
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("named.ngi: super-resolution restore needs a network"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("'tiny-x4'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find((dir_ / "empty").string()), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

// "every tool restoring with the matching network by default": with no
// restore option, `mesh` restores with the named network when it is found (the --sr mesh) and
// bicubically with a warning when it is not (the --bicubic mesh, exit 0).
TEST_F(NgiEvalCli, meshDefaultRestoreIsTheNamedNetworkWhenFound)
{
    const fs::path shipped = dir_ / "shipped", assetPath = dir_ / "named.ngi";
    fs::create_directories(shipped);
    fs::create_directories(dir_ / "empty");
    const ngi::NetworkWeights x4 = t::tinyNetwork(4, 0.01f);
    ngi::writeNetworkWeights(x4, shipped / "x4.ngiw");
    ngi::Asset asset = t::rippleAsset();
    asset.networkId = x4.name;
    asset.networkHash = ngi::networkHash(x4);
    ngi::writeAsset(asset, assetPath);
    const std::string mesh = "mesh " + assetPath.string() + " --lod 0 ";
    const ToolRun def = run(mesh + "--networks " + shipped.string() + " -o " + (dir_ / "default.obj").string());
    ASSERT_EQ(def.exitCode, 0) << def.err;
    EXPECT_NE(def.out.find("super-resolution: network " + (shipped / "x4.ngiw").string()), std::string::npos)
        << def.out;
    ASSERT_EQ(run(mesh + "--sr --networks " + shipped.string() + " -o " + (dir_ / "sr.obj").string()).exitCode, 0);
    ASSERT_EQ(run(mesh + "--no-sr -o " + (dir_ / "bilinear.obj").string()).exitCode, 0);
    ASSERT_EQ(run(mesh + "--bicubic -o " + (dir_ / "bicubic.obj").string()).exitCode, 0);
    const ToolRun missing =
        run(mesh + "--networks " + (dir_ / "empty").string() + " -o " + (dir_ / "missing.obj").string());
    ASSERT_EQ(missing.exitCode, 0) << missing.err;
    EXPECT_NE(missing.err.find("warning: " + assetPath.string()), std::string::npos) << missing.err;
    EXPECT_NE(missing.err.find((dir_ / "empty").string()), std::string::npos) << missing.err;
    auto far = [](const ngi::TriangleMesh& a, const ngi::TriangleMesh& b) {
        double d = a.positions.size() == b.positions.size() ? 0.0 : INFINITY;
        for (size_t i = 0; i < a.positions.size() && i < b.positions.size(); ++i)
            d = std::max(d, double(glm::length(a.positions[i] - b.positions[i])));
        return d;
    };
    const ngi::TriangleMesh d = ngi::readMesh(dir_ / "default.obj"), sr = ngi::readMesh(dir_ / "sr.obj"),
                            bilinear = ngi::readMesh(dir_ / "bilinear.obj"), m = ngi::readMesh(dir_ / "missing.obj"),
                            bicubic = ngi::readMesh(dir_ / "bicubic.obj");
    EXPECT_EQ(far(d, sr), 0.0);
    EXPECT_EQ(far(m, bicubic), 0.0);
    EXPECT_GT(far(bicubic, bilinear), 1e-5);
    EXPECT_GT(far(d, bilinear), 1e-2) << "a network that changes nothing tests nothing";
    EXPECT_EQ(run(mesh + "--no-sr --networks " + shipped.string() + " -o " + (dir_ / "x.obj").string()).exitCode, 2);
}

TEST_F(NgiEvalCli, meshRejectsCorruptAssetsBadLodAndSuperResolution)
{
    const fs::path assetPath = dir_ / "ripple.ngi", out = dir_ / "out.obj";
    ngi::writeAsset(t::rippleAsset(), assetPath);
    auto expectFailure = [&](const std::string& args, int code, const std::string& text) {
        const ToolRun r = run(args);
        EXPECT_EQ(r.exitCode, code) << args << "\n" << r.err;
        EXPECT_NE(r.err.find(text), std::string::npos) << args << "\n" << r.err;
        EXPECT_FALSE(fs::exists(out)) << args;
    };
    const std::string mesh = "mesh " + assetPath.string();
    expectFailure(mesh + " --lod 6.5 -o " + out.string(), 1, "outside [0, 6]");
    expectFailure(mesh + " --lod -1 -o " + out.string(), 1, "outside [0, 6]");
    expectFailure(mesh + " --lod 1 --sr -o " + out.string(), 1, "ripple.ngi: super-resolution restore needs a network");
    // A network for the wrong factor (the asset stores level 2: x4), a missing weights file,
    // --weights without --sr.
    const fs::path x8 = dir_ / "x8.ngiw";
    ngi::writeNetworkWeights(t::tinyNetwork(8, 0.0f), x8);
    expectFailure(mesh + " --lod 0 --sr --weights " + x8.string() + " -o " + out.string(), 1, "needs x4");
    expectFailure(mesh + " --lod 0 --sr --weights " + (dir_ / "none.ngiw").string() + " -o " + out.string(), 1,
                  "none.ngiw");
    expectFailure(mesh + " --lod 0 --weights " + x8.string() + " -o " + out.string(), 2, "--weights needs --sr");
    expectFailure(mesh + " --lod x -o " + out.string(), 2, "--lod expects a number");
    expectFailure(mesh + " --lod 1", 2, "-o OUT");
    expectFailure(mesh + " -o " + out.string(), 2, "--lod F or --grid N");
    expectFailure("mesh " + (dir_ / "none.ngi").string() + " --lod 1 -o " + out.string(), 1, "none.ngi");
    // One flipped byte in the last chunk's payload: its CRC fails.
    {
        std::fstream f(assetPath, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(-5, std::ios::end);
        const char c = char(f.get());
        f.seekp(-5, std::ios::end);
        f.put(char(c ^ 0x10));
    }
    const ToolRun r = run(mesh + " --lod 1 -o " + out.string());
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(r.err.find("ripple.ngi"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("CRC"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(out));
}

// Regression: no output may replace an input, and a run that fails leaves an
// existing output byte-identical with no temporary file beside it.
TEST_F(NgiEvalCli, outputsNeverReplaceAnInputOrAnExistingFileOnFailure)
{
    const fs::path assetPath = dir_ / "ripple.ngi", out = dir_ / "out.obj", json = dir_ / "d.json";
    ngi::writeAsset(t::rippleAsset(), assetPath);
    const std::string a = write("a.off", t::octaSphere(4));
    std::ofstream(out, std::ios::binary) << "an existing mesh";
    std::ofstream(json, std::ios::binary) << "an existing report";
    const std::string assetBytes = slurp(assetPath), meshBytes = slurp(a);
    const struct {
        std::string args, text;
    } cases[] = {
        {"mesh " + assetPath.string() + " --lod 1 -o " + assetPath.string(), "this output is the input"},
        {"mesh " + assetPath.string() + " --lod 1 -o " + (dir_ / "." / "ripple.ngi").string(),
         "this output is the input"},
        {"mesh " + assetPath.string() + " --lod 1 -o " + (dir_ / "out.stl").string(), "cannot write mesh format"},
        {"mesh " + assetPath.string() + " --lod 1 -o " + dir_.string(), "is a directory"},
        {"mesh " + assetPath.string() + " --lod 99 -o " + out.string(), "outside [0, 6]"},  // fails after staging
        {"distance " + a + " " + a + " --samples 100 --json=" + a, "this output is the input"},
        {"distance " + a + " " + (dir_ / "none.off").string() + " --samples 100 --json=" + json.string(), "none.off"},
    };
    for (const auto& c : cases) {
        const ToolRun r = run(c.args);
        EXPECT_EQ(r.exitCode, 1) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.text), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_EQ(slurp(assetPath), assetBytes);
        EXPECT_EQ(slurp(a), meshBytes);
        EXPECT_EQ(slurp(out), "an existing mesh");
        EXPECT_EQ(slurp(json), "an existing report");
        for (const auto& e : fs::directory_iterator(dir_))
            EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << c.args << ": " << e.path();
    }
    // A successful run replaces the existing output.
    ASSERT_EQ(run("mesh " + assetPath.string() + " --lod 1 -o " + out.string()).exitCode, 0);
    EXPECT_GT(ngi::readMesh(out).triangles.size(), 0u);
}

TEST_F(NgiEvalCli, meshWritesTheAdaptiveSurfaceForABoundOrACameraAndRejectsBadValues)
{
    const fs::path assetPath = dir_ / "adaptive-torus.ngi";
    ngi::writeAsset(ngi::makeAnalyticAsset("torus", ngi::rippledTorusGeometryImage(129, 0.08f), 2), assetPath);
    const fs::path out = dir_ / "adaptive.obj";
    auto triangles = [](const std::string& text) {
        const size_t at = text.find(": ");
        return at == std::string::npos ? 0ul : std::stoul(text.substr(at + 2));
    };
    const ToolRun fine = run("mesh " + assetPath.string() + " --max-error 0.001 -o " + out.string());
    ASSERT_EQ(fine.exitCode, 0) << fine.err;
    EXPECT_NE(fine.out.find("adaptive:"), std::string::npos) << fine.out;
    const ToolRun coarse = run("mesh " + assetPath.string() + " --max-error 0.05 -o " + out.string());
    ASSERT_EQ(coarse.exitCode, 0) << coarse.err;
    EXPECT_LT(4 * triangles(coarse.out), triangles(fine.out)) << fine.out << coarse.out;
    EXPECT_GT(ngi::readMesh(out).triangles.size(), 0u);
    const ToolRun camera = run("mesh " + assetPath.string() +
                               " --eye 0.5,0.5,2.5 --look-at 0.5,0.5,0.5 --max-error-px 2 "
                               "--size 640x480 -o " +
                               out.string());
    ASSERT_EQ(camera.exitCode, 0) << camera.err;
    EXPECT_NE(camera.out.find("facing away"), std::string::npos) << camera.out;
    // Bad values name the flag and exit 2; nothing is written over the last good mesh.
    const auto before = fs::last_write_time(out);
    for (const std::string bad :
         {"--max-error 0", "--max-error -1", "--max-error nan", "--max-error 1e999", "--max-error 2",
          "--eye 1,1 --look-at 0,0,0 --max-error-px 1", "--eye 1,1,1 --look-at 0,0,0 --max-error-px 0",
          "--eye 1,1,1 --look-at 0,0,0", "--eye 1,1,1 --look-at 0,0,0 --max-error-px 1 --size 0x10",
          "--eye 1,1,1 --look-at 0,0,0 --max-error-px 1 --fov 200", "--lod 1 --max-error 0.01"}) {
        const ToolRun r = run("mesh " + assetPath.string() + " " + bad + " -o " + out.string());
        EXPECT_EQ(r.exitCode, 2) << bad << ": " << r.err;
        const std::string flag = bad.substr(0, bad.find(' '));
        EXPECT_TRUE(r.err.find(flag) != std::string::npos || r.err.find("--max-error-px") != std::string::npos ||
                    r.err.find("--size") != std::string::npos || r.err.find("--fov") != std::string::npos)
            << bad << ": " << r.err;
    }
    EXPECT_EQ(fs::last_write_time(out), before);
    // The eye on the look-at point is one clear error naming the file.
    const ToolRun same =
        run("mesh " + assetPath.string() + " --eye 1,1,1 --look-at 1,1,1 --max-error-px 1 -o " + out.string());
    EXPECT_EQ(same.exitCode, 1) << same.err;
    EXPECT_NE(same.err.find("adaptive-torus.ngi"), std::string::npos) << same.err;
}

// A FIFO (which a plain open waits on forever) or a directory as the asset or the weights:
// one error naming it, a non-zero exit, no output; under `timeout`, so that a hang fails
// instead of blocking.
TEST_F(NgiEvalCli, aFifoOrADirectoryAsAnInputIsOneErrorNamingIt)
{
    const fs::path assetPath = dir_ / "ripple.ngi", out = dir_ / "out.obj";
    ngi::writeAsset(t::rippleAsset(), assetPath);
    const fs::path fifo = dir_ / "pipe.ngi", folder = dir_ / "folder.ngiw";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    fs::create_directories(folder);
    for (const fs::path& bad : {fifo, folder}) {
        const std::string expected =
            bad.string() + (bad == fifo ? ": is a FIFO" : ": is a directory") + ", not a regular file";
        for (const std::string& args :
             {"mesh " + bad.string() + " --lod 1 -o " + out.string(),
              "mesh " + assetPath.string() + " --lod 0 --sr --weights " + bad.string() + " -o " + out.string()}) {
            const ToolRun r = run(args, "timeout 120 ");
            EXPECT_EQ(r.exitCode, 1) << args << "\n" << r.err;  // 124: it hung
            EXPECT_NE(r.err.find(expected), std::string::npos) << args << "\n" << r.err;
            EXPECT_FALSE(fs::exists(out));
        }
    }
}

// ngi-eval mesh ended by SIGTERM while its output is staged leaves no temporary file and no
// output (what ngi-bake and ngi-render do, through the one output stager).
TEST_F(NgiEvalCli, meshInterruptedBySigtermLeavesNoTemporaryFile)
{
    // 513^2 samples drawn at level 0: half a million triangles, a ~20 MB OBJ.
    const fs::path assetPath = dir_ / "sphere.ngi", out = dir_ / "big.obj";
    ngi::writeAsset(ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(513), 2), assetPath);
    auto staged = [&] {
        for (const auto& e : fs::directory_iterator(dir_))
            if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
        return false;
    };
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        std::freopen("/dev/null", "w", stdout);
        std::freopen("/dev/null", "w", stderr);
        ::execl(NGI_EVAL_EXE, NGI_EVAL_EXE, "mesh", assetPath.c_str(), "--lod", "0", "--no-sr", "-o", out.c_str(),
                static_cast<char*>(nullptr));
        ::_exit(127);
    }
    // Wait for the staged file (the run is interrupted mid-write), at most a minute.
    int status = 0;
    bool exited = false, seen = false;
    for (int i = 0; i < 60000 && !seen && !exited; ++i) {
        seen = staged();
        if (!seen) {
            exited = ::waitpid(child, &status, WNOHANG) == child;
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    }
    ASSERT_FALSE(exited) << "ngi-eval ended before its output was staged: " << status;
    ASSERT_TRUE(seen);
    ::kill(child, SIGTERM);
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
    EXPECT_FALSE(staged());
    EXPECT_FALSE(fs::exists(out));
}

// Output paths a user can get wrong are named as given: no extension, or empty.
TEST_F(NgiEvalCli, meshOutputWithoutExtensionOrEmptyIsOneClearError)
{
    const fs::path assetPath = dir_ / "ripple.ngi";
    ngi::writeAsset(t::rippleAsset(), assetPath);
    ToolRun r = run("mesh " + assetPath.string() + " --lod 1 -o " + (dir_ / "out").string());
    EXPECT_EQ(r.exitCode, 1) << r.err;
    EXPECT_NE(r.err.find((dir_ / "out").string() + ": the output path has no extension (expected .obj, .off or .ply)"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find(".tmp"), std::string::npos) << r.err;
    r = run("mesh " + assetPath.string() + " --lod 1 -o ''");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("-o: the output path is empty"), std::string::npos) << r.err;
    r = run("distance " + assetPath.string() + " " + assetPath.string() + " --json=");
    EXPECT_EQ(r.exitCode, 2) << r.err;
    EXPECT_NE(r.err.find("--json=: the output path is empty"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "out"));
}

// Number flags: negative, out-of-range, non-finite and huge values are refused naming the flag.
TEST_F(NgiEvalCli, numberFlagsRefuseNegativeOutOfRangeAndNonFiniteValues)
{
    const fs::path assetPath = dir_ / "ripple.ngi", out = dir_ / "out.obj";
    ngi::writeAsset(t::rippleAsset(), assetPath);
    const std::string a = write("a.off", t::octaSphere(4));
    const struct {
        std::string args, text;
    } cases[] = {
        {"distance " + a + " " + a + " --samples -1", "--samples expects an integer in [0, 100000000], got '-1'"},
        {"distance " + a + " " + a + " --samples ' 5'", "--samples expects an integer"},
        {"distance " + a + " " + a + " --seed 18446744073709551616", "--seed expects an integer"},
        {"distance " + a + " " + a + " --seed 0x1g", "--seed expects an integer"},
        {"distance " + a + " " + a + " --threads 4294967297", "--threads expects an integer in [0, 256]"},
        {"mesh " + assetPath.string() + " --lod 1e999 -o " + out.string(), "--lod expects a number, got '1e999'"},
        {"mesh " + assetPath.string() + " --lod nan -o " + out.string(), "--lod expects a number, got 'nan'"},
        {"mesh " + assetPath.string() + " --grid -3 -o " + out.string(), "--grid expects an integer"},
    };
    for (const auto& c : cases) {
        const ToolRun r = run(c.args);
        EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.text), std::string::npos) << c.args << "\n" << r.err;
    }
    EXPECT_FALSE(fs::exists(out));
}

}  // namespace

TEST_F(NgiEvalCli, watertightPrintsOpenEdgesPerLodAndRejectsBadInput)
{
    // The analytic rippled torus carries its periodic seams: closed at every drawn LoD.
    const fs::path assetPath = dir_ / "torus.ngi";
    ngi::writeAsset(ngi::makeAnalyticAsset("torus", ngi::rippledTorusGeometryImage(65), 2), assetPath);
    const ToolRun ok = run("watertight " + assetPath.string());
    ASSERT_EQ(ok.exitCode, 0) << ok.err;
    EXPECT_NE(ok.out.find("seams matched"), std::string::npos) << ok.out;
    EXPECT_NE(ok.out.find("| 0.0 | 8192 | 0 | 0.0000 |"), std::string::npos) << ok.out;
    EXPECT_NE(ok.out.find("| 0.5 | 8192 | 0 |"), std::string::npos) << ok.out;
    EXPECT_NE(ok.out.find("| adaptive 1% | "), std::string::npos) << ok.out;
    EXPECT_EQ(ok.out.find(" | 1 | "), std::string::npos) << ok.out;  // no row with an open edge
    // Bad input: a missing asset names the file (exit 1); usage errors exit 2.
    const ToolRun missing = run("watertight " + (dir_ / "missing.ngi").string());
    EXPECT_EQ(missing.exitCode, 1);
    EXPECT_NE(missing.err.find("missing.ngi"), std::string::npos) << missing.err;
    EXPECT_EQ(run("watertight " + assetPath.string() + " --bogus").exitCode, 2);
    EXPECT_EQ(run("watertight " + assetPath.string() + " --weights x.ngiw").exitCode, 2);
    EXPECT_EQ(run("watertight").exitCode, 2);
}
