// The ngi-bake tool: every bad input gives one clear error, a non-zero exit and no output file;
// a good input writes the asset, the full-resolution PNGs and the JSON summary.
#include "ngi/asset.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/png_io.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

class BakeCli : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("ngi_bake_cli_" + std::to_string(::getpid()) + "_" +
                                            ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path file(const std::string& name) const { return dir_ / name; }
    void writeText(const std::string& name, const std::string& text) const { std::ofstream(file(name), std::ios::binary) << text; }

    // Runs ngi-bake with `arguments`; returns the exit code, stderr in `errors`.
    int bake(const std::string& arguments, std::string& errors) const {
        const fs::path errFile = dir_ / "stderr.txt";
        const std::string command = std::string("'") + NGI_BAKE_EXE + "' " + arguments + " > /dev/null 2> '" + errFile.string() + "'";
        const int status = std::system(command.c_str());
        std::ifstream in(errFile);
        std::stringstream text;
        text << in.rdbuf();
        errors = text.str();
        fs::remove(errFile);
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    // Expects failure naming `needle`, with nothing written to dir_ but the inputs.
    void expectFailure(const std::string& input, const std::string& needle, int code = 1, const std::string& extra = "") {
        SCOPED_TRACE(input);
        std::string errors;
        EXPECT_EQ(bake("'" + file(input).string() + "' -o '" + file("out.ngi").string() + "' --resolution 32 --store-res 8 --json '" +
                           file("out.json").string() + "' " + extra,
                       errors),
                  code);
        EXPECT_NE(errors.find(needle), std::string::npos) << errors;
        EXPECT_EQ(std::count(errors.begin(), errors.end(), '\n'), code == 1 ? 1 : std::count(errors.begin(), errors.end(), '\n'))
            << "one message: " << errors;
        EXPECT_FALSE(fs::exists(file("out.ngi")));
        EXPECT_FALSE(fs::exists(file("out.json")));
        for (const auto& entry : fs::directory_iterator(dir_))
            EXPECT_EQ(entry.path().extension() == ".png" || entry.path().filename().string().find(".tmp") != std::string::npos, false)
                << entry.path();
    }
    fs::path dir_;
};

TEST_F(BakeCli, BadInputsFailWithOneClearMessageAndNoOutput) {
    expectFailure("missing.obj", "no such file");
    writeText("mesh.xyz", "0 0 0\n");
    expectFailure("mesh.xyz", "unknown mesh format");
    writeText("corrupt.off", "OFF\nthis is not a number\n");
    expectFailure("corrupt.off", "corrupt.off");
    writeText("empty.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
    expectFailure("empty.off", "no triangles");
    writeText("nan.off", "OFF\n3 1 0\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
    expectFailure("nan.off", "nan.off");
    writeText("fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
    expectFailure("fin.obj", "non-manifold edge");
    writeText("degenerate.obj", "v 0 0 0\nv 1 0 0\nv 1 0 0\nf 1 2 3\n");
    expectFailure("degenerate.obj", "degenerate");
}

TEST_F(BakeCli, BadArgumentsAndUnwritableOutputsFail) {
    ngi::writeMesh(file("torus.obj"), ngi::makeTorus(16, 8));
    std::string errors;
    EXPECT_EQ(bake("'" + file("torus.obj").string() + "'", errors), 2);  // no -o
    EXPECT_NE(errors.find("no output file"), std::string::npos) << errors;
    expectFailure("torus.obj", "--param", 2, "--param magic");
    expectFailure("torus.obj", "power of two", 1, "--resolution 100");
    expectFailure("torus.obj", "--export-full", 1, "--export-full '" + file("nowhere").string() + "'");
    EXPECT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("no/such/dir/out.ngi").string() + "'", errors), 1);
    EXPECT_NE(errors.find("does not exist"), std::string::npos) << errors;
}

TEST_F(BakeCli, WritesAssetPngsAndJson) {
    ngi::writeMesh(file("torus.obj"), ngi::makeTorus(24, 12));
    std::string errors;
    ASSERT_EQ(bake("'" + file("torus.obj").string() + "' -o '" + file("torus.ngi").string() +
                       "' --resolution 32 --store-res 8 --remesh-vertices 600 --export-full '" + dir_.string() + "' --json '" +
                       file("torus.json").string() + "'",
                   errors),
              0)
        << errors;
    ngi::Asset asset = ngi::readAsset(file("torus.ngi"));
    EXPECT_EQ(asset.storedSize(), 9u);
    EXPECT_EQ(asset.fullResolution, 32u);
    EXPECT_EQ(asset.sourceName, "torus.obj");
    EXPECT_NE(asset.sourceHash, 0u);
    ngi::PngImage positions = ngi::readPng(file("torus_position.png"));
    EXPECT_EQ(positions.width, 33u);
    EXPECT_EQ(positions.bitDepth, 16u);
    EXPECT_TRUE(fs::exists(file("torus_normal.png")));
    std::ifstream json(file("torus.json"));
    nlohmann::json summary = nlohmann::json::parse(json);
    for (const char* key : {"input", "clean", "remesh", "genus", "boundaries", "cut", "parameterization", "seconds",
                            "peakMemoryBytes", "assetBytes", "compressionRatio"})
        EXPECT_TRUE(summary.contains(key)) << key;
    EXPECT_EQ(summary["genus"].get<int>(), 1);
    EXPECT_EQ(summary["parameterization"]["flippedTriangles"].get<int>(), 0);
    EXPECT_TRUE(summary["seconds"].contains("remesh"));
}

} // namespace
