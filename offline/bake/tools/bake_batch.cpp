// ngi-bake --batch (bake_batch.h): input list, names, resume, child processes, summary, table.
#include "bake_batch.h"

#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/param/detail_density.h"
#include "ngi/param/parameterize.h"

#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace ngi {
namespace {

const char* kBatchUsage =
    "usage: ngi-bake --batch DIR_OR_LIST --out DIR [--jobs N] [--shard I/N] [--timeout SECONDS]\n"
    "                [--resolution 1024] [--store-res 128 | --target-bytes N [--normal-bits B]]\n"
    "                [--param ot|ricci|harmonic|tutte|authalic]\n"
    "                [--remesh-vertices N] [--feature-angle DEG] [--free-seams] [--no-split] [--detail-density S]\n"
    "                [--no-appearance]\n"
    "                [--split-pieces K|auto]\n"
    "                [--networks DIR | --no-network] [--quiet]\n"
    "  DIR_OR_LIST        a directory (every .obj .off .ply .stl .gltf .glb in it, sorted by name)\n"
    "                     or a text file of mesh paths, one per line ('#' comments)\n"
    "  --out DIR          writes DIR/NAME.ngi per input (NAME.EXT.ngi when two inputs share a\n"
    "                     stem) and appends one JSON line per input to DIR/summary.jsonl\n"
    "  --jobs N           bakes N inputs at a time, each in its own process (default 1)\n"
    "  --shard I/N        only every N-th input starting at I (0-based); writes\n"
    "                     DIR/summary.shard-I-of-N.jsonl (merge: concatenate the summaries)\n"
    "  --timeout SECONDS  kills a bake that runs longer (default: none)\n"
    "  --target-bytes N   every asset in at most N bytes (ngi-bake --help); the summary line\n"
    "                     holds the stored resolution and quantization step each bake chose\n"
    "  --networks DIR, --no-network: passed to every bake (ngi-bake --help)\n"
    "  --quiet            no progress lines\n"
    "  Inputs already baked with the same file contents and options are skipped (resume).\n"
    "  Exit status: 0 all baked, 1 some failed, 2 usage error.\n";

using Clock = std::chrono::steady_clock;

struct BatchArguments {
    fs::path source, out;
    uint32_t jobs = 1;
    uint32_t shardIndex = 0, shardCount = 1;
    bool sharded = false;
    double timeoutSeconds = 0.0;  // 0: none
    uint32_t resolution = 1024, storeResolution = 128;
    ParameterizationMethod method = ParameterizationMethod::OptimalTransport;
    uint32_t remeshVertices = 0;  // 0: the bake's default for the resolution
    double featureAngle = 60.0;
    bool quiet = false;
    bool freeSeams = false;
    bool noDetailTransfer = false;
    bool noAppearance = false;
    double detailDensity = 0.0;  // --detail-density (0: the area measure)
    uint32_t splitPieces = 0;    // --split-pieces K (0: none)
    bool splitAuto = false;      // --split-pieces auto
    bool noSplit = false;        // --no-split
    uint64_t targetBytes = 0;    // --target-bytes (0: --store-res decides)
    uint32_t normalBits = 0;     // --normal-bits, with --target-bytes
    bool normalBitsSet = false;
    fs::path networks;       // --networks DIR, passed to every bake ("" = the default search)
    bool noNetwork = false;  // --no-network
};

bool isPowerOfTwo(uint32_t v) { return v != 0 && (v & (v - 1)) == 0; }

BatchArguments parseBatchArguments(int argc, char** argv)
{
    BatchArguments a;
    for (int i = 1; i < argc; ++i)  // before the values: "--batch --help" asks for help
        if (std::strcmp(argv[i], "-h") == 0 || std::strcmp(argv[i], "--help") == 0) throw UsageError("");
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        const std::string& arg = args.flag();
        if (args.is("-h", "--help"))
            throw UsageError("");
        else if (args.is("--batch"))
            a.source = args.value();
        else if (args.is("--out"))
            a.out = args.value();
        else if (args.is("--jobs")) {
            a.jobs = parseUintOption(arg, args.value());
            if (a.jobs == 0 || a.jobs > 256) throw UsageError("--jobs expects a count in [1, 256]");
        } else if (args.is("--shard")) {
            const std::string text = args.value();
            const size_t slash = text.find('/');
            if (slash == std::string::npos) throw UsageError("--shard expects I/N, got '" + text + "'");
            a.shardIndex = parseUintOption(arg, text.substr(0, slash));
            a.shardCount = parseUintOption(arg, text.substr(slash + 1));
            if (a.shardCount == 0 || a.shardIndex >= a.shardCount)
                throw UsageError("--shard expects I/N with 0 <= I < N, got '" + text + "'");
            a.sharded = true;
        } else if (args.is("--timeout")) {
            const std::string text = args.value();
            a.timeoutSeconds = parseFloatOption(arg, text);
            if (!(a.timeoutSeconds > 0.0)) throw UsageError("--timeout expects seconds > 0, got '" + text + "'");
        } else if (args.is("--resolution"))
            a.resolution = parseUintOption(arg, args.value());
        else if (args.is("--store-res"))
            a.storeResolution = parseUintOption(arg, args.value());
        else if (args.is("--target-bytes")) {
            a.targetBytes = parseUintOption(arg, args.value());
            if (a.targetBytes == 0) throw UsageError("--target-bytes expects a positive byte count");
        } else if (args.is("--normal-bits")) {
            a.normalBits = parseUintOption(arg, args.value());
            if (a.normalBits > 16) throw UsageError("--normal-bits expects 0 to 16");
            a.normalBitsSet = true;
        } else if (args.is("--param")) {
            try {
                a.method = parseParameterizationMethod(args.value());
            } catch (const Error& e) {
                throw UsageError(e.what());
            }
        } else if (args.is("--remesh-vertices"))
            a.remeshVertices = parseUintOption(arg, args.value());
        else if (args.is("--feature-angle"))
            a.featureAngle = parseFloatOptionInRange(arg, args.value(), 0.0, 180.0, "degrees");
        else if (args.is("--free-seams"))
            a.freeSeams = true;
        else if (args.is("--no-split"))
            a.noSplit = true;
        else if (args.is("--no-detail-transfer"))
            a.noDetailTransfer = true;
        else if (args.is("--no-appearance"))
            a.noAppearance = true;
        else if (args.is("--detail-density"))
            a.detailDensity = parseFloatOptionInRange(arg, args.value(), 0.0, kMaxDetailDensity, "a strength");
        else if (args.is("--split-pieces")) {
            const std::string pieces = args.value();
            a.splitAuto = pieces == "auto";
            a.splitPieces = a.splitAuto ? 0 : parseUintOption(arg, pieces);
            if (!a.splitAuto && (a.splitPieces < 2 || a.splitPieces > 256))
                throw UsageError("--split-pieces expects 2 to 256 pieces, or auto");
        } else if (args.is("--networks"))
            a.networks = args.value();
        else if (args.is("--no-network"))
            a.noNetwork = true;
        else if (args.is("--quiet"))
            a.quiet = true;
        else if (args.is("-o", "--output") || args.is("--json") || args.is("--export-full") || args.is("--export-mesh"))
            throw UsageError(arg +
                             " is not available with --batch (the outputs are DIR/NAME.ngi and DIR/summary.jsonl)");
        else if (!args.positional())
            throw args.unknown();
        else
            throw UsageError("unexpected argument '" + arg + "' (the inputs come from --batch DIR_OR_LIST)");
    }
    if (a.source.empty()) throw UsageError("--batch expects a directory or a list file");
    if (a.out.empty()) throw UsageError("no output directory (--out DIR)");
    if (a.normalBitsSet && a.targetBytes == 0) throw UsageError("--normal-bits needs --target-bytes");
    if (a.splitAuto && a.targetBytes == 0) throw UsageError("--split-pieces auto needs --target-bytes");
    // The bake would refuse these for every input; one usage error says it once.
    if (!isPowerOfTwo(a.resolution) || a.resolution < 2 || a.resolution > kMaxFullResolution)
        throw UsageError("--resolution " + std::to_string(a.resolution) + " is not a power of two in [2, " +
                         std::to_string(kMaxFullResolution) + "]");
    if (!isPowerOfTwo(a.storeResolution) || a.storeResolution > a.resolution)
        throw UsageError("--store-res " + std::to_string(a.storeResolution) +
                         " is not a power of two in [1, resolution = " + std::to_string(a.resolution) + "]");
    // A mistyped directory would silently name no network: say so before anything is baked.
    if (!a.networks.empty() && !fs::is_directory(a.networks))
        throw UsageError("--networks " + a.networks.string() + ": not a directory");
    return a;
}

