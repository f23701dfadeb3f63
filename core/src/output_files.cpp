// All-or-nothing output files: temporary files beside their destinations, renamed at the
// end (ngi/output_files.h). The project's one implementation of temporary file + rename.
#include "ngi/output_files.h"

#include "ngi/error.h"

#include <cerrno>
#include <cstring>
#include <random>
#include <string>

#include <fcntl.h>
#include <unistd.h>

namespace ngi {
namespace {

namespace fs = std::filesystem;

// The path `p` names, for comparison: absolute, symbolic links resolved as far as the path
// exists, "." and ".." removed.
fs::path normalized(const fs::path& p)
{
    std::error_code ec;
    fs::path absolute = fs::absolute(p, ec);
    if (ec) absolute = p;
    fs::path canonical = fs::weakly_canonical(absolute, ec);
    return ec ? absolute.lexically_normal() : canonical;
}

// Whether `a` and `b` name the same file: the same inode when both exist (so a hard link or
// a symbolic link to an input is caught), otherwise the same normalized path.
bool sameFile(const fs::path& a, const fs::path& b)
{
    std::error_code ea, eb;
    if (fs::exists(a, ea) && fs::exists(b, eb)) {
        std::error_code ec;
        return fs::equivalent(a, b, ec);
    }
    return normalized(a) == normalized(b);
}

fs::path directoryOf(const fs::path& file) { return file.has_parent_path() ? file.parent_path() : fs::path("."); }

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

} // namespace

void refuseOutputEqualToInput(const std::vector<fs::path>& outputs, const std::vector<fs::path>& inputs)
{
    for (size_t i = 0; i < outputs.size(); ++i) {
        if (outputs[i].empty()) continue;
        for (const fs::path& input : inputs)
            if (!input.empty() && sameFile(outputs[i], input))
                throw Error(outputs[i].string() + ": this output is the input " + quoted(input) +
                            "; refusing to overwrite an input (choose another output path)");
        for (size_t j = 0; j < i; ++j)
            if (!outputs[j].empty() && sameFile(outputs[i], outputs[j]))
                throw Error(outputs[i].string() + ": this output is also the output " + quoted(outputs[j]) +
                            "; every output needs its own path");
    }
}

OutputFiles::OutputFiles(const std::vector<fs::path>& outputs, const std::vector<fs::path>& inputs)
{
    refuseOutputEqualToInput(outputs, inputs);
    for (const fs::path& output : outputs)
        if (!output.empty()) add(output);
}

OutputFiles::~OutputFiles() { removeTemporaries(); }

OutputFiles::OutputFiles(OutputFiles&& other) noexcept : entries_(std::move(other.entries_)) { other.entries_.clear(); }

OutputFiles& OutputFiles::operator=(OutputFiles&& other) noexcept
{
    if (this != &other) {
        removeTemporaries();
        entries_ = std::move(other.entries_);
        other.entries_.clear();
    }
    return *this;
}

void OutputFiles::add(const fs::path& destination)
{
    if (destination.empty()) throw Error("an output path is empty");
    std::error_code ec;
    const fs::path dir = directoryOf(destination);
    if (!fs::is_directory(dir, ec))
        throw Error(destination.string() + ": cannot create file (the directory " + quoted(dir) + " does not exist)");
    if (fs::is_directory(destination, ec))
        throw Error(destination.string() + ": is a directory; an output must be a file path");
    for (const Entry& e : entries_)
        if (sameFile(e.destination, destination))
            throw Error(destination.string() + ": this output is also the output " + quoted(e.destination) +
                        "; every output needs its own path");
    entries_.push_back({destination, {}});
}

fs::path OutputFiles::stage(const fs::path& destination)
{
    Entry* entry = nullptr;
    for (Entry& e : entries_)
        if (e.destination == destination) entry = &e;
    if (!entry)
        for (Entry& e : entries_)
            if (sameFile(e.destination, destination)) entry = &e;
    if (!entry) throw Error(destination.string() + ": not a declared output of this run (internal error)");
    if (!entry->temporary.empty()) return entry->temporary;

    // Hidden, unique (O_EXCL), in the destination's directory so that the rename is atomic.
    std::random_device random;
    const fs::path dir = directoryOf(destination);
    const std::string stem = destination.stem().string(), extension = destination.extension().string();
    for (int attempt = 0; attempt < 100; ++attempt) {
        const fs::path temporary =
            dir / ("." + stem + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(random()) + extension);
        const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0) {
            ::close(fd);
            entry->temporary = temporary;
            return temporary;
        }
        if (errno != EEXIST)
            throw Error(destination.string() + ": cannot create file (" + std::strerror(errno) + ")");
    }
    throw Error(destination.string() + ": cannot create a unique temporary file beside it");
}

void OutputFiles::write(const fs::path& destination, std::span<const uint8_t> bytes)
{
    const fs::path temporary = stage(destination);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) throw Error(destination.string() + ": cannot create file (" + std::strerror(errno) + ")");
    size_t done = 0;
    int error = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            error = n < 0 ? errno : ENOSPC;
            break;
        }
        done += size_t(n);
    }
    if (!error && ::fsync(fd) != 0) error = errno;
    if (::close(fd) != 0 && !error) error = errno;
    if (error) throw Error(destination.string() + ": write failed (" + std::strerror(error) + ")");
}

void OutputFiles::writeWith(const fs::path& destination, const std::function<void(const fs::path&)>& writer)
{
    const fs::path temporary = stage(destination);
    try {
        writer(temporary);
    } catch (const Error& e) {
        std::string message = e.what();
        const std::string from = temporary.string(), to = destination.string();
        for (size_t at = message.find(from); at != std::string::npos; at = message.find(from, at + to.size()))
            message.replace(at, from.size(), to);
        throw Error(message);
    }
}

void OutputFiles::commit()
{
    // Everything that can fail before the first rename is checked first: nothing is
    // replaced unless the whole run produced every output.
    for (const Entry& e : entries_) {
        if (e.temporary.empty())
            throw Error(e.destination.string() + ": this output was never written (internal error)");
        std::error_code ec;
        if (fs::is_directory(e.destination, ec))
            throw Error(e.destination.string() + ": is a directory; an output must be a file path");
    }
    for (Entry& e : entries_) {
        std::error_code ec;
        fs::rename(e.temporary, e.destination, ec);
        if (ec) throw Error(e.destination.string() + ": cannot replace file (" + ec.message() + ")");
        e.temporary.clear();
    }
    entries_.clear();
}

void OutputFiles::removeTemporaries() noexcept
{
    for (const Entry& e : entries_)
        if (!e.temporary.empty()) {
            std::error_code ec;
            fs::remove(e.temporary, ec);
        }
    entries_.clear();
}

void writeFileAtomic(const fs::path& path, std::span<const uint8_t> bytes)
{
    OutputFiles files({path});
    files.write(path, bytes);
    files.commit();
}

} // namespace ngi
