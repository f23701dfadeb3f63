// The shipped networks and the one an asset names (ngi/network_catalog.h): found by name and
// hash, a retrained network of the same name and a missing one are reported, never used; a
// network file that does not read is skipped and reported.
#include "ngi/network_catalog.h"

#include "ngi/error.h"

#include "../support/tiny_network.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

namespace {

namespace fs = std::filesystem;

class NetworkCatalog : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_network_catalog_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // An asset with one chart of full resolution 64 stored at `storedLevel`.
    static ngi::Asset asset(uint32_t storedLevel)
    {
        ngi::Asset a;
        ngi::AssetChart c;
        c.fullResolution = 64;
        c.storedLevel = storedLevel;
        a.charts.push_back(c);
        return a;
    }

    fs::path dir_;
};

TEST_F(NetworkCatalog, NamesTheNetworkOfTheLargestChartsFactorAndFindsItByNameAndHash)
{
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(4, 0.0f), dir_ / "a.ngiw");
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(8, 0.0f), dir_ / "b.ngiw");
    const std::vector<fs::path> dirs{dir_ / "missing", dir_};
    std::vector<std::string> skipped;
    const std::vector<ngi::ShippedNetwork> shipped = ngi::findShippedNetworks(dirs, skipped);
    ASSERT_EQ(shipped.size(), 2u);
    EXPECT_TRUE(skipped.empty());

    ngi::Asset x8 = asset(3);
    const ngi::ShippedNetwork* named = ngi::nameMatchingNetwork(x8, shipped);
    ASSERT_NE(named, nullptr);
    EXPECT_EQ(named->path, dir_ / "b.ngiw");
    EXPECT_EQ(x8.networkId, "tiny-x8");
    EXPECT_EQ(x8.networkHash, ngi::networkHash(ngi::test::tinyNetwork(8, 0.0f)));
    std::string problem;
    const std::optional<ngi::NetworkWeights> found = ngi::findAssetNetwork(x8, dirs, problem, skipped);
    ASSERT_TRUE(found) << problem;
    EXPECT_EQ(*found, ngi::test::tinyNetwork(8, 0.0f));
    EXPECT_TRUE(problem.empty());
    EXPECT_EQ(ngi::networkMismatch(x8, *found), "");

    // x16: no shipped network; the names are cleared.
    ngi::Asset x16 = asset(4);
    x16.networkId = "stale";
    EXPECT_EQ(ngi::nameMatchingNetwork(x16, shipped), nullptr);
    EXPECT_EQ(x16.networkId, "");
    EXPECT_EQ(x16.networkHash, 0u);
    EXPECT_FALSE(ngi::findAssetNetwork(x16, dirs, problem, skipped));
    EXPECT_NE(problem.find("names no network"), std::string::npos) << problem;
}

TEST_F(NetworkCatalog, ReportsARetrainedNetworkOfTheSameNameWithBothHashes)
{
    ngi::Asset a = asset(3);
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(8, 0.0f), dir_ / "net.ngiw");
    std::vector<std::string> skipped;
    ngi::nameMatchingNetwork(a, ngi::findShippedNetworks(std::vector<fs::path>{dir_}, skipped));
    ASSERT_EQ(a.networkId, "tiny-x8");
    const ngi::NetworkWeights retrained = ngi::test::tinyNetwork(8, 0.25f);  // same name, other weights
    ngi::writeNetworkWeights(retrained, dir_ / "net.ngiw");
    std::string problem;
    EXPECT_FALSE(ngi::findAssetNetwork(a, std::vector<fs::path>{dir_}, problem, skipped));
    EXPECT_NE(problem.find(ngi::networkHashText(a.networkHash)), std::string::npos) << problem;
    EXPECT_NE(problem.find(ngi::networkHashText(ngi::networkHash(retrained))), std::string::npos) << problem;
    EXPECT_NE(problem.find((dir_ / "net.ngiw").string()), std::string::npos) << problem;
    // --weights with it: a warning naming both, the network still returned (an override).
    std::string warning;
    const ngi::NetworkWeights given = ngi::networkForRestore(a, dir_ / "net.ngiw", {}, warning, skipped);
    EXPECT_EQ(given, retrained);
    EXPECT_NE(warning.find("'tiny-x8' (hash " + ngi::networkHashText(a.networkHash)), std::string::npos) << warning;
    EXPECT_NE(warning.find(ngi::networkHashText(ngi::networkHash(retrained))), std::string::npos) << warning;
}

