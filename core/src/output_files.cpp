// All-or-nothing output files: temporary files beside their destinations, renamed at the
// end (ngi/output_files.h). The project's one implementation of temporary file + rename.
#include "ngi/output_files.h"

#include "ngi/error.h"
#include "file_kind.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <mutex>
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

// Interrupted runs leave no temporary file (DESIGN.md "Nothing replaced"): every staged
// temporary file is listed here, by absolute path, from its creation until it is renamed or
// removed; SIGINT, SIGTERM and SIGHUP remove the listed files, then end the process as the
// signal would have. Only what is async-signal-safe runs in the handler: atomic loads and
// unlink(). A signal whose disposition is not the default (a host's handler, SIG_IGN under
// nohup) is left alone.
constexpr size_t kMaxListedTemporaries = 256;
std::atomic<char*> listedTemporaries[kMaxListedTemporaries];

extern "C" void removeTemporariesAndReraise(int signal)
{
    for (std::atomic<char*>& slot : listedTemporaries)
        if (const char* path = slot.load()) ::unlink(path);
    std::signal(signal, SIG_DFL);
    std::raise(signal);
}

void removeTemporariesOnSignals()
{
    static std::once_flag once;
    std::call_once(once, [] {
        for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
            struct sigaction current {};
            if (::sigaction(signal, nullptr, &current) != 0 || current.sa_handler != SIG_DFL) continue;
            struct sigaction action {};
            action.sa_handler = removeTemporariesAndReraise;
            sigemptyset(&action.sa_mask);
            ::sigaction(signal, &action, nullptr);
        }
    });
}

// Lists `temporary` for removal on a signal (silently not, in the unlikely case that more
// than kMaxListedTemporaries files are staged at once).
void listTemporary(const fs::path& temporary)
{
    removeTemporariesOnSignals();
    std::error_code ec;
    const fs::path absolute = fs::absolute(temporary, ec);
    char* copy = ::strdup((ec ? temporary : absolute).c_str());
    if (!copy) return;
    for (std::atomic<char*>& slot : listedTemporaries) {
        char* empty = nullptr;
        if (slot.compare_exchange_strong(empty, copy)) return;
    }
    std::free(copy);
}

void unlistTemporary(const fs::path& temporary) noexcept
{
    std::error_code ec;
    const fs::path absolute = fs::absolute(temporary, ec);
    const std::string path = (ec ? temporary : absolute).string();
    for (std::atomic<char*>& slot : listedTemporaries) {
        char* listed = slot.load();
        if (listed && path == listed && slot.compare_exchange_strong(listed, nullptr)) {
            std::free(listed);
            return;
        }
    }
}

fs::path directoryOf(const fs::path& file) { return file.has_parent_path() ? file.parent_path() : fs::path("."); }

std::string quoted(const fs::path& p) { return "'" + p.string() + "'"; }

// The file a commit replaces for `destination`: the destination itself, or the regular file
// its symbolic link resolves to (the link is kept). Throws ngi::Error naming `destination`
// if it exists and is neither a regular file nor a symbolic link to one: a device, a FIFO or
// a socket is never replaced (and never opened: writing to one could block forever).
fs::path replacedFile(const fs::path& destination)
{
    std::error_code ec;
    const fs::file_status own = fs::symlink_status(destination, ec);
    if (ec || own.type() == fs::file_type::not_found || fs::is_regular_file(own)) return destination;
    if (fs::is_directory(own)) throw Error(destination.string() + ": is a directory; an output must be a file path");
    if (!fs::is_symlink(own))
        throw Error(destination.string() + ": is " + detail::fileKindName(own.type()) +
                    ", not a regular file; refusing to replace it");
    const fs::path target = fs::canonical(destination, ec);
    if (ec)
        throw Error(destination.string() + ": is a symbolic link whose target does not exist; refusing to replace " +
                    "the link (name the target, or remove the link)");
    const fs::file_status pointed = fs::symlink_status(target, ec);
    if (ec || !fs::is_regular_file(pointed))
        throw Error(destination.string() + ": is a symbolic link to " + quoted(target) + ", which is " +
                    (ec ? std::string("unreadable") : detail::fileKindName(pointed.type())) +
                    ", not a regular file; refusing to replace it");
    return target;
}

}  // namespace

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
    if (destination.empty()) throw Error("the output path is empty");
    std::error_code ec;
    const fs::path dir = directoryOf(destination);
    if (!fs::is_directory(dir, ec))
        throw Error(destination.string() + ": cannot create file (the directory " + quoted(dir) + " does not exist)");
    if (fs::is_directory(destination, ec))
        throw Error(destination.string() + ": is a directory; an output must be a file path");
    const fs::path replaced = replacedFile(destination);
    for (const Entry& e : entries_)
        if (sameFile(e.destination, destination) || sameFile(e.replaced, replaced))
            throw Error(destination.string() + ": this output is also the output " + quoted(e.destination) +
                        "; every output needs its own path");
    entries_.push_back({destination, replaced, {}});
}

fs::path OutputFiles::stage(const fs::path& destination)
{
    Entry* entry = nullptr;
    for (Entry& e : entries_)
        if (e.destination == destination) entry = &e;
    if (!entry)
        for (Entry& e : entries_)
            if (sameFile(e.destination, destination)) entry = &e;
    if (destination.empty()) throw Error("the output path is empty");
    if (!entry) throw Error(destination.string() + ": not a declared output of this run (internal error)");
    if (!entry->temporary.empty()) return entry->temporary;

    // Hidden, unique (O_EXCL), in the directory of the file it replaces so that the rename is
    // atomic; with the destination's extension, which chooses the format.
    std::random_device random;
    const fs::path dir = directoryOf(entry->replaced);
    const std::string stem = entry->replaced.stem().string(), extension = destination.extension().string();
    for (int attempt = 0; attempt < 100; ++attempt) {
        const fs::path temporary =
            dir / ("." + stem + ".tmp" + std::to_string(::getpid()) + "_" + std::to_string(random()) + extension);
        // Listed before it exists: a signal right after the file is made must find it listed.
        // (The name holds this process's id: no other live process makes it.)
        listTemporary(temporary);
        const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        const int openError = errno;
        if (fd >= 0) {
            ::close(fd);
            entry->temporary = temporary;
            return temporary;
        }
        unlistTemporary(temporary);
        errno = openError;
        if (errno != EEXIST) throw Error(destination.string() + ": cannot create file (" + std::strerror(errno) + ")");
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
        // What was checked when it was declared, again: the destination may have become a
        // directory, a device, a FIFO or a symbolic link since.
        if (replacedFile(e.destination) != e.replaced)
            throw Error(e.destination.string() + ": changed while this run wrote it (it is now " +
                        "a symbolic link, or links elsewhere); refusing to replace it");
    }
    for (Entry& e : entries_) {
        std::error_code ec;
        fs::rename(e.temporary, e.replaced, ec);
        if (ec) throw Error(e.destination.string() + ": cannot replace file (" + ec.message() + ")");
        unlistTemporary(e.temporary);
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
            unlistTemporary(e.temporary);
        }
    entries_.clear();
}

void writeFileAtomic(const fs::path& path, std::span<const uint8_t> bytes)
{
    OutputFiles files({path});
    files.write(path, bytes);
    files.commit();
}

}  // namespace ngi
