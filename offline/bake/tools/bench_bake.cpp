// ngi-bench-bake: bakes each mesh given on the command line at the default settings and prints
// one table row per mesh: seconds per stage (read, clean, cut search, remesh, cut, parameterize, match seams,
// rasterize, store), total, and the peak resident memory of that bake (the process's
// high-water mark is reset before each mesh through /proc/self/clear_refs).
#include "ngi/bake/bake.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/mesh/mesh_io.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace {

void resetPeakMemory()
{
    std::ofstream clear("/proc/self/clear_refs");
    clear << "5";  // resets VmHWM to the current RSS (Linux >= 4.0)
}

}  // namespace

int main(int argc, char** argv)
{
    uint32_t resolution = 1024;
    std::vector<std::string> meshes;
    try {
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            if (args.is("--resolution"))
                resolution = uint32_t(ngi::parseIntegerOptionInRange(args.flag(), args.value(), 2, 1u << 16));
            else if (args.is("--help", "-h")) {
                std::printf("usage: ngi-bench-bake [--resolution 1024] MESH...\n");
                return 0;
            } else if (args.positional())
                meshes.push_back(args.flag());
            else
                throw args.unknown();
        }
    } catch (const ngi::UsageError& e) {
        std::fprintf(stderr, "ngi-bench-bake: %s\n", e.what());
        return 2;
    }
    if (meshes.empty()) {
        std::fprintf(stderr, "ngi-bench-bake: no meshes given (e.g. data/meshes/bunny00.off)\n");
        return 2;
    }
    const char* stages[] = {"clean",        "cut search",  "remesh",    "cut",
                            "parameterize", "match seams", "rasterize", "store"};
    std::printf("| mesh | vertices in -> remeshed | genus | read s |");
    for (const char* s : stages) std::printf(" %s s |", s);
    std::printf(" total s | peak MiB | charts | OT it (max) | cut paths |\n|---|---|---|---|");
    for (size_t i = 0; i < std::size(stages); ++i) std::printf("---|");
    std::printf("---|---|---|---|---|\n");
    int failures = 0;
    for (const std::string& path : meshes) {
        const std::string name = std::filesystem::path(path).stem().string();
        resetPeakMemory();
        try {
            const auto start = std::chrono::steady_clock::now();
            const ngi::TriangleMesh mesh = ngi::readMesh(path);
            const double readSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            ngi::BakeOptions options;
            options.sourceName = path;
            options.resolution = resolution;
            options.storeResolution = std::min<uint32_t>(128, resolution);
            const ngi::BakeResult result = ngi::bakeMesh(mesh, options);
            const ngi::BakeReport& r = result.report;
            size_t remeshed = 0, cutPaths = 0;
            int otIterations = 0;
            std::set<int> groups;  // the pieces of a split component share its one remesh
            for (const ngi::ChartReport& c : r.charts) {
                if (c.splitGroup < 0 || groups.insert(c.splitGroup).second) remeshed += c.remesh.outputVertices;
                cutPaths += c.cut.extremityPaths;
                otIterations = std::max(otIterations, c.parameterization.otIterations);
            }
            std::printf("| %s | %zu -> %zu | %ld | %.2f |", name.c_str(), r.cleaned.vertices, remeshed,
                        r.charts.size() == 1 ? r.charts[0].cut.genus : r.cleaned.genus, readSeconds);
            for (const char* s : stages) {
                double seconds = 0.0;
                for (const ngi::StageTime& t : r.stages)
                    if (t.stage == s) seconds = t.seconds;
                std::printf(" %.2f |", seconds);
            }
            std::printf(" %.1f | %.0f | %zu | %d | %zu |\n", r.totalSeconds + readSeconds,
                        double(ngi::peakResidentBytes()) / (1024.0 * 1024.0), r.charts.size(), otIterations, cutPaths);
        } catch (const ngi::Error& e) {
            std::printf("| %s | failed: %s |\n", name.c_str(), e.what());
            ++failures;
        }
        std::fflush(stdout);
    }
    return failures ? 1 : 0;
}
