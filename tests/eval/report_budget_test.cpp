// `ngi-eval report`'s rate-distortion at byte budgets on a sphere at resolution 64
// with tiny networks x2/x4/x8 in a temporary --networks directory: every budget asset fits its
// budget and is what `ngi-bake --target-bytes` writes (byte for byte, the bake time in META
// aside), the peer fits the budget and its best qp is the smallest CD of qp 10/12/14, a budget
// below the smallest asset is a row saying so, and the SVG and the cross-mesh table exist.
#include "ngi/asset.h"
#include "ngi/eval/report.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/network_weights.h"

#include "run_tool.h"
#include "tiny_network.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& p)
{
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// The cells of the Markdown row starting with `head`, split at '|' (the first is empty).
std::vector<std::string> rowCells(const std::string& page, const std::string& head, size_t from = 0)
{
    const size_t at = page.find("\n" + head, from);
    if (at == std::string::npos) return {};
    const std::string line = page.substr(at + 1, page.find('\n', at + 1) - at - 1);
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, '|')) cells.push_back(cell);
    return cells;
}

double number(const std::string& cell)
{
    std::string digits;
    for (char c : cell)
        if (c != ',' && c != ' ') digits += c;
    return std::stod(digits);
}

struct Chunk {
    std::string name;
    uint32_t chart = 0;
    std::vector<uint8_t> bytes;
};

// The chunks of a serialized asset in file order, their payloads (core's one table reader).
std::vector<Chunk> chunksOf(const std::vector<uint8_t>& file)
{
    std::vector<Chunk> out;
    for (const ngi::AssetChunkSize& c : ngi::assetChunkSizes(file))
        out.push_back({c.name, c.chart, {file.begin() + long(c.offset), file.begin() + long(c.offset + c.bytes)}});
    return out;
}

// The bake's metadata without its wall-clock time (the one field two bakes do not share).
nlohmann::json metadataWithoutTime(const std::vector<uint8_t>& file)
{
    nlohmann::json j = nlohmann::json::parse(ngi::parseAsset(file, "asset").metadataJson);
    if (j.contains("bake")) j["bake"].erase("totalSeconds");
    return j;
}

// A small report of `mesh` (OT only, one stored resolution, few samples) at `budgets`, with
// the networks in dir/networks, written to dir/out.
ngi::ReportOptions smallBudgetReport(const fs::path& dir, const fs::path& mesh, uint32_t resolution,
                                     std::vector<size_t> budgets)
{
    ngi::ReportOptions o;
    o.meshes = {mesh};
    o.outDir = dir / "out";
    o.resolution = resolution;
    o.storedResolutions = {16};
    o.parameterizations = {ngi::ParameterizationMethod::OptimalTransport};
    o.pictureStoredResolution = 16;
    o.sampleCount = 3000;
    o.pictureSize = 32;
    o.budgets = std::move(budgets);
    o.networks = dir / "networks";
    o.command = "test";
    return o;
}

