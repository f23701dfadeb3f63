// ngi core: the files a tool run writes, all or nothing (DESIGN.md "The asset contract":
// every writer writes a temporary file and renames it only when the whole run succeeded; an
// output path equal to an input is refused).
//
// A tool declares its outputs (and its inputs) before the expensive work, so that a bad
// output path fails in milliseconds, not after a bake. Each output is then written to a
// temporary file beside its destination; commit() renames them all at the end. Until then
// no pre-existing file is touched, and a failure (an exception unwinding past the
// transaction) removes every temporary file, and so does SIGINT, SIGTERM or SIGHUP (each
// staged file is removed, then the signal ends the process as it would have; a signal with a
// handler of its own, or ignored, is left alone). Nothing that is not a regular file is ever
// replaced: an output that is a device, a FIFO or a socket is refused when it is declared,
// and a symbolic link is written through to its target, never replaced by a file.
//
// This is the one implementation of "temporary file + rename" in the project:
// writeFileAtomic (one file) and every writer built on it (writeAsset, writePng,
// writeNetworkWeights, writeMesh) go through it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <vector>

namespace ngi {

// Throws ngi::Error if an output is the same file as an input, or two outputs are the same
// file: the same file by std::filesystem::equivalent when both exist (hard links and
// symbolic links included), otherwise the same weakly canonical absolute path. Empty paths
// (an optional output not given) are ignored. The message names both paths.
void refuseOutputEqualToInput(const std::vector<std::filesystem::path>& outputs,
                              const std::vector<std::filesystem::path>& inputs);

// A set of output files written all or nothing. Move-only; the destructor removes the
// temporary files of a transaction that was not committed.
class OutputFiles {
public:
    OutputFiles() = default;
    // Declares `outputs` (empty paths are skipped) and checks them against `inputs` and each
    // other (refuseOutputEqualToInput), then add()s each. Throws ngi::Error naming the path.
    explicit OutputFiles(const std::vector<std::filesystem::path>& outputs,
                         const std::vector<std::filesystem::path>& inputs = {});
    ~OutputFiles();
    OutputFiles(OutputFiles&& other) noexcept;
    OutputFiles& operator=(OutputFiles&& other) noexcept;
    OutputFiles(const OutputFiles&) = delete;
    OutputFiles& operator=(const OutputFiles&) = delete;

    // Declares one more output. Checks now what can be checked without writing: the path is
    // not empty, its directory exists, it is not already declared, and it is either new, a
    // regular file, or a symbolic link to an existing regular file. Throws ngi::Error
    // "PATH: problem" otherwise, e.g. "PATH: is a directory; an output must be a file path",
    // "PATH: is a character device, not a regular file; refusing to replace it" (also for a
    // FIFO, a socket or a block device: they are never opened, so nothing can block on them),
    // "PATH: is a symbolic link whose target does not exist; ...".
    // A symbolic link to a regular file is written through: its target is replaced (the
    // temporary file lives beside the target) and the link itself stays a link.
    void add(const std::filesystem::path& destination);

    // Creates (exclusively, empty) and returns the temporary file for a declared
    // `destination`: a hidden file in the same directory (the link target's, for a symbolic
    // link) whose name ends with the destination's extension, so writers that choose the
    // format by extension (writeMesh) write the same format. Any writer may replace it,
    // atomically or not. Staging the same destination twice returns the same path. Throws
    // ngi::Error if `destination` is empty ("the output path is empty"), was not declared, or
    // the file cannot be created.
    std::filesystem::path stage(const std::filesystem::path& destination);

    // stage(destination), then writes `bytes` to it and flushes them to disk (fsync).
    void write(const std::filesystem::path& destination, std::span<const uint8_t> bytes);

    // stage(destination), then runs `writer` on the temporary path (writeAsset, writePng,
    // writeMesh, ...). An ngi::Error it throws is rethrown with the temporary path replaced
    // by `destination`, so that the message names the file the user asked for.
    void writeWith(const std::filesystem::path& destination,
                   const std::function<void(const std::filesystem::path& temporary)>& writer);

    // Renames every staged file onto its destination (a symbolic link's target), in
    // declaration order. Throws ngi::Error, renaming nothing, if a declared output was never
    // staged (the run did not produce all it promised) or a destination has become something
    // add() refuses (a directory, a device, a FIFO) or a symbolic link since it was declared. A rename that still
    // fails (a full disk cannot make it fail: the bytes are already written) leaves the
    // outputs before it committed and the rest untouched. After commit() the object is empty.
    void commit();

private:
    struct Entry {
        std::filesystem::path destination;  // as declared
        std::filesystem::path replaced;     // what commit() renames onto (a link's target)
        std::filesystem::path temporary;
    };
    void removeTemporaries() noexcept;
    std::vector<Entry> entries_;
};

// Writes `bytes` to `path` all or nothing: a one-file OutputFiles. On any failure the
// destination is untouched and no temporary file is left behind.
void writeFileAtomic(const std::filesystem::path& path, std::span<const uint8_t> bytes);

}  // namespace ngi