TEST_F(NetworkCatalog, NoNetworkFoundIsOneErrorListingTheDirectories)
{
    ngi::Asset a = asset(3);
    a.networkId = "ngi-sr-x8";
    a.networkHash = 42;
    std::string warning;
    std::vector<std::string> skipped;
    try {
        ngi::networkForRestore(a, "", std::vector<fs::path>{dir_}, warning, skipped);
        FAIL() << "expected an error";
    } catch (const ngi::Error& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("needs a network"), std::string::npos) << what;
        EXPECT_NE(what.find("'ngi-sr-x8'"), std::string::npos) << what;
        EXPECT_NE(what.find(dir_.string()), std::string::npos) << what;
    }
    // A network file that does not read is named in the error of a network not found.
    ngi::writeFileAtomic(dir_ / "broken.ngiw", std::vector<uint8_t>{1, 2, 3});
    try {
        ngi::networkForRestore(a, "", std::vector<fs::path>{dir_}, warning, skipped);
        FAIL() << "expected an error";
    } catch (const ngi::Error& e) {
        EXPECT_NE(
            std::string(e.what()).find("skipped a network file that does not read: " + (dir_ / "broken.ngiw").string()),
            std::string::npos)
            << e.what();
    }
}

// One broken *.ngiw in the networks directory (or a directory or FIFO named *.ngiw) does not
// hide the valid network beside it: it is skipped, and said in `skipped` for the tool to warn.
TEST_F(NetworkCatalog, AnUnrelatedBrokenNetworkFileIsSkippedWithAWarning)
{
    const ngi::NetworkWeights x8 = ngi::test::tinyNetwork(8, 0.0f);
    ngi::writeNetworkWeights(x8, dir_ / "b.ngiw");
    ngi::writeFileAtomic(dir_ / "a.ngiw", std::vector<uint8_t>{1, 2, 3});
    fs::create_directories(dir_ / "c.ngiw");
    ngi::Asset a = asset(3);
    a.networkId = x8.name;
    a.networkHash = ngi::networkHash(x8);
    const std::vector<fs::path> dirs{dir_};

    std::vector<std::string> skipped;
    const std::vector<ngi::ShippedNetwork> shipped = ngi::findShippedNetworks(dirs, skipped);
    ASSERT_EQ(shipped.size(), 1u);
    EXPECT_EQ(shipped[0].path, dir_ / "b.ngiw");
    ASSERT_EQ(skipped.size(), 1u);  // a directory is not a candidate at all
    EXPECT_EQ(skipped[0].rfind((dir_ / "a.ngiw").string() + ": ", 0), 0u) << skipped[0];

    skipped.clear();
    std::string problem, warning;
    const std::optional<ngi::NetworkWeights> found = ngi::findAssetNetwork(a, dirs, problem, skipped);
    ASSERT_TRUE(found) << problem;
    EXPECT_EQ(*found, x8);
    EXPECT_EQ(skipped.size(), 1u);
    skipped.clear();
    EXPECT_EQ(ngi::networkForRestore(a, "", dirs, warning, skipped), x8);
    EXPECT_EQ(skipped.size(), 1u);
    skipped.clear();
    std::string why;
    const std::optional<ngi::NetworkWeights> byDefault = ngi::defaultRestoreNetwork(a, dirs, why, skipped);
    ASSERT_TRUE(byDefault) << why;
    EXPECT_EQ(*byDefault, x8);
    EXPECT_EQ(skipped.size(), 1u);
}

TEST_F(NetworkCatalog, SearchPathIsTheExplicitDirectoryElseTheEnvironmentThenBesideTheExecutable)
{
    EXPECT_EQ(ngi::networkSearchPath(dir_), std::vector<fs::path>{dir_});
    ::setenv("NGI_NETWORK_DIR", dir_.c_str(), 1);
    const std::vector<fs::path> withEnv = ngi::networkSearchPath();
    ::unsetenv("NGI_NETWORK_DIR");
    ASSERT_EQ(withEnv.size(), 3u);
    EXPECT_EQ(withEnv[0], dir_);
    const fs::path bin = fs::read_symlink("/proc/self/exe").parent_path();
    EXPECT_EQ(withEnv[1], (bin / ".." / ".." / "assets").lexically_normal());
    EXPECT_EQ(ngi::networkSearchPath().size(), 2u);
}

}  // namespace