// The bake options as ngi-bake arguments, in one canonical spelling: passed to every child
// and, joined, the options fingerprint that decides whether an earlier bake is still valid.
std::vector<std::string> bakeArguments(const BatchArguments& a)
{
    char angle[32];
    std::snprintf(angle, sizeof angle, "%.9g", a.featureAngle);
    std::vector<std::string> args{"--resolution",      std::to_string(a.resolution),
                                  "--store-res",       std::to_string(a.storeResolution),
                                  "--param",           parameterizationName(a.method),
                                  "--remesh-vertices", std::to_string(a.remeshVertices),
                                  "--feature-angle",   angle};
    if (a.freeSeams) args.push_back("--free-seams");
    if (a.noDetailTransfer) args.push_back("--no-detail-transfer");
    if (a.noAppearance) args.push_back("--no-appearance");
    if (a.targetBytes) args.insert(args.end(), {"--target-bytes", std::to_string(a.targetBytes)});
    if (a.normalBitsSet) args.insert(args.end(), {"--normal-bits", std::to_string(a.normalBits)});
    // Only when set: batches baked before the option keep their fingerprint (resume).
    if (a.detailDensity != 0.0) {
        char strength[32];
        std::snprintf(strength, sizeof strength, "%.9g", a.detailDensity);
        args.insert(args.end(), {"--detail-density", strength});
    }
    if (a.splitPieces) args.insert(args.end(), {"--split-pieces", std::to_string(a.splitPieces)});
    if (a.splitAuto) args.insert(args.end(), {"--split-pieces", "auto"});
    if (a.noSplit) args.push_back("--no-split");
    // The network named (and the gain fitted) is part of what a bake makes, so it is part of
    // the fingerprint: the directory as given, made absolute for the children.
    if (a.noNetwork) args.push_back("--no-network");
    if (!a.networks.empty())
        args.insert(args.end(), {"--networks", fs::absolute(a.networks).lexically_normal().string()});
    return args;
}

