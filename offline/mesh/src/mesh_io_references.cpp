// ngi offline: the files a mesh refers to (glTF buffers and images, OBJ material libraries
// and their textures). A mesh may name only files in its own directory or below it: a
// downloaded model must not make the baker read /etc/passwd or a user's keys into a texture.
#include "mesh_io_internal.h"

#include "ngi/asset.h"
#include "ngi/error.h"

#include <algorithm>
#include <system_error>

namespace ngi::mesh_io {

bool insideDirectory(const std::filesystem::path& directory, const std::filesystem::path& path)
{
    std::error_code ec;
    const std::filesystem::path full = std::filesystem::absolute(path, ec).lexically_normal();
    if (ec) return false;
    const std::filesystem::path relative = full.lexically_relative(directory);
    return !relative.empty() && *relative.begin() != ".." && relative.is_relative();
}

std::filesystem::path meshDirectory(const Input& input)
{
    std::error_code ec;
    std::filesystem::path directory = std::filesystem::absolute(input.directory.value_or("."), ec).lexically_normal();
    if (ec) fail(input, "cannot resolve the directory of the mesh: " + ec.message());
    if (!directory.has_filename() && directory != directory.root_path())
        directory = directory.parent_path();  // "/a/b/" -> "/a/b"
    return directory;
}

std::filesystem::path referencedFile(const Input& input, const std::filesystem::path& base, std::string_view reference,
                                     const std::string& what)
{
    const std::string written(reference);
    if (!input.directory)
        fail(input,
             "cannot read the " + what + " '" + written + "': a mesh read from memory may only use embedded data");
    std::string relative = written;
    std::replace(relative.begin(), relative.end(), '\\', '/');  // written on Windows
    const std::filesystem::path directory = meshDirectory(input);
    std::error_code ec;
    const std::filesystem::path full = (std::filesystem::absolute(base, ec) / relative).lexically_normal();
    const bool drive = relative.size() >= 2 && relative[1] == ':';  // "C:/textures/a.png"
    if (relative.empty() || relative.front() == '/' || drive || ec || !insideDirectory(directory, full))
        fail(input,
             "refusing to read the " + what + " '" + written + "' (" + full.string() +
                 "): it must name a file in the directory of the mesh (" + directory.string() + ") or below it");
    return full;
}

std::vector<uint8_t> readReferencedFile(const Input& input, const std::filesystem::path& path, const std::string& what)
{
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) fail(input, "the " + what + " " + path.string() + " does not exist");
    try {
        return readFileBytes(path);
    } catch (const Error& e) {
        fail(input, "cannot read the " + what + ": " + e.what());
    }
}

}  // namespace ngi::mesh_io
