// libFuzzer target: one mesh reader (readMesh, which only takes a path). Built once per
// format with NGI_FUZZ_MESH_EXTENSION (".obj", ".off", ".ply", ".stl", ".gltf", ".glb"):
// readMesh picks the reader by extension, so each input is written to a temporary file of
// this process with that extension. An ngi::Error is the expected answer to a bad input;
// anything else escaping (std::bad_alloc included: sizes must be checked before allocating)
// is a finding. What reads must keep readMesh's contract: triangles, finite coordinates,
// indices in range.
#include "ngi/error.h"
#include "ngi/mesh/mesh_io.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>

#ifndef NGI_FUZZ_MESH_EXTENSION
#error "NGI_FUZZ_MESH_EXTENSION must name the mesh format, e.g. \".obj\""
#endif

namespace {

// A directory of this process's own, removed at exit (the fuzzer exits through exit()).
const std::filesystem::path& inputPath()
{
    static const std::filesystem::path path = [] {
        const std::filesystem::path dir =
            std::filesystem::temp_directory_path() / ("ngi-fuzz-" + std::to_string(getpid()));
        std::filesystem::create_directories(dir);
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(std::filesystem::temp_directory_path() / ("ngi-fuzz-" + std::to_string(getpid())), ec);
        });
        return dir / (std::string("input") + NGI_FUZZ_MESH_EXTENSION);
    }();
    return path;
}

[[noreturn]] void invariantFailed(const char* what)
{
    std::fprintf(stderr, "ngi fuzz: invariant failed: %s\n", what);
    std::abort();
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::filesystem::path& path = inputPath();
    FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    std::fclose(f);
    ngi::TriangleMesh mesh;
    try {
        mesh = ngi::readMesh(path);
    } catch (const ngi::Error&) {
        return 0;
    }
    if (mesh.triangles.empty()) invariantFailed("readMesh returned a mesh without triangles");
    for (const auto& p : mesh.positions)
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) invariantFailed("readMesh returned a non-finite vertex");
    for (const auto& t : mesh.triangles)
        if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size())
            invariantFailed("readMesh returned a triangle with a vertex out of range");
    return 0;
}
