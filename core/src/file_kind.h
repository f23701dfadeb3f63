// ngi core (private): what a file that is not a regular file is, for the messages of the
// input opener (readFileBytes) and the output stager (OutputFiles).
#pragma once

#include <filesystem>
#include <string>

namespace ngi::detail {

// "a directory", "a FIFO", "a character device", ... for `type` ("a special file" for a type
// without a plainer name). Callers write "PATH: is " + fileKindName(type) + ", ...".
inline std::string fileKindName(std::filesystem::file_type type)
{
    using std::filesystem::file_type;
    switch (type) {
    case file_type::regular: return "a regular file";
    case file_type::directory: return "a directory";
    case file_type::symlink: return "a symbolic link";
    case file_type::fifo: return "a FIFO";
    case file_type::character: return "a character device";
    case file_type::block: return "a block device";
    case file_type::socket: return "a socket";
    default: return "a special file";
    }
}

}  // namespace ngi::detail
