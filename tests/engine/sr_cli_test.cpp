// Hostile super-resolution networks through the tools, as a user runs them:
// weights that overflow, a network of 4000 layers, networks the asset or the GPU cannot use.
// ngi-render and ngi-eval end every case with exit 1 and one message naming the asset and the
// network (its path, or the asset's WGHT chunk), write nothing, and never hang or crash.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/network_weights.h"
#include "ngi/nn/architecture.h"
#include "hostile_networks.h"
#include "run_tool.h"

#include <gtest/gtest.h>

#include <cfloat>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <unistd.h>

namespace {

namespace fs = std::filesystem;

using ngi::test::ToolRun;

void writeBytes(const fs::path& path, const std::vector<uint8_t>& bytes)
{
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// The small default architecture (attention included) for x4, random weights of magnitude ~5
// and an attention scale of FLT_MAX: the logits overflow to +-inf and the softmax is NaN (the
// original crash).
ngi::NetworkWeights overflowingAttention()
{
    ngi::NetworkWeights net = ngi::test::smallDefaultNetwork("attention", 11, 5.0f);
    for (ngi::NetworkLayer& l : net.layers)
        if (l.kind == ngi::LayerKind::NeighborhoodCrossAttention) l.attentionScale = FLT_MAX;
    return net;
}

class SrCli : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() / ("ngi_sr_cli_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
        asset_ = (dir_ / "sphere.ngi").string();  // 65^2, stores level 2 (17^2): needs x4
        ngi::writeAsset(ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(65), 2), asset_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // An asset like asset_ that carries `weights` as its WGHT chunk.
    std::string assetWithWeights(const std::string& name, const std::vector<uint8_t>& weights)
    {
        ngi::Asset a = ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(65), 2);
        a.weights = weights;
        const std::string path = (dir_ / name).string();
        ngi::writeAsset(a, path);
        return path;
    }
    std::string weightsFile(const std::string& name, const std::vector<uint8_t>& bytes)
    {
        const fs::path path = dir_ / name;
        writeBytes(path, bytes);
        return path.string();
    }

    // Runs a tool line that must fail with exit 1 and `text`, writing no `out`.
    void expectFailure(const std::string& command, const fs::path& out, const std::string& text)
    {
        const ToolRun r = ngi::test::runShell(command);
        EXPECT_EQ(r.exitCode, 1) << command << "\n" << r.output;
        EXPECT_NE(r.output.find(text), std::string::npos) << command << "\n" << r.output;
        EXPECT_FALSE(fs::exists(out)) << command;
    }
    std::string render(const std::string& asset, const std::string& args) const
    {
        return NGI_RENDER_BIN " " + asset + " -o " + png().string() + " --size 32x32 --samples 1 " + args;
    }
    fs::path png() const { return dir_ / "out.png"; }
    fs::path obj() const { return dir_ / "out.obj"; }

    fs::path dir_;
    std::string asset_;
};

// Findings: overflowing weights crashed ngi-eval (attention read out of bounds), made it write
// OBJs of nan, and made ngi-render exit 0 with a blank image, also through the asset's own
// WGHT chunk.
TEST_F(SrCli, OverflowingWeightsAreAnErrorNamingTheAssetAndTheNetwork)
{
    const std::vector<uint8_t> attention = ngi::serializeNetworkWeights(overflowingAttention());
    const std::string attentionPath = weightsFile("attention.ngiw", attention);
    const std::string withAttention = assetWithWeights("with_attention.ngi", attention);
    const std::vector<uint8_t> huge = ngi::serializeNetworkWeights(ngi::test::tinyNetwork(4, FLT_MAX));
    const std::string hugePath = weightsFile("huge.ngiw", huge);
    const std::string withHuge = assetWithWeights("with_huge.ngi", huge);
#ifdef NGI_EVAL_BIN
    const std::string mesh = " --lod 0 --sr -o " + obj().string();
    expectFailure(NGI_EVAL_BIN " mesh " + asset_ + mesh + " --weights " + attentionPath, obj(),
                  asset_ + ": " + attentionPath + ": the restore produced non-finite values (layer ");
    expectFailure(NGI_EVAL_BIN " mesh " + withAttention + mesh, obj(),
                  withAttention + ": the asset's WGHT chunk: the restore produced non-finite values (layer ");
    expectFailure(NGI_EVAL_BIN " mesh " + asset_ + mesh + " --weights " + hugePath, obj(),
                  asset_ + ": " + hugePath + ": the restore produced non-finite values (layer 0)");
#endif
    expectFailure(render(asset_, "--sr --weights " + hugePath), png(),
                  asset_ + ": " + hugePath + ": the restore produced non-finite values (");
    expectFailure(render(withHuge, "--sr"), png(),
                  withHuge + ": the asset's WGHT chunk: the restore produced non-finite values (");
    expectFailure(render(withAttention, "--sr"), png(),
                  withAttention + ": the asset's WGHT chunk: the restore produced non-finite values (");
}

// Finding: a 330 KB network of 4000 layers hung ngi-render and ngi-eval. The reader refuses it
// from its header, before allocating or running anything.
TEST_F(SrCli, ANetworkBeyondTheLimitsIsRefusedBeforeAnythingRuns)
{
    const std::vector<uint8_t> deep = ngi::test::unvalidatedWeightsFile(ngi::test::longNetwork(3997, 4));
    const std::string deepPath = weightsFile("deep.ngiw", deep);
    const std::string withDeep = assetWithWeights("with_deep.ngi", deep);
    const std::string limit = "the network has 4000 layers; the limit is 256 (kMaxNetworkLayers)";
    expectFailure(render(asset_, "--sr --weights " + deepPath), png(), deepPath + ": " + limit);
    expectFailure(render(withDeep, "--sr"), png(), withDeep + ": the asset's WGHT chunk: " + limit);
#ifdef NGI_EVAL_BIN
    expectFailure(NGI_EVAL_BIN " mesh " + asset_ + " --lod 0 --sr -o " + obj().string() + " --weights " + deepPath,
                  obj(), deepPath + ": " + limit);
    expectFailure(NGI_EVAL_BIN " mesh " + withDeep + " --lod 0 --sr -o " + obj().string(), obj(),
                  withDeep + ": the asset's WGHT chunk: " + limit);
#endif
}

// Finding: ngi-render's "x8 network does not restore ..." and GPU layer messages named neither
// the asset nor the network.
TEST_F(SrCli, RenderMessagesNameTheAssetAndTheNetwork)
{
    const std::string x8 = (dir_ / "x8.ngiw").string(), wide = (dir_ / "wide.ngiw").string();
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(8, 0.0f), x8);
    ngi::writeNetworkWeights(ngi::test::wideConvNetwork(4), wide);
    expectFailure(
        render(asset_, "--sr --weights " + x8), png(),
        asset_ + ": the x8 network " + x8 +
            " restores 17 samples per side to 129, but this asset's full resolution is 65 (it needs a x4 network)");
    expectFailure(render(asset_, "--sr --weights " + wide), png(),
                  asset_ + ": " + wide + ": layer 1 has too many input channels (500)");
    const std::string withWide =
        assetWithWeights("with_wide.ngi", ngi::serializeNetworkWeights(ngi::test::wideConvNetwork(4)));
    expectFailure(render(withWide, "--sr"), png(),
                  withWide + ": the asset's WGHT chunk: layer 1 has too many input channels");
}

}  // namespace