std::string lower(std::string s)
{
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

bool hasMeshExtension(const fs::path& p)
{
    static const std::set<std::string> kExtensions = {".obj", ".off", ".ply", ".stl", ".gltf", ".glb"};
    return kExtensions.count(lower(p.extension().string())) > 0;
}

// The inputs of DIR_OR_LIST in batch order. Throws UsageError when there is none.
std::vector<fs::path> listInputs(const fs::path& source)
{
    std::vector<fs::path> inputs;
    std::error_code ec;
    if (fs::is_directory(source, ec)) {
        for (const fs::directory_entry& entry : fs::directory_iterator(source, ec))
            if (entry.is_regular_file(ec) && hasMeshExtension(entry.path())) inputs.push_back(entry.path());
        if (ec) throw UsageError(source.string() + ": cannot list the directory: " + ec.message());
        std::sort(inputs.begin(), inputs.end(),
                  [](const fs::path& x, const fs::path& y) { return x.filename().string() < y.filename().string(); });
        if (inputs.empty())
            throw UsageError(source.string() + ": no .obj .off .ply .stl .gltf .glb file in the directory");
    } else {
        std::vector<uint8_t> bytes;
        try {
            bytes = readFileBytes(source);  // a FIFO or a device is refused, never waited on
        } catch (const Error& e) {
            throw UsageError(std::string(e.what()) + " (--batch expects a directory or a list file)");
        }
        std::istringstream in(std::string(bytes.begin(), bytes.end()));
        std::string line;
        while (std::getline(in, line)) {
            const size_t begin = line.find_first_not_of(" \t\r");
            if (begin == std::string::npos || line[begin] == '#') continue;
            const size_t end = line.find_last_not_of(" \t\r");
            inputs.push_back(line.substr(begin, end - begin + 1));
        }
        if (inputs.empty()) throw UsageError(source.string() + ": the list file names no mesh");
    }
    return inputs;
}

// The asset name of each input: STEM.ngi, or FILENAME.ngi for inputs whose stem another
// input shares. Decided over the whole list (before sharding) so every shard agrees.
// Throws UsageError naming both inputs when two still clash (the same file name twice).
std::vector<std::string> assetNames(const std::vector<fs::path>& inputs)
{
    std::map<std::string, int> stems;
    for (const fs::path& p : inputs) ++stems[p.stem().string()];
    std::vector<std::string> names;
    std::map<std::string, size_t> owner;
    for (size_t i = 0; i < inputs.size(); ++i) {
        const std::string stem = inputs[i].stem().string();
        const std::string name = (stems[stem] > 1 ? inputs[i].filename().string() : stem) + ".ngi";
        auto [it, fresh] = owner.emplace(name, i);
        if (!fresh)
            throw UsageError(inputs[it->second].string() + " and " + inputs[i].string() + " would both be baked to " +
                             name + "; list only one, or bake them into different --out directories");
        names.push_back(name);
    }
    return names;
}

std::string hex64(uint64_t v)
{
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
    return text;
}

// The options fingerprint, plus the baker: the FNV-1a 64 of this executable, so that a batch
// resumed by another build of ngi-bake (a fixed bug, a changed map) bakes everything again
// instead of keeping assets another build made.
std::string optionsFingerprint(const BatchArguments& a)
{
    std::string s;
    for (const std::string& part : bakeArguments(a)) s += (s.empty() ? "" : " ") + part;
    std::string baker = "unknown";
    try {
        baker = hex64(fnv1a64(readFileBytes("/proc/self/exe")));
    } catch (const Error&) {
        // No /proc: the options alone decide.
    }
    return s + " --baker " + baker;
}

fs::path summaryPath(const BatchArguments& a)
{
    if (!a.sharded) return a.out / "summary.jsonl";
    return a.out / ("summary.shard-" + std::to_string(a.shardIndex) + "-of-" + std::to_string(a.shardCount) + ".jsonl");
}

// Every "ok" or "skipped" line of every DIR/summary*.jsonl, by asset name. Lines that do not
// parse, and a last line with no newline (a record cut short by a crash or a full disk, even
// one that happens to parse), are ignored: at worst that input is baked again.
std::multimap<std::string, nlohmann::json> previousBakes(const fs::path& out)
{
    std::multimap<std::string, nlohmann::json> done;
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(out, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.rfind("summary", 0) != 0 || entry.path().extension() != ".jsonl") continue;
        std::ifstream in(entry.path());
        std::string line;
        while (std::getline(in, line)) {
            if (in.eof()) break;  // no newline after it: not a whole record
            nlohmann::json j = nlohmann::json::parse(line, nullptr, false);
            if (j.is_discarded() || !j.is_object() || !j.contains("output") || !j.contains("status")) continue;
            if (j["status"] == "ok" || j["status"] == "skipped")
                done.emplace(j["output"].get<std::string>(), std::move(j));
        }
    }
    return done;
}

