// PipelineCacheFile: the pipeline cache the tools keep on disk. A valid file seeds the cache;
// corrupt, truncated or foreign files are ignored (never handed to the driver); saves are
// atomic (no temporary left behind); a SuperResolution compiles through it.
#include "vulkan_fixture.h"

#include "ngi/engine/pipeline_cache.h"
#include "ngi/engine/super_resolution.h"
#include "ngi/nn/architecture.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace {

namespace fs = std::filesystem;

class PipelineCache : public VulkanTest {
protected:
    void SetUp() override
    {
        VulkanTest::SetUp();
        dir_ = fs::temp_directory_path() / ("ngi-pipeline-cache-test-" + std::to_string(::getpid()));
        fs::remove_all(dir_);
    }
    void TearDown() override
    {
        fs::remove_all(dir_);
        VulkanTest::TearDown();
    }
    std::vector<char> read(const fs::path& p)
    {
        std::ifstream in(p, std::ios::binary);
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    void write(const fs::path& p, const std::vector<char>& bytes)
    {
        std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
    }
    // A file saved after compiling a small network's pipelines through the cache.
    fs::path savedCache()
    {
        const fs::path p = dir_ / "sub" / "cache.bin";
        ngi::vk::PipelineCacheFile cache(context(), p);
        EXPECT_FALSE(cache.loaded());
        EXPECT_EQ(cache.reason(), "no file");
        ngi::nn::SuperResolutionConfig config;
        config.scaleFactor = 2;
        config.features = 4;
        config.attentionHeads = 1;
        config.resBlocks = 1;
        config.upsampleFeatures = 4;
        const ngi::NetworkWeights net = ngi::nn::buildSuperResolutionNetwork(config, "cache");
        ngi::vk::SuperResolutionOptions options;
        options.pipelineCache = cache.handle();
        ngi::vk::SuperResolution sr(context(), net, options);
        EXPECT_GT(sr.pipelineCount(), 4u);   // every op's pipeline, at construction
        EXPECT_GE(cache.save(), 56u + 32u);  // ngi header + the driver's header at least
        return p;
    }
    fs::path dir_;
};

TEST_F(PipelineCache, ASavedFileSeedsTheNextCacheAtomically)
{
    const fs::path p = savedCache();
    ngi::vk::PipelineCacheFile again(context(), p);
    EXPECT_TRUE(again.loaded()) << again.reason();
    EXPECT_GT(again.save(), 0u);
    size_t files = 0;
    for (const auto& e : fs::directory_iterator(p.parent_path())) files += e.is_regular_file();
    EXPECT_EQ(files, 1u);  // the temporary was renamed over the target
}

TEST_F(PipelineCache, CorruptTruncatedAndForeignFilesAreIgnored)
{
    const fs::path p = savedCache();
    const std::vector<char> good = read(p);
    ASSERT_GE(good.size(), 56u + 32u);
    auto reasonFor = [&](std::vector<char> bytes) {
        write(p, bytes);
        ngi::vk::PipelineCacheFile cache(context(), p);
        EXPECT_NE(cache.handle(), VK_NULL_HANDLE);
        return cache.reason();
    };
    std::vector<char> bad = good;
    bad[bad.size() - 1] ^= 0x5a;
    EXPECT_EQ(reasonFor(bad), "checksum mismatch");
    EXPECT_EQ(reasonFor(std::vector<char>(good.begin(), good.begin() + 20)), "truncated header");
    EXPECT_EQ(reasonFor(std::vector<char>(good.begin(), good.begin() + std::ptrdiff_t(good.size() - 1))),
              "size mismatch");
    bad = good;
    bad[20] ^= 1;  // driverVersion
    EXPECT_EQ(reasonFor(bad), "written by another device or driver");
    bad = good;
    bad[0] = 'X';
    EXPECT_EQ(reasonFor(bad), "not an ngi pipeline cache");
    EXPECT_EQ(reasonFor({}), "truncated header");
    // A file that is still usable after all of this: the next save replaces it.
    ngi::vk::PipelineCacheFile cache(context(), p);
    cache.save();
    EXPECT_TRUE(ngi::vk::PipelineCacheFile(context(), p).loaded());
}

TEST_F(PipelineCache, TheDefaultPathIsKeyedByTheDevice)
{
    const char* old = std::getenv("XDG_CACHE_HOME");
    const std::string saved = old ? old : "";
    ::setenv("XDG_CACHE_HOME", dir_.c_str(), 1);
    const fs::path p = ngi::vk::defaultPipelineCachePath(context());
    if (old)
        ::setenv("XDG_CACHE_HOME", saved.c_str(), 1);
    else
        ::unsetenv("XDG_CACHE_HOME");
    EXPECT_EQ(p.parent_path(), dir_ / "ngi");
    const std::string name = p.filename().string();
    EXPECT_EQ(name.rfind("pipelines-", 0), 0u);
    std::string suffix = "-";
    suffix += std::to_string(context().properties.driverVersion);
    suffix += ".bin";
    EXPECT_NE(name.find(suffix), std::string::npos) << name;
    EXPECT_EQ(name.size(), 10 + 32 + suffix.size()) << name;  // "pipelines-" + 16 bytes in hex
}

}  // namespace
