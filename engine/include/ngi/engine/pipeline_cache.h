// ngi engine: a VkPipelineCache kept in a file between runs, so that a tool's second start
// does not compile the compute and graphics pipelines again (Vulkan spec, "Pipeline Cache").
//
// File: a small ngi header (magic, format version, the device's vendorID, deviceID,
// driverVersion and pipelineCacheUUID, the data size and its FNV-1a 64 checksum) followed by
// vkGetPipelineCacheData's bytes. A file that is missing, truncated, corrupt (checksum),
// written by another device or driver, or whose own Vulkan header disagrees is ignored (the
// cache starts empty and reason() says why): drivers are not trusted with foreign bytes.
// save() writes through the one output stager (writeFileAtomic, ngi/output_files.h): a
// temporary file renamed over the target, so a crash or a concurrent run never leaves half a
// file, and a path that is a device or a FIFO is refused, never replaced.
#pragma once

#include "ngi/engine/context.h"

#include <vulkan/vulkan.h>

#include <filesystem>
#include <string>

namespace ngi::vk {

// $XDG_CACHE_HOME/ngi/pipelines-UUID-DRIVERVERSION.bin, else $HOME/.cache/ngi/...; UUID =
// the device's pipelineCacheUUID in hex. Empty when neither variable is set.
std::filesystem::path defaultPipelineCachePath(const Context& context);

class PipelineCacheFile {
public:
    // Creates the cache, seeded from `path` if that file is valid for this device (see the
    // top of this file; never an error). An empty path: an in-memory cache, save() does
    // nothing. ngi::Error only if the driver cannot create a pipeline cache.
    PipelineCacheFile(const Context& context, std::filesystem::path path);
    // Destroys the cache without writing it (call save() first).
    ~PipelineCacheFile();
    PipelineCacheFile(const PipelineCacheFile&) = delete;
    PipelineCacheFile& operator=(const PipelineCacheFile&) = delete;

    VkPipelineCache handle() const { return cache_; }
    const std::filesystem::path& path() const { return path_; }
    // Whether the file's data seeded the cache; reason(): why not ("no file", "checksum
    // mismatch", "written by another device or driver", ...), empty when it did.
    bool loaded() const { return reason_.empty(); }
    const std::string& reason() const { return reason_; }

    // Writes the cache's current data to path() atomically (creating its directory).
    // ngi::Error naming the path on failure. Returns the bytes written (0 for no path).
    size_t save() const;

private:
    const Context& context_;
    std::filesystem::path path_;
    VkPipelineCache cache_ = VK_NULL_HANDLE;
    std::string reason_;
};

}  // namespace ngi::vk
