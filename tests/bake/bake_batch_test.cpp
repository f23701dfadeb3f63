// ngi-bake --batch (offline/bake/tools/bake_batch.h): continues past a bad file, records every
// input in summary.jsonl, resumes without rewriting done assets, shards cover the inputs once,
// --jobs 2 gives what --jobs 1 gives, stem clashes get distinct names, --timeout kills.
#include "ngi/asset.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/mesh/procedural_meshes.h"
#include "ngi/network_weights.h"

#include "../support/tiny_network.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const std::string kFast = " --resolution 32 --store-res 8 --remesh-vertices 600";

class BakeBatch : public ::testing::Test {
protected:
    void SetUp() override
    {
        dir_ = fs::temp_directory_path() /
            ("ngi_bake_batch_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_ / "in");
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path in(const std::string& name) const { return dir_ / "in" / name; }
    fs::path out(const std::string& name = "out") const { return dir_ / name; }

    // Two good meshes and one file that is not a mesh, plus a file the batch ignores.
    void writeInputs() const
    {
        ngi::writeMesh(in("sphere.off"), ngi::makeSphere(2));
        ngi::writeMesh(in("torus.obj"), ngi::makeTorus(16, 8));
        std::ofstream(in("broken.off")) << "OFF\nthis is not a count\n";
        std::ofstream(in("notes.txt")) << "not an input\n";
    }

    // Runs ngi-bake with `arguments`; returns the exit code, stdout in `output`.
    int run(const std::string& arguments, std::string& output, const std::string& prefix = "") const
    {
        const fs::path outFile = dir_ / "stdout.txt";
        std::string command = prefix + "'";  // appended piece by piece: GCC 12 warns (-Wrestrict) on one long + chain
        command += NGI_BAKE_EXE;
        command += "' " + arguments;
        command += " > '" + outFile.string() + "'";
        command += " 2>> '" + (dir_ / "stderr.txt").string() + "'";
        const int status = std::system(command.c_str());
        std::ifstream file(outFile);
        std::stringstream text;
        text << file.rdbuf();
        output = text.str();
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    int batch(const std::string& arguments, std::string& output) const
    {
        return run("--batch '" + (dir_ / "in").string() + "' " + arguments + kFast, output);
    }

    // Every line of a summary file, parsed.
    static std::vector<nlohmann::json> summary(const fs::path& path)
    {
        std::vector<nlohmann::json> lines;
        std::ifstream file(path);
        std::string line;
        while (std::getline(file, line)) lines.push_back(nlohmann::json::parse(line));
        return lines;
    }
    // Status by input file name.
    static std::map<std::string, std::string> statusByInput(const std::vector<nlohmann::json>& lines)
    {
        std::map<std::string, std::string> status;
        for (const nlohmann::json& j : lines)
            status[fs::path(j["input"].get<std::string>()).filename().string()] = j["status"];
        return status;
    }
    static std::vector<uint8_t> bytes(const fs::path& path) { return ngi::readFileBytes(path); }

    fs::path dir_;
};

TEST_F(BakeBatch, ContinuesPastABadFileAndResumesWithoutRewriting)
{
    writeInputs();
    std::string table;
    EXPECT_EQ(batch("--out '" + out().string() + "'", table), 1) << table;
    std::vector<nlohmann::json> lines = summary(out() / "summary.jsonl");
    ASSERT_EQ(lines.size(), 3u);  // notes.txt is not a mesh file
    const std::map<std::string, std::string> expected = {
        {"broken.off", "failed"}, {"sphere.off", "ok"}, {"torus.obj", "ok"}};
    EXPECT_EQ(statusByInput(lines), expected);
    for (const nlohmann::json& j : lines) {
        const std::string input = j["input"];
        if (j["status"] == "failed") {
            EXPECT_NE(j["error"].get<std::string>().find("broken.off"), std::string::npos) << j.dump();
            EXPECT_FALSE(fs::exists(out() / "broken.ngi"));
            continue;
        }
        const fs::path asset = out() / j["output"].get<std::string>();
        ASSERT_TRUE(fs::exists(asset)) << asset;
        EXPECT_EQ(j["assetBytes"].get<uintmax_t>(), fs::file_size(asset));
        EXPECT_EQ(j["chartCount"].get<int>(), 1);
        EXPECT_GT(j["areaDistortionMean"].get<double>(), 0.0);
        EXPECT_GT(j["seconds"].get<double>(), 0.0);
        ASSERT_TRUE(j["stageSeconds"].is_object()) << j.dump();  // where the time went
        EXPECT_GT(j["stageSeconds"].value("parameterize", -1.0), 0.0) << j.dump();
        char hash[17];
        std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(ngi::fnv1a64(bytes(input))));
        EXPECT_EQ(j["inputHash"].get<std::string>(), hash);
        EXPECT_EQ(ngi::readAsset(asset).sourceHash, ngi::fnv1a64(bytes(input)));
    }
    // The table names the failure and counts every status.
    EXPECT_NE(table.find("broken.off"), std::string::npos) << table;
    EXPECT_NE(table.find("ok            2"), std::string::npos) << table;
    EXPECT_NE(table.find("failed        1"), std::string::npos) << table;
    EXPECT_NE(table.find("median"), std::string::npos) << table;

    // Resume: the two done inputs are skipped, their assets untouched; the bad file fails again.
    const auto sphereTime = fs::last_write_time(out() / "sphere.ngi"),
               torusTime = fs::last_write_time(out() / "torus.ngi");
    const std::vector<uint8_t> sphereBytes = bytes(out() / "sphere.ngi"), torusBytes = bytes(out() / "torus.ngi");
    EXPECT_EQ(batch("--out '" + out().string() + "'", table), 1) << table;
    lines = summary(out() / "summary.jsonl");
    ASSERT_EQ(lines.size(), 6u);
    const std::map<std::string, std::string> resumed = {
        {"broken.off", "failed"}, {"sphere.off", "skipped"}, {"torus.obj", "skipped"}};
    EXPECT_EQ(statusByInput({lines.begin() + 3, lines.end()}), resumed);
    EXPECT_EQ(fs::last_write_time(out() / "sphere.ngi"), sphereTime);
    EXPECT_EQ(fs::last_write_time(out() / "torus.ngi"), torusTime);
    EXPECT_EQ(bytes(out() / "sphere.ngi"), sphereBytes);
    EXPECT_EQ(bytes(out() / "torus.ngi"), torusBytes);
    EXPECT_NE(table.find("skipped       2"), std::string::npos) << table;

    // A changed input or changed options bake again.
    ngi::writeMesh(in("sphere.off"), ngi::makeSphere(1));
    EXPECT_EQ(batch("--out '" + out().string() + "'", table), 1) << table;
    lines = summary(out() / "summary.jsonl");
    ASSERT_EQ(lines.size(), 9u);
    const std::map<std::string, std::string> changed = {
        {"broken.off", "failed"}, {"sphere.off", "ok"}, {"torus.obj", "skipped"}};
    EXPECT_EQ(statusByInput({lines.begin() + 6, lines.end()}), changed);
    EXPECT_EQ(run("--batch '" + (dir_ / "in").string() + "' --out '" + out().string() +
                      "' --resolution 32 --store-res 8 --remesh-vertices 700",
                  table),
              1);
    lines = summary(out() / "summary.jsonl");
    ASSERT_EQ(lines.size(), 12u);
    const std::map<std::string, std::string> options = {
        {"broken.off", "failed"}, {"sphere.off", "ok"}, {"torus.obj", "ok"}};
    EXPECT_EQ(statusByInput({lines.begin() + 9, lines.end()}), options);
}

// A summary whose last record was cut short (a crash or a full disk mid-write): on resume that
// record does not count, even when what is left happens to parse (its input is baked again),
// and the next record starts on a line of its own instead of being appended to it.
TEST_F(BakeBatch, ACutLastSummaryLineIsIgnoredAndTheNextRecordStartsOnANewLine)
{
    ngi::writeMesh(in("sphere.off"), ngi::makeSphere(2));
    ngi::writeMesh(in("torus.obj"), ngi::makeTorus(16, 8));
    std::string table;
    ASSERT_EQ(batch("--out '" + out().string() + "'", table), 0) << table;
    const fs::path path = out() / "summary.jsonl";
    auto text = [&] {
        std::ifstream file(path, std::ios::binary);
        return std::string((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    };
    auto lines = [&] {
        std::vector<std::string> result;
        std::istringstream all(text());
        for (std::string line; std::getline(all, line);) result.push_back(line);
        return result;
    };
    ASSERT_EQ(lines().size(), 2u);
    ASSERT_NE(lines()[1].find("torus.obj"), std::string::npos);  // inputs in name order

    // Half of the last record is lost: torus is baked again, the cut record stays alone on its
    // line and both new records are whole.
    fs::resize_file(path, text().size() - lines()[1].size() / 2 - 1);
    EXPECT_EQ(batch("--out '" + out().string() + "'", table), 0) << table;
    std::vector<std::string> now = lines();
    ASSERT_EQ(now.size(), 4u) << text();
    EXPECT_FALSE(nlohmann::json::accept(now[1])) << now[1];
    EXPECT_EQ(statusByInput({nlohmann::json::parse(now[2]), nlohmann::json::parse(now[3])}),
              (std::map<std::string, std::string>{{"sphere.off", "skipped"}, {"torus.obj", "ok"}}));

    // Only the newline is lost: the record parses but is not known to be whole, so torus is
    // baked again, and the next record starts on a new line.
    fs::resize_file(path, text().size() - 1);
    EXPECT_EQ(batch("--out '" + out().string() + "'", table), 0) << table;
    now = lines();
    ASSERT_EQ(now.size(), 6u) << text();
    for (size_t i = 2; i < now.size(); ++i) EXPECT_TRUE(nlohmann::json::accept(now[i])) << now[i];
    EXPECT_EQ(statusByInput({nlohmann::json::parse(now[4]), nlohmann::json::parse(now[5])}),
              (std::map<std::string, std::string>{{"sphere.off", "skipped"}, {"torus.obj", "ok"}}));
    EXPECT_EQ(text().back(), '\n');
}

// Another build of ngi-bake (here: the same executable with one byte appended, so its hash
// differs and it still runs) bakes again what this one baked; this one still skips it.
TEST_F(BakeBatch, AnotherBuildOfTheBakerBakesAgainInsteadOfResuming)
{
    ngi::writeMesh(in("sphere.off"), ngi::makeSphere(2));
    const fs::path other = dir_ / "ngi-bake-other";
    fs::copy_file(NGI_BAKE_EXE, other);
    std::ofstream(other, std::ios::binary | std::ios::app) << '\n';
    fs::permissions(other, fs::perms::owner_all);
    std::string table;
    const std::string arguments = "--batch '" + (dir_ / "in").string() + "' --out '" + out().string() + "'" + kFast;
    ASSERT_EQ(run(arguments, table), 0) << table;
    ASSERT_EQ(run(arguments, table), 0) << table;
    const int status = std::system(("'" + other.string() + "' " + arguments + " > /dev/null 2>&1").c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    const std::vector<nlohmann::json> lines = summary(out() / "summary.jsonl");
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0]["status"], "ok");
    EXPECT_EQ(lines[1]["status"], "skipped");
    EXPECT_EQ(lines[2]["status"], "ok") << "the other build resumed the first one's bake";
    EXPECT_NE(lines[2]["options"], lines[0]["options"]);
}

// --networks DIR and --no-network reach every bake (and the fingerprint): the asset names the
// x4 network of DIR, or none.
TEST_F(BakeBatch, PassesTheNetworkOptionsToEveryBake)
{
    ngi::writeMesh(in("sphere.off"), ngi::makeSphere(2));
    fs::create_directories(dir_ / "nets");
    ngi::writeNetworkWeights(ngi::test::tinyNetwork(4, 0.0f), dir_ / "nets" / "x4.ngiw");
    std::string table;
    // kFast stores 8 of 32: x4.
    ASSERT_EQ(batch("--out '" + out("named").string() + "' --networks '" + (dir_ / "nets").string() + "'", table), 0)
        << table;
    EXPECT_EQ(ngi::readAsset(out("named") / "sphere.ngi").networkId, "tiny-x4");
    ASSERT_EQ(
        batch("--out '" + out("none").string() + "' --networks '" + (dir_ / "nets").string() + "' --no-network", table),
        0)
        << table;
    EXPECT_EQ(ngi::readAsset(out("none") / "sphere.ngi").networkId, "");
    const std::vector<nlohmann::json> named = summary(out("named") / "summary.jsonl"),
                                      none = summary(out("none") / "summary.jsonl");
    ASSERT_EQ(named.size(), 1u);
    ASSERT_EQ(none.size(), 1u);
    EXPECT_NE(named[0]["options"].get<std::string>().find("--networks"), std::string::npos) << named[0].dump();
    EXPECT_NE(none[0]["options"].get<std::string>().find("--no-network"), std::string::npos) << none[0].dump();
}

// --detail-density reaches every bake: the fingerprint holds it (absent at 0, so batches baked
// before the option still resume) and the torus's map moves off area preservation as the
// one-mesh bake's does (BakeCli.DetailDensityMovesSamplesAndIsRecorded: 0.040 -> 0.054).
TEST_F(BakeBatch, PassesTheDetailDensityToEveryBake)
{
    ngi::writeMesh(in("torus.obj"), ngi::makeTorus(24, 12));
    std::string table;
    ASSERT_EQ(batch("--out '" + out("area").string() + "'", table), 0) << table;
    ASSERT_EQ(batch("--out '" + out("detail").string() + "' --detail-density 4", table), 0) << table;
    const std::vector<nlohmann::json> area = summary(out("area") / "summary.jsonl"),
                                      detail = summary(out("detail") / "summary.jsonl");
    ASSERT_EQ(area.size(), 1u);
    ASSERT_EQ(detail.size(), 1u);
    EXPECT_EQ(area[0]["options"].get<std::string>().find("--detail-density"), std::string::npos) << area[0].dump();
    EXPECT_NE(detail[0]["options"].get<std::string>().find("--detail-density 4"), std::string::npos)
        << detail[0].dump();
    EXPECT_GT(detail[0]["areaDistortionMean"].get<double>(), 1.2 * area[0]["areaDistortionMean"].get<double>())
        << area[0].dump() << detail[0].dump();
}

// --split-pieces K reaches every bake and its fingerprint (absent when not set): the
// torus bakes as several charts.
TEST_F(BakeBatch, PassesTheSplitToEveryBake)
{
    ngi::writeMesh(in("torus.obj"), ngi::makeTorus(24, 12));
    std::string table;
    ASSERT_EQ(batch("--out '" + out("split").string() + "' --resolution 64 --store-res 16 --split-pieces 3", table), 0)
        << table;
    const std::vector<nlohmann::json> split = summary(out("split") / "summary.jsonl");
    ASSERT_EQ(split.size(), 1u);
    EXPECT_NE(split[0]["options"].get<std::string>().find("--split-pieces 3"), std::string::npos) << split[0].dump();
    EXPECT_GE(split[0]["chartCount"].get<int>(), 3) << split[0].dump();
    EXPECT_EQ(batch("--out '" + out("bad").string() + "' --split-pieces 1", table), 2);
    EXPECT_EQ(batch("--out '" + out("bad").string() + "' --split-pieces auto", table), 2)
        << "auto needs --target-bytes";
}

// --target-bytes reaches every bake: each asset within the budget, the summary
// says what the rate control chose, and the budget is part of the resume fingerprint.
TEST_F(BakeBatch, TargetBytesBoundsEveryAssetAndIsInTheFingerprint)
{
    ngi::writeMesh(in("torus.obj"), ngi::makeTorus(24, 12));
    ngi::writeMesh(in("sphere.off"), ngi::makeSphere(2));
    std::string table;
    ASSERT_EQ(batch("--out '" + out("free").string() + "'", table), 0) << table;
    const std::vector<nlohmann::json> free = summary(out("free") / "summary.jsonl");
    ASSERT_EQ(free.size(), 2u);
    EXPECT_EQ(free[0]["options"].get<std::string>().find("--target-bytes"), std::string::npos) << free[0].dump();
    // 90% of the smaller unconstrained asset: the rate control must give something up.
    const size_t budget =
        size_t(0.9 * double(std::min(free[0]["assetBytes"].get<size_t>(), free[1]["assetBytes"].get<size_t>())));
    const std::string budgeted = "--out '" + out("budget").string() + "' --target-bytes " + std::to_string(budget);
    ASSERT_EQ(batch(budgeted, table), 0) << table;
    const std::vector<nlohmann::json> lines = summary(out("budget") / "summary.jsonl");
    ASSERT_EQ(lines.size(), 2u);
    for (const nlohmann::json& j : lines) {
        SCOPED_TRACE(j.dump());
        EXPECT_EQ(j["status"], "ok");
        EXPECT_LE(j["assetBytes"].get<size_t>(), budget);
        EXPECT_EQ(fs::file_size(out("budget") / j["output"].get<std::string>()), j["assetBytes"].get<size_t>());
        EXPECT_EQ(j["rateControl"]["targetBytes"].get<size_t>(), budget);
        EXPECT_GT(j["rateControl"]["positionStep"].get<uint32_t>(), 0u);
        // Measured against the input: above zero (a coded restore), within 2% of the size.
        EXPECT_GT(j["rateControl"]["rmsToInput"].get<double>(), 0.0);
        EXPECT_LT(j["rateControl"]["rmsToInput"].get<double>(), 0.02);
        EXPECT_GE(j["storeResolution"].get<uint32_t>(), 1u);
        EXPECT_NE(j["options"].get<std::string>().find("--target-bytes " + std::to_string(budget)), std::string::npos);
    }
    // Resume: the same budget skips both; another budget bakes both again.
    ASSERT_EQ(batch(budgeted, table), 0) << table;
    const std::vector<nlohmann::json> again = summary(out("budget") / "summary.jsonl");
    ASSERT_EQ(again.size(), 4u);
    EXPECT_EQ(again[2]["status"], "skipped");
    EXPECT_EQ(again[3]["status"], "skipped");
    ASSERT_EQ(batch("--out '" + out("budget").string() + "' --target-bytes " + std::to_string(budget + 64), table), 0)
        << table;
    const std::vector<nlohmann::json> rebaked = summary(out("budget") / "summary.jsonl");
    ASSERT_EQ(rebaked.size(), 6u);
    EXPECT_EQ(rebaked[4]["status"], "ok");
    EXPECT_EQ(rebaked[5]["status"], "ok");
}

TEST_F(BakeBatch, ShardsCoverEveryInputOnceAndJobsTwoMatchesJobsOne)
{
    writeInputs();
    ngi::writeMesh(in("cylinder.ply"), ngi::makeOpenCylinder(16, 4));
    std::string table;
    EXPECT_EQ(batch("--out '" + out("shards").string() + "' --shard 0/2", table), 1) << table;
    EXPECT_EQ(batch("--out '" + out("shards").string() + "' --shard 1/2", table), 0)
        << table;  // no bad file in shard 1
    std::vector<nlohmann::json> lines = summary(out("shards") / "summary.shard-0-of-2.jsonl");
    const std::vector<nlohmann::json> second = summary(out("shards") / "summary.shard-1-of-2.jsonl");
    EXPECT_EQ(lines.size(), 2u);
    EXPECT_EQ(second.size(), 2u);
    lines.insert(lines.end(), second.begin(), second.end());  // merge: concatenate
    std::map<std::string, int> seen;
    for (const nlohmann::json& j : lines) ++seen[fs::path(j["input"].get<std::string>()).filename().string()];
    const std::map<std::string, int> once = {
        {"broken.off", 1}, {"cylinder.ply", 1}, {"sphere.off", 1}, {"torus.obj", 1}};
    EXPECT_EQ(seen, once);

    EXPECT_EQ(batch("--out '" + out("one").string() + "' --jobs 1", table), 1) << table;
    EXPECT_EQ(batch("--out '" + out("two").string() + "' --jobs 2", table), 1) << table;
    const std::vector<nlohmann::json> one = summary(out("one") / "summary.jsonl"),
                                      two = summary(out("two") / "summary.jsonl");
    EXPECT_EQ(statusByInput(one), statusByInput(two));
    ASSERT_EQ(one.size(), 4u);
    ASSERT_EQ(two.size(), 4u);
    for (const nlohmann::json& j : one) EXPECT_EQ(j["options"], two[0]["options"]);
    // The same geometry (the metadata holds stage timings, so the files differ in bytes).
    for (const char* name : {"sphere.ngi", "torus.ngi", "cylinder.ngi"}) {
        const ngi::Asset reference = ngi::readAsset(out("one") / name);
        for (const char* other : {"two", "shards"}) {
            SCOPED_TRACE(std::string(other) + "/" + name);
            const ngi::Asset asset = ngi::readAsset(out(other) / name);
            EXPECT_EQ(asset.sourceHash, reference.sourceHash);
            EXPECT_EQ(asset.offset, reference.offset);
            EXPECT_EQ(asset.scale, reference.scale);
            ASSERT_EQ(asset.charts.size(), reference.charts.size());
            for (size_t c = 0; c < asset.charts.size(); ++c) {
                EXPECT_EQ(asset.charts[c].positions, reference.charts[c].positions);
                EXPECT_EQ(asset.charts[c].normals, reference.charts[c].normals);
            }
        }
    }
}

TEST_F(BakeBatch, StemClashesGetDistinctNamesAndListFilesWork)
{
    ngi::writeMesh(in("part.off"), ngi::makeSphere(2));
    ngi::writeMesh(in("part.obj"), ngi::makeTorus(16, 8));
    const fs::path list = dir_ / "list.txt";
    std::ofstream(list) << "# two meshes with one stem\n"
                        << in("part.off").string() << "\n\n  " << in("part.obj").string() << "  \n";
    std::string table;
    EXPECT_EQ(run("--batch '" + list.string() + "' --out '" + out().string() + "'" + kFast, table), 0) << table;
    EXPECT_EQ(ngi::readAsset(out() / "part.off.ngi").sourceHash, ngi::fnv1a64(bytes(in("part.off"))));
    EXPECT_EQ(ngi::readAsset(out() / "part.obj.ngi").sourceHash, ngi::fnv1a64(bytes(in("part.obj"))));
    EXPECT_EQ(summary(out() / "summary.jsonl").size(), 2u);

    // The same file name twice cannot get two names: refused before anything is baked.
    std::ofstream(list) << in("part.off").string() << "\n" << in("part.off").string() << "\n";
    EXPECT_EQ(run("--batch '" + list.string() + "' --out '" + out("clash").string() + "'" + kFast, table), 2);
    EXPECT_FALSE(fs::exists(out("clash") / "summary.jsonl"));
}

// A FIFO (which a plain open waits on forever) or a directory as a list entry fails that
// entry naming it, and the batch goes on; as the list itself it is a usage error naming it.
// Under `timeout`, so that a hang fails instead of blocking.
TEST_F(BakeBatch, AFifoOrADirectoryInTheListFailsThatEntryWithoutHanging)
{
    ngi::writeMesh(in("sphere.off"), ngi::makeSphere(2));
    ASSERT_EQ(::mkfifo(in("pipe.off").c_str(), 0600), 0);
    fs::create_directories(in("folder.obj"));
    const fs::path list = dir_ / "list.txt";
    std::ofstream(list) << in("pipe.off").string() << "\n"
                        << in("folder.obj").string() << "\n"
                        << in("sphere.off").string() << "\n";
    std::string table;
    EXPECT_EQ(run("--batch '" + list.string() + "' --out '" + out().string() + "'" + kFast, table, "timeout 300 "), 1)
        << table;
    std::map<std::string, std::string> errors;
    for (const nlohmann::json& j : summary(out() / "summary.jsonl"))
        errors[fs::path(j["input"].get<std::string>()).filename().string()] =
            j["status"].get<std::string>() + ": " + j.value("error", "");
    EXPECT_EQ(errors["pipe.off"], "failed: " + in("pipe.off").string() + ": is a FIFO, not a regular file");
    EXPECT_EQ(errors["folder.obj"], "failed: " + in("folder.obj").string() + ": is a directory, not a regular file");
    EXPECT_EQ(errors["sphere.off"], "ok: ");

    ASSERT_EQ(::mkfifo((dir_ / "list.fifo").c_str(), 0600), 0);
    EXPECT_EQ(run("--batch '" + (dir_ / "list.fifo").string() + "' --out '" + out("fifo").string() + "'" + kFast, table,
                  "timeout 300 "),
              2);
    std::ifstream stderrFile(dir_ / "stderr.txt");
    const std::string stderrText((std::istreambuf_iterator<char>(stderrFile)), std::istreambuf_iterator<char>());
    EXPECT_NE(stderrText.find((dir_ / "list.fifo").string() + ": is a FIFO, not a regular file"), std::string::npos)
        << stderrText;
}

TEST_F(BakeBatch, UsageErrorsExitTwo)
{
    writeInputs();
    std::string table;
    EXPECT_EQ(batch("", table), 2);  // no --out
    EXPECT_EQ(batch("--out '" + out().string() + "' --shard 2/2", table), 2);
    EXPECT_EQ(batch("--out '" + out().string() + "' --jobs 0", table), 2);
    EXPECT_EQ(batch("--out '" + out().string() + "' -o x.ngi", table), 2);
    EXPECT_EQ(run("--batch '" + (dir_ / "missing").string() + "' --out '" + out().string() + "'", table), 2);
    EXPECT_EQ(run("--batch '" + (dir_ / "in").string() + "' --out '" + out().string() + "' --resolution 48", table), 2);
    EXPECT_EQ(batch("--out '" + out().string() + "' --networks '" + (dir_ / "no-such-dir").string() + "'", table), 2);
    EXPECT_EQ(batch("--out '" + out().string() + "' --detail-density -1", table), 2);
    EXPECT_EQ(batch("--out '" + out().string() + "' --detail-density nan", table), 2);
    EXPECT_EQ(batch("--out '" + out().string() + "' --target-bytes 0", table), 2);
    EXPECT_EQ(batch("--out '" + out().string() + "' --normal-bits 4", table), 2);  // needs --target-bytes
    EXPECT_EQ(batch("--out '" + out().string() + "' --target-bytes 4096 --normal-bits 17", table), 2);
    std::ifstream errors(dir_ / "stderr.txt");
    const std::string stderrText((std::istreambuf_iterator<char>(errors)), std::istreambuf_iterator<char>());
    EXPECT_NE(stderrText.find("--networks " + (dir_ / "no-such-dir").string() + ": not a directory"), std::string::npos)
        << stderrText;
    EXPECT_NE(stderrText.find("--detail-density expects a strength in [0, 64], got '-1'"), std::string::npos)
        << stderrText;
    EXPECT_NE(stderrText.find("--normal-bits needs --target-bytes"), std::string::npos) << stderrText;
    EXPECT_FALSE(fs::exists(out() / "summary.jsonl"));
}

// A bake over --timeout is killed, recorded as failed, and leaves no temporary file.
TEST_F(BakeBatch, TimeoutKillsTheBakeAndCleansUp)
{
    ngi::writeMesh(in("torus.obj"), ngi::makeTorus(64, 32));
    std::string table;
    EXPECT_EQ(
        run("--batch '" + (dir_ / "in").string() + "' --out '" + out().string() + "' --resolution 256 --timeout 0.001",
            table),
        1);
    const std::vector<nlohmann::json> lines = summary(out() / "summary.jsonl");
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0]["status"], "failed");
    EXPECT_NE(lines[0]["error"].get<std::string>().find("timed out"), std::string::npos) << lines[0].dump();
    for (const fs::directory_entry& e : fs::directory_iterator(out()))
        EXPECT_EQ(e.path().filename(), "summary.jsonl") << e.path();
}

}  // namespace
