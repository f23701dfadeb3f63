// ngi engine: a VkPipelineCache persisted in a file (see pipeline_cache.h). Vulkan spec,
// "Pipeline Cache" (VkPipelineCacheHeaderVersionOne: the header every cache blob starts
// with); FNV-1a: Fowler, Noll, Vo (IETF draft-eastlake-fnv).
#include "ngi/engine/pipeline_cache.h"

#include "ngi/engine/vk_check.h"
#include "ngi/asset.h"
#include "ngi/error.h"
#include "ngi/output_files.h"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <system_error>
#include <vector>

namespace ngi::vk {

namespace {

constexpr char kMagic[8] = {'N', 'G', 'I', 'P', 'C', 'A', 'C', 'H'};
constexpr uint32_t kFormatVersion = 1;

struct FileHeader {
    char magic[8];
    uint32_t formatVersion;
    uint32_t vendorID, deviceID, driverVersion;
    uint8_t uuid[VK_UUID_SIZE];
    uint64_t dataSize;
    uint64_t checksum;
};
static_assert(sizeof(FileHeader) == 56);

uint64_t fnv1a64(const uint8_t* p, size_t n)
{
    uint64_t h = 14695981039346656037ull;
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

FileHeader headerFor(const VkPhysicalDeviceProperties& props)
{
    FileHeader h{};
    std::memcpy(h.magic, kMagic, sizeof kMagic);
    h.formatVersion = kFormatVersion;
    h.vendorID = props.vendorID;
    h.deviceID = props.deviceID;
    h.driverVersion = props.driverVersion;
    std::memcpy(h.uuid, props.pipelineCacheUUID, VK_UUID_SIZE);
    return h;
}

// The reason `bytes` cannot seed this device's cache, or "" (then `data` is its payload).
std::string validate(const std::vector<uint8_t>& bytes, const VkPhysicalDeviceProperties& props,
                     std::vector<uint8_t>& data)
{
    FileHeader h;
    if (bytes.size() < sizeof h) return "truncated header";
    std::memcpy(&h, bytes.data(), sizeof h);
    if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0) return "not an ngi pipeline cache";
    if (h.formatVersion != kFormatVersion) return "format version " + std::to_string(h.formatVersion);
    const FileHeader mine = headerFor(props);
    if (h.vendorID != mine.vendorID || h.deviceID != mine.deviceID || h.driverVersion != mine.driverVersion ||
        std::memcmp(h.uuid, mine.uuid, VK_UUID_SIZE) != 0)
        return "written by another device or driver";
    if (h.dataSize != bytes.size() - sizeof h) return "size mismatch";
    const uint8_t* payload = bytes.data() + sizeof h;
    if (fnv1a64(payload, h.dataSize) != h.checksum) return "checksum mismatch";
    // The driver's own header (VkPipelineCacheHeaderVersionOne) must agree as well.
    if (h.dataSize < 32) return "no Vulkan cache header";
    uint32_t vk[4];
    std::memcpy(vk, payload, sizeof vk);
    if (vk[0] < 32 || vk[0] > h.dataSize || vk[1] != VK_PIPELINE_CACHE_HEADER_VERSION_ONE || vk[2] != props.vendorID ||
        vk[3] != props.deviceID || std::memcmp(payload + 16, props.pipelineCacheUUID, VK_UUID_SIZE) != 0)
        return "Vulkan cache header of another device";
    data.assign(payload, payload + h.dataSize);
    return "";
}

}  // namespace

std::filesystem::path defaultPipelineCachePath(const Context& context)
{
    std::filesystem::path dir;
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
        dir = std::filesystem::path(xdg) / "ngi";
    else if (const char* home = std::getenv("HOME"); home && *home)
        dir = std::filesystem::path(home) / ".cache" / "ngi";
    else
        return {};
    static const char* hex = "0123456789abcdef";
    std::string uuid;
    for (uint8_t b : context.properties.pipelineCacheUUID) uuid += {hex[b >> 4], hex[b & 15]};
    return dir / ("pipelines-" + uuid + "-" + std::to_string(context.properties.driverVersion) + ".bin");
}

PipelineCacheFile::PipelineCacheFile(const Context& context, std::filesystem::path path)
    : context_(context), path_(std::move(path))
{
    std::vector<uint8_t> data;
    if (path_.empty()) {
        reason_ = "no file (in-memory cache)";
    } else {
        std::error_code ec;
        if (!std::filesystem::exists(path_, ec))
            reason_ = "no file";
        else {
            try {
                reason_ = validate(readFileBytes(path_), context.properties, data);
            } catch (const Error& e) {
                reason_ = e.what();  // a FIFO, a directory, unreadable: ignored like a bad file
            }
        }
    }
    VkPipelineCacheCreateInfo info{VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO};
    info.initialDataSize = data.size();
    info.pInitialData = data.empty() ? nullptr : data.data();
    NGI_VK_CHECK(vkCreatePipelineCache(context.device, &info, nullptr, &cache_));
}

PipelineCacheFile::~PipelineCacheFile()
{
    if (cache_) vkDestroyPipelineCache(context_.device, cache_, nullptr);
}

size_t PipelineCacheFile::save() const
{
    if (path_.empty()) return 0;
    size_t size = 0;
    NGI_VK_CHECK(vkGetPipelineCacheData(context_.device, cache_, &size, nullptr));
    std::vector<uint8_t> data(size);
    // VK_INCOMPLETE cannot happen with the size just queried; any error throws.
    NGI_VK_CHECK(vkGetPipelineCacheData(context_.device, cache_, &size, data.data()));
    data.resize(size);
    FileHeader h = headerFor(context_.properties);
    h.dataSize = size;
    h.checksum = fnv1a64(data.data(), size);

    std::error_code ec;
    if (path_.has_parent_path()) std::filesystem::create_directories(path_.parent_path(), ec);
    if (ec) throw Error(path_.string() + ": cannot create the pipeline cache directory (" + ec.message() + ")");
    // Concurrent runs each stage their own temporary file and the last rename wins.
    std::vector<uint8_t> bytes(sizeof h + size);
    std::memcpy(bytes.data(), &h, sizeof h);
    if (size) std::memcpy(bytes.data() + sizeof h, data.data(), size);
    writeFileAtomic(path_, bytes);
    return sizeof h + size;
}

}  // namespace ngi::vk
