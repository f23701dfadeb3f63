// `ngi-eval report`: the report's options and its progress line on stderr (ngi/eval/report.h runs it).
#include "eval_commands.h"

#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/eval/report.h"
#include "ngi/output_files.h"
#include "ngi/param/parameterize.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <unistd.h>

namespace ngi::eval_cli {
namespace {

namespace fs = std::filesystem;

// The items of a comma-separated list, empty items left out.
std::vector<std::string> splitList(const std::string& text)
{
    std::vector<std::string> items;
    size_t start = 0;
    while (start <= text.size()) {
        const size_t end = std::min(text.find(',', start), text.size());
        if (end > start) items.push_back(text.substr(start, end - start));
        start = end + 1;
    }
    return items;
}

// `seconds` as "1h02m" or "3m04s", for the progress line.
std::string duration(double seconds)
{
    char buffer[32];
    const long s = long(seconds + 0.5);
    if (s >= 3600)
        std::snprintf(buffer, sizeof buffer, "%ldh%02ldm", s / 3600, (s / 60) % 60);
    else
        std::snprintf(buffer, sizeof buffer, "%ldm%02lds", s / 60, s % 60);
    return buffer;
}

}  // namespace

int reportCommand(const std::vector<std::string>& arguments, const std::string& commandLine)
{
    ngi::ReportOptions options;
    std::optional<std::string> meshes, out;
    ngi::ArgReader args(arguments);
    while (args.next()) {
        const std::string& a = args.flag();
        if (args.is("--meshes"))
            meshes = args.value();
        else if (args.is("--out"))
            out = args.value();
        else if (args.is("--resolution"))
            options.resolution = uint32_t(ngi::parseIntegerOptionInRange(a, args.value(), 0, 1u << 16));
        else if (args.is("--stored")) {
            options.storedResolutions.clear();
            for (const std::string& item : splitList(args.value()))
                options.storedResolutions.push_back(uint32_t(ngi::parseIntegerOptionInRange(a, item, 0, 1u << 16)));
        } else if (args.is("--params")) {
            options.parameterizations.clear();
            for (const std::string& item : splitList(args.value())) {
                try {
                    options.parameterizations.push_back(ngi::parseParameterizationMethod(item));
                } catch (const ngi::Error& e) {
                    throw UsageError(std::string("--params: ") + e.what());
                }
            }
        } else if (args.is("--jobs"))
            options.jobs = unsigned(ngi::parseIntegerOptionInRange(a, args.value(), 0, 64));
        else if (args.is("--reuse"))
            options.reuse = true;
        else if (args.is("--samples"))
            options.sampleCount = uint32_t(ngi::parseIntegerOptionInRange(a, args.value(), 0, 100000000));
        else if (args.is("--picture-size"))
            options.pictureSize = uint32_t(ngi::parseIntegerOptionInRange(a, args.value(), 0, 2048));
        else if (args.is("--weights"))
            options.networkWeights = args.value();
        else if (args.is("--note"))
            options.resolutionNote = args.value();
        else if (args.is("--budgets")) {
            options.budgets.clear();
            const std::string& list = args.value();
            if (list != "none")
                for (const std::string& item : splitList(list)) {
                    options.budgets.push_back(size_t(ngi::parseIntegerOptionInRange(a, item, 0, uint64_t(1) << 32)));
                    if (options.budgets.back() == 0) throw UsageError("--budgets: a budget must be at least 1 byte");
                }
        } else if (args.is("--networks")) {
            options.networks = args.value();
            if (!fs::is_directory(options.networks))
                throw UsageError("--networks " + options.networks.string() + ": not a directory");
        } else
            throw args.unknown();
    }
    if (!meshes) throw UsageError("report expects --meshes DIR_OR_LIST");
    if (!out) throw UsageError("report expects --out DIR");
    options.meshes = ngi::resolveMeshList(*meshes);
    options.outDir = *out;
    std::vector<fs::path> inputs = options.meshes;
    inputs.push_back(options.networkWeights);
    ngi::refuseOutputEqualToInput({options.outDir}, inputs);  // --out is a directory it fills
    options.command = commandLine;

    const auto start = std::chrono::steady_clock::now();
    const bool tty = isatty(fileno(stderr));
    options.progress = [&](const ngi::ReportProgress& p) {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const double fraction = p.total > 0.0 ? p.done / p.total : 1.0;
        const int width = 30, filled = int(fraction * width + 0.5);
        const std::string bar = std::string(size_t(filled), '#') + std::string(size_t(width - filled), '.');
        const std::string eta = fraction > 0.0 ? duration(elapsed * (1.0 - fraction) / fraction) : "?";
        std::fprintf(stderr, "%s[%s] %3.0f%%  %s elapsed, ETA %s  %-40.40s%s", tty ? "\r" : "", bar.c_str(),
                     fraction * 100.0, duration(elapsed).c_str(), eta.c_str(), p.step.c_str(), tty ? "" : "\n");
        std::fflush(stderr);
    };
    const ngi::ReportResult result = ngi::runReport(options);
    if (tty) std::fputc('\n', stderr);
    for (const std::string& file : result.skippedNetworkFiles)
        std::fprintf(stderr, "ngi-eval: warning: skipped a network file that does not read: %s\n", file.c_str());
    std::printf("wrote %s: %zu meshes, %zu failed bakes, %zu failed measurements, %s\n", result.reportPath.c_str(),
                result.meshCount, result.failedBakes, result.failedMeasurements, duration(result.seconds).c_str());
    return 0;
}

}  // namespace ngi::eval_cli