// Appends one line to the summary with a single write (O_APPEND: lines of concurrent
// batches on one machine never interleave), then flushes it to disk. When the file does not
// end with a newline (a record cut short by a crash or a full disk), the line starts with one,
// so that the cut record stays alone on its line and this one is whole.
void appendLine(const fs::path& path, const std::string& line)
{
    const int fd = ::open(path.c_str(), O_RDWR | O_APPEND | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) throw Error(path.string() + ": cannot open the summary: " + std::strerror(errno));
    char last = '\n';
    if (const off_t size = ::lseek(fd, 0, SEEK_END); size > 0 && ::pread(fd, &last, 1, size - 1) != 1) last = '\n';
    const std::string text = (last == '\n' ? "" : "\n") + line + "\n";
    const ssize_t written = ::write(fd, text.data(), text.size());
    const int saved = errno;
    ::fdatasync(fd);
    ::close(fd);
    if (written != ssize_t(text.size()))
        throw Error(path.string() + ": cannot append to the summary: " + std::strerror(written < 0 ? saved : ENOSPC));
}

std::string readText(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// What a failed child said: its "ngi-bake: error: ..." line, else its last line.
std::string childError(const std::string& stderrText)
{
    std::istringstream lines(stderrText);
    std::string line, last, error;
    const std::string prefix = "ngi-bake: error: ";
    while (std::getline(lines, line)) {
        if (line.rfind(prefix, 0) == 0) error = line.substr(prefix.size());
        if (!line.empty()) last = line;
    }
    return error.empty() ? last : error;
}

std::vector<std::string> childWarnings(const std::string& stderrText)
{
    std::istringstream lines(stderrText);
    std::string line;
    std::vector<std::string> warnings;
    const std::string prefix = "ngi-bake: WARNING: ";
    while (std::getline(lines, line))
        if (line.rfind(prefix, 0) == 0) warnings.push_back(line.substr(prefix.size()));
    return warnings;
}

struct Job {
    size_t index = 0;  // into the shard's inputs
    fs::path input;
    std::string name;  // DIR/name is the asset
    uint64_t inputHash = 0;
    pid_t pid = -1;
    Clock::time_point start;
    fs::path jsonFile, stderrFile;
    bool timedOut = false;
};

struct Outcome {
    std::string status;  // ok, failed, skipped
    std::string error;
    double seconds = 0.0;
    std::string input;
};

class Batch {
public:
    explicit Batch(BatchArguments a) : a_(std::move(a)), fingerprint_(optionsFingerprint(a_)) {}
    Batch(const Batch&) = delete;
    Batch& operator=(const Batch&) = delete;
    // On an error mid-batch (the summary cannot be written): no bake outlives the batch and
    // no scratch file stays behind.
    ~Batch()
    {
        for (const Job& job : running_) {
            ::kill(job.pid, SIGKILL);
            ::waitpid(job.pid, nullptr, 0);
        }
        std::error_code ec;
        if (!scratch_.empty()) fs::remove_all(scratch_, ec);
    }

    int run()
    {
        const std::vector<fs::path> all = listInputs(a_.source);
        const std::vector<std::string> names = assetNames(all);
        for (size_t i = a_.shardIndex; i < all.size(); i += a_.shardCount) {
            inputs_.push_back(all[i]);
            names_.push_back(names[i]);
        }
        std::error_code ec;
        fs::create_directories(a_.out, ec);
        if (!fs::is_directory(a_.out)) throw UsageError(a_.out.string() + ": cannot create the output directory");
        summary_ = summaryPath(a_);
        previous_ = previousBakes(a_.out);
        char scratch[] = "/tmp/ngi-batch-XXXXXX";
        const char* tmp = ::mkdtemp(scratch);
        if (!tmp) throw Error(std::string("cannot create a scratch directory in /tmp: ") + std::strerror(errno));
        scratch_ = tmp;
        tty_ = ::isatty(STDERR_FILENO);
        start_ = Clock::now();

        size_t next = 0;
        std::vector<Job>& running = running_;
        while (next < inputs_.size() || !running.empty()) {
            while (next < inputs_.size() && running.size() < a_.jobs) {
                Job job;
                job.index = next;
                job.input = inputs_[next];
                job.name = names_[next];
                ++next;
                if (!prepare(job)) continue;  // skipped or failed before baking
                spawn(job);
                running.push_back(std::move(job));
            }
            if (running.empty()) continue;
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            for (size_t r = 0; r < running.size();) {
                if (poll(running[r])) {
                    running.erase(running.begin() + long(r));
                } else {
                    ++r;
                }
            }
        }
        fs::remove_all(scratch_, ec);
        scratch_.clear();
        if (tty_ && !a_.quiet) std::fputs("\n", stderr);
        printTable();
        for (const Outcome& o : outcomes_)
            if (o.status == "failed") return 1;
        return 0;
    }

private:
    // Hashes the input and skips it when its asset is up to date. Returns true when it
    // must be baked; otherwise records the outcome.
    bool prepare(Job& job)
    {
        const auto start = Clock::now();
        std::vector<uint8_t> bytes;
        try {
            bytes = readFileBytes(job.input);
        } catch (const std::exception& e) {
            finish(job, "failed", e.what(), seconds(start), nullptr);
            return false;
        }
        job.inputHash = fnv1a64(bytes);
        const fs::path asset = a_.out / job.name;
        auto [begin, end] = previous_.equal_range(job.name);
        if (begin == end || !fs::exists(asset)) return true;
        std::vector<uint8_t> assetBytes;
        uint64_t assetSourceHash = 0;
        try {
            assetBytes = readFileBytes(asset);
            assetSourceHash = parseAsset(assetBytes, asset.string()).sourceHash;
        } catch (const std::exception&) {
            return true;  // unreadable or corrupt: bake it again
        }
        if (assetSourceHash != job.inputHash) return true;
        const std::string inputHash = hex64(job.inputHash), assetHash = hex64(fnv1a64(assetBytes));
        for (auto it = begin; it != end; ++it) {
            const nlohmann::json& j = it->second;
            if (j.value("inputHash", "") == inputHash && j.value("options", "") == fingerprint_ &&
                j.value("assetHash", "") == assetHash) {
                finish(job, "skipped", "", seconds(start), &j);
                return false;
            }
        }
        return true;
    }

    // fork + exec of this binary as a one-mesh ngi-bake, stdout to /dev/null, stderr and
    // the JSON report to scratch files.
    void spawn(Job& job)
    {
        job.jsonFile = scratch_ / (std::to_string(job.index) + ".json");
        job.stderrFile = scratch_ / (std::to_string(job.index) + ".err");
        std::string input = job.input.string();
        if (!input.empty() && input[0] == '-') input = "./" + input;  // not an option
        std::vector<std::string> args = {
            "ngi-bake", input, "-o", (a_.out / job.name).string(), "--json", job.jsonFile.string(), "--quiet"};
        for (const std::string& s : bakeArguments(a_)) args.push_back(s);
        std::vector<char*> argv;
        for (std::string& s : args) argv.push_back(s.data());
        argv.push_back(nullptr);
        std::fflush(stdout);
        std::fflush(stderr);
        job.start = Clock::now();
        const pid_t parent = ::getpid();
        const pid_t pid = ::fork();
        if (pid < 0) throw Error(std::string("cannot start a bake process: ") + std::strerror(errno));
        if (pid == 0) {
            // The child: dies with the batch (SIGTERM, so that it removes its staged files
            // first: ngi/output_files.h), writes nothing to the batch's terminal.
            ::prctl(PR_SET_PDEATHSIG, SIGTERM);
            if (::getppid() != parent) ::_exit(127);
            const int null = ::open("/dev/null", O_WRONLY);
            const int err = ::open(job.stderrFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
            if (null < 0 || err < 0) ::_exit(127);
            ::dup2(null, STDOUT_FILENO);
            ::dup2(err, STDERR_FILENO);
            ::execv("/proc/self/exe", argv.data());
            const char* message = "ngi-bake: error: cannot run /proc/self/exe\n";
            (void)!::write(STDERR_FILENO, message, std::strlen(message));
            ::_exit(127);
        }
        job.pid = pid;
    }

    // Checks one running child: true (and the outcome recorded) when it has ended.
    bool poll(Job& job)
    {
        int status = 0;
        const pid_t r = ::waitpid(job.pid, &status, WNOHANG);
        if (r == 0) {
            if (a_.timeoutSeconds > 0.0 && !job.timedOut && seconds(job.start) > a_.timeoutSeconds) {
                ::kill(job.pid, SIGKILL);
                job.timedOut = true;
            }
            return false;
        }
        const double elapsed = seconds(job.start);
        const std::string errText = readText(job.stderrFile);
        std::error_code ec;
        if (r < 0) {
            finish(job, "failed", std::string("lost the bake process: ") + std::strerror(errno), elapsed, nullptr);
        } else if (job.timedOut || (WIFSIGNALED(status) && WTERMSIG(status) != 0)) {
            // A killed bake never ran OutputFiles' cleanup: remove its temporary asset
            // (".STEM.tmpPID_*" beside DIR/NAME.ngi, ngi/output_files.h).
            const std::string prefix =
                "." + fs::path(job.name).stem().string() + ".tmp" + std::to_string(job.pid) + "_";
            for (const fs::directory_entry& e : fs::directory_iterator(a_.out, ec))
                if (e.path().filename().string().rfind(prefix, 0) == 0) fs::remove(e.path(), ec);
            char text[96];
            if (job.timedOut)
                std::snprintf(text, sizeof text, "timed out after %g s (--timeout)", a_.timeoutSeconds);
            else
                std::snprintf(text, sizeof text, "the bake crashed: signal %d (%s)", WTERMSIG(status),
                              strsignal(WTERMSIG(status)));
            finish(job, "failed", text, elapsed, nullptr);
        } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
            nlohmann::json report = nlohmann::json::parse(readText(job.jsonFile), nullptr, false);
            std::vector<uint8_t> assetBytes;
            try {
                assetBytes = readFileBytes(a_.out / job.name);
            } catch (const std::exception& e) {
                finish(job, "failed", e.what(), elapsed, nullptr);
                return true;
            }
            nlohmann::json fields;
            fields["assetBytes"] = assetBytes.size();
            fields["assetHash"] = hex64(fnv1a64(assetBytes));
            if (report.is_object()) {
                fields["chartCount"] = report.value("chartCount", 0);
                if (report.contains("parameterization"))
                    fields["areaDistortionMean"] = report["parameterization"].value("areaDistortionMean", 0.0);
                // Where the time went (wall seconds per stage, summed over charts).
                if (report.contains("seconds") && report["seconds"].is_object())
                    fields["stageSeconds"] = report["seconds"];
                // What the rate control chose (--target-bytes): the level, the step and its distance to the input.
                if (report.contains("storeResolution")) fields["storeResolution"] = report["storeResolution"];
                if (report.contains("rateControl") && report["rateControl"].is_object())
                    for (const char* key : {"targetBytes", "positionStep", "tangentScale", "stepGrade", "rmsToInput"})
                        if (report["rateControl"].contains(key))
                            fields["rateControl"][key] = report["rateControl"][key];
            }
            fields["warnings"] = childWarnings(errText);
            finish(job, "ok", "", elapsed, &fields);
        } else {
            std::string error = childError(errText);
            if (error.empty()) error = "the bake exited with status " + std::to_string(WEXITSTATUS(status));
            finish(job, "failed", error, elapsed, nullptr);
        }
        fs::remove(job.jsonFile, ec);
        fs::remove(job.stderrFile, ec);
        return true;
    }

    // Records one input's outcome: a summary line, a progress line.
    void finish(const Job& job, const std::string& status, const std::string& error, double secs,
                const nlohmann::json* fields)
    {
        nlohmann::json line;
        line["input"] = job.input.string();
        line["output"] = job.name;
        line["status"] = status;
        line["error"] = error;
        line["seconds"] = secs;
        line["assetBytes"] = 0;
        line["chartCount"] = 0;
        line["areaDistortionMean"] = nullptr;
        line["stageSeconds"] = nullptr;
        if (fields)  // a bake's results, or for a skip those of the bake it keeps
            for (const char* key : {"assetBytes", "assetHash", "chartCount", "areaDistortionMean", "stageSeconds",
                                    "warnings", "storeResolution", "rateControl"})
                if (fields->contains(key)) line[key] = (*fields)[key];
        line["inputHash"] = job.inputHash ? hex64(job.inputHash) : "";
        line["options"] = fingerprint_;
        appendLine(summary_, line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
        outcomes_.push_back({status, error, secs, job.input.string()});
        if (status == "ok") bakedSeconds_ += secs, ++baked_;
        progress(job, status, secs);
    }

    void progress(const Job& job, const std::string& status, double secs)
    {
        if (a_.quiet) return;
        const size_t done = outcomes_.size(), total = inputs_.size();
        std::string eta = "--:--";
        if (baked_ > 0) {
            // The mean bake time of this run, shared by the jobs; skips cost nothing.
            const double left = bakedSeconds_ / double(baked_) * double(total - done) / double(a_.jobs);
            char text[32];
            std::snprintf(text, sizeof text, "%d:%02d", int(left) / 60, int(left) % 60);
            eta = text;
        }
        const int width = 20, filled = int(double(width) * double(done) / double(std::max<size_t>(total, 1)));
        const std::string bar = std::string(size_t(filled), '#') + std::string(size_t(width - filled), '.');
        if (tty_) {
            std::fprintf(stderr, "\r\033[K[%s] %zu/%zu  ETA %s  %s %s (%.1f s)", bar.c_str(), done, total, eta.c_str(),
                         status.c_str(), job.input.filename().string().c_str(), secs);
            if (status == "failed") std::fprintf(stderr, "\n");  // keep failures on screen
        } else {
            std::fprintf(stderr, "ngi-bake: [%zu/%zu] %-7s %s (%.2f s) ETA %s\n", done, total, status.c_str(),
                         job.input.string().c_str(), secs, eta.c_str());
        }
        std::fflush(stderr);
    }

    void printTable() const
    {
        size_t ok = 0, failed = 0, skipped = 0;
        std::vector<double> times;
        for (const Outcome& o : outcomes_) {
            if (o.status == "ok")
                ++ok, times.push_back(o.seconds);
            else if (o.status == "failed")
                ++failed;
            else
                ++skipped;
        }
        std::printf("ngi-bake batch: %zu input%s", outcomes_.size(), outcomes_.size() == 1 ? "" : "s");
        if (a_.sharded) std::printf(" (shard %u/%u)", a_.shardIndex, a_.shardCount);
        std::printf(" in %.1f s, summary %s\n", seconds(start_), summary_.string().c_str());
        std::printf("  %-8s %6s\n  %-8s %6zu\n  %-8s %6zu\n  %-8s %6zu\n", "status", "count", "ok", ok, "failed",
                    failed, "skipped", skipped);
        if (!times.empty()) {
            std::sort(times.begin(), times.end());
            const size_t n = times.size();
            const double median = n % 2 ? times[n / 2] : 0.5 * (times[n / 2 - 1] + times[n / 2]);
            std::printf("  seconds per bake (%zu baked): min %.2f  median %.2f  max %.2f\n", n, times.front(), median,
                        times.back());
        }
        if (failed) {
            std::printf("  failures:\n");
            for (const Outcome& o : outcomes_)
                if (o.status == "failed") {
                    // Most messages already start with the input's path; do not say it twice.
                    if (o.error.rfind(o.input + ":", 0) == 0)
                        std::printf("    %s\n", o.error.c_str());
                    else
                        std::printf("    %s: %s\n", o.input.c_str(), o.error.c_str());
                }
        }
        std::fflush(stdout);
    }

    static double seconds(Clock::time_point since)
    {
        return std::chrono::duration<double>(Clock::now() - since).count();
    }

    BatchArguments a_;
    std::string fingerprint_;
    std::vector<fs::path> inputs_;
    std::vector<std::string> names_;
    fs::path summary_, scratch_;
    std::multimap<std::string, nlohmann::json> previous_;
    std::vector<Job> running_;
    std::vector<Outcome> outcomes_;
    double bakedSeconds_ = 0.0;
    size_t baked_ = 0;
    bool tty_ = false;
    Clock::time_point start_;
};

}  // namespace

bool isBatchCommand(int argc, char** argv)
{
    for (int i = 1; i < argc; ++i)
        if (std::strcmp(argv[i], "--batch") == 0) return true;
    return false;
}

int runBatch(int argc, char** argv)
{
    try {
        BatchArguments a = parseBatchArguments(argc, argv);
        return Batch(std::move(a)).run();
    } catch (const UsageError& e) {
        if (*e.what()) std::fprintf(stderr, "ngi-bake: %s\n", e.what());
        std::fputs(kBatchUsage, *e.what() ? stderr : stdout);
        return *e.what() ? 2 : 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-bake: error: %s\n", e.what());
        return 1;
    }
}

}  // namespace ngi