TEST(ReportBudgets, AssetsAreNgiBakesAndThePeerIsTheBestQp)
{
    const fs::path dir = fs::temp_directory_path() /
        ("ngi_report_budgets_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    fs::remove_all(dir);
    fs::create_directories(dir / "networks");
    const fs::path mesh = dir / "sphere.off";
    ngi::writeMesh(mesh, ngi::makeSphere(2));
    for (uint32_t factor : {2u, 4u, 8u})
        ngi::writeNetworkWeights(ngi::test::tinyNetwork(factor, 0.01f),
                                 dir / "networks" / ("tiny-x" + std::to_string(factor) + ".ngiw"));

    const ngi::ReportOptions o = smallBudgetReport(dir, mesh, 64, {100, 1500, 3000});  // 100: below any asset
    const ngi::ReportResult r = ngi::runReport(o);
    const std::string page = slurp(r.reportPath);

    ASSERT_NE(page.find("## Rate-distortion at byte budgets"), std::string::npos);
    EXPECT_TRUE(fs::exists(o.outDir / "plots" / "rd_budget_cd_sphere.svg"));
    EXPECT_NE(slurp(o.outDir / "plots" / "rd_budget_cd_sphere.svg").find("<polyline"), std::string::npos);
    // The cross-mesh table is at the budget nearest 16 KB (3000 here) and counts the win.
    EXPECT_NE(page.find("### All meshes at 3,000 B"), std::string::npos);
    EXPECT_TRUE(std::regex_search(page, std::regex(R"(ngi wins on [01] of 1 meshes at 3,000 B)")));

    const size_t perMesh = page.find("### sphere at every budget");
    ASSERT_NE(perMesh, std::string::npos);
    // Below the smallest asset: a row saying so, the report goes on.
    const std::vector<std::string> below = rowCells(page, "| 100 |", perMesh);
    ASSERT_GE(below.size(), 3u);
    EXPECT_NE(below[2].find("failed ["), std::string::npos);
    EXPECT_NE(page.find("below the smallest asset"), std::string::npos);

    for (size_t budget : {size_t(1500), size_t(3000)}) {
        SCOPED_TRACE(budget);
        const fs::path asset = o.outDir / "assets" / ("sphere.ot.t" + std::to_string(budget) + ".ngi");
        const std::vector<uint8_t> ours = ngi::readFileBytes(asset);
        EXPECT_LE(ours.size(), budget);
        const fs::path cli = dir / ("cli" + std::to_string(budget) + ".ngi");
        const ngi::test::ToolRun run =
            ngi::test::runShell(std::string(NGI_BAKE_EXE) + " " + mesh.string() + " -o " + cli.string() +
                                " --resolution 64 --store-res 64 --quiet --networks " + (dir / "networks").string() +
                                " --target-bytes " + std::to_string(budget));
        ASSERT_EQ(run.exitCode, 0) << run.output;
        const std::vector<uint8_t> theirs = ngi::readFileBytes(cli);
        EXPECT_EQ(ours.size(), theirs.size());
        EXPECT_TRUE(std::equal(ours.begin(), ours.begin() + 16, theirs.begin()));  // magic, version, chunk count
        const std::vector<Chunk> a = chunksOf(ours), b = chunksOf(theirs);
        ASSERT_EQ(a.size(), b.size());
        for (size_t i = 0; i < a.size(); ++i) {
            EXPECT_EQ(a[i].name, b[i].name);
            EXPECT_EQ(a[i].chart, b[i].chart);
            if (a[i].name != "META") {
                EXPECT_TRUE(a[i].bytes == b[i].bytes) << "chunk " << i << " " << a[i].name;
            }
        }
        EXPECT_EQ(metadataWithoutTime(ours), metadataWithoutTime(theirs));
        const ngi::Asset parsed = ngi::parseAsset(ours, asset.string());
        EXPECT_FALSE(parsed.networkId.empty());  // a tiny network restores every level here

        // The row: ngi bytes as on disk, the network named, each qp's CD, the best the smallest.
        const std::vector<std::string> row =
            rowCells(page, "| " + std::string(budget == 1500 ? "1,500" : "3,000") + " |", perMesh);
        ASSERT_EQ(row.size(), 13u) << page;
        EXPECT_EQ(number(row[2]), double(ours.size()));
        EXPECT_NE(row[5].find(parsed.networkId), std::string::npos);
        const double qp10 = number(row[8]), qp12 = number(row[9]), qp14 = number(row[10]);
        const std::string best = row[11];
        const int bestQp = std::stoi(best);
        const double bestCd = std::stod(row[12]);
        EXPECT_EQ(bestCd, std::min({qp10, qp12, qp14})) << best;
        EXPECT_EQ(bestCd, bestQp == 10 ? qp10 : bestQp == 12 ? qp12 : qp14);
        std::smatch parts;  // "qp, bytes, triangles"
        ASSERT_TRUE(std::regex_search(best, parts, std::regex(R"(^\s*(\d+), ([\d,]+), ([\d,]+))"))) << best;
        const double peerBytes = number(parts[2]);
        EXPECT_LE(peerBytes, double(budget));
    }
    fs::remove_all(dir);
}

// A component with thin parts splits by default; at a byte budget ngi-bake checks the split
// against one chart per component and keeps the one closer to the input. The report's budget
// rows follow it: each budget asset is ngi-bake's (byte for byte, META's time aside), and the
// "stored" cell gives the chart count where the split was kept.
TEST(ReportBudgets, ThinPartsAreCheckedAgainstOneChartAsNgiBakeDoes)
{
    const fs::path dir = fs::temp_directory_path() /
        ("ngi_report_thin_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
    fs::remove_all(dir);
    fs::create_directories(dir / "networks");  // empty: no network, the rate control alone
    const fs::path mesh = dir / "arms.obj";
    ngi::writeMesh(mesh, ngi::makeTwoArmedBody(3));

    const ngi::ReportOptions o = smallBudgetReport(dir, mesh, 128, {6000});
    const ngi::ReportResult r = ngi::runReport(o);
    const std::string page = slurp(r.reportPath);

    const fs::path asset = o.outDir / "assets" / "arms.ot.t6000.ngi";
    const std::vector<uint8_t> ours = ngi::readFileBytes(asset);
    const fs::path cli = dir / "cli.ngi", json = dir / "cli.json";
    const ngi::test::ToolRun run =
        ngi::test::runShell(std::string(NGI_BAKE_EXE) + " " + mesh.string() + " -o " + cli.string() +
                            " --resolution 128 --quiet --networks " + (dir / "networks").string() +
                            " --target-bytes 6000 --json " + json.string());
    ASSERT_EQ(run.exitCode, 0) << run.output;
    std::ifstream in(json);
    const nlohmann::json summary = nlohmann::json::parse(in);
    ASSERT_TRUE(summary.contains("splitChoice")) << summary.dump();  // the check ran in ngi-bake
    const std::vector<uint8_t> theirs = ngi::readFileBytes(cli);
    ASSERT_EQ(ours.size(), theirs.size());
    const std::vector<Chunk> a = chunksOf(ours), b = chunksOf(theirs);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i].name != "META") {
            EXPECT_TRUE(a[i].bytes == b[i].bytes) << "chunk " << i << " " << a[i].name;
        }
    EXPECT_EQ(metadataWithoutTime(ours), metadataWithoutTime(theirs));

    const size_t charts = ngi::parseAsset(ours, asset.string()).charts.size();
    EXPECT_EQ(charts, summary["chartCount"].get<size_t>());
    const std::vector<std::string> row = rowCells(page, "| 6,000 |", page.find("### arms at every budget"));
    ASSERT_EQ(row.size(), 13u) << page;
    EXPECT_EQ(row[3].find("charts)") != std::string::npos, charts > 1) << row[3];
    fs::remove_all(dir);
}

}  // namespace

namespace {

TEST(ReportBudgetsCli, BadBudgetsAndNetworksAreUsageErrors)
{
    const std::string out = (std::filesystem::temp_directory_path() / "ngi_report_budgets_cli_out").string();
    for (const std::string& options : {std::string("--budgets 4096,0"), std::string("--budgets 4k"),
                                       std::string("--networks /nonexistent/networks")}) {
        const ngi::test::ToolRun run =
            ngi::test::runShell(std::string(NGI_EVAL_EXE) + " report --meshes a.off --out " + out + " " + options);
        EXPECT_EQ(run.exitCode, 2) << options << ": " << run.output;
        EXPECT_NE(run.output.find(options.substr(0, options.find(' '))), std::string::npos) << run.output;
    }
    EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
