// libFuzzer target: one mesh reader (readMesh, which only takes a path). Built once per
// format with NGI_FUZZ_MESH_EXTENSION (".obj", ".off", ".ply", ".stl", ".gltf", ".glb"):
// readMesh picks the reader by extension, so each input is written to a temporary file of
// this process with that extension. An ngi::Error is the expected answer to a bad input;
// anything else escaping (std::bad_alloc included: sizes must be checked before allocating)
// is a finding. What reads must keep readMesh's contract: triangles, finite coordinates,
// indices in range. Each input is also read from memory with its appearance (embedded
// images decoded), whose arrays must match the triangles and hold finite values.
#include "ngi/error.h"
#include "ngi/mesh/mesh_io.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <span>
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
            std::filesystem::remove_all(
                std::filesystem::temp_directory_path() / ("ngi-fuzz-" + std::to_string(getpid())), ec);
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

}  // namespace

void checkAppearance(const ngi::TriangleMesh& mesh, const ngi::MeshAppearance& appearance)
{
    const size_t corners = mesh.triangles.size() * 3;
    if (!appearance.cornerUVs.empty() && appearance.cornerUVs.size() != corners)
        invariantFailed("UVs do not cover every corner");
    if (!appearance.cornerColors.empty() && appearance.cornerColors.size() != corners)
        invariantFailed("colours do not cover every corner");
    if (!appearance.triangleMaterial.empty() && appearance.triangleMaterial.size() != mesh.triangles.size())
        invariantFailed("materials do not cover every triangle");
    for (const auto& uv : appearance.cornerUVs)
        if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) invariantFailed("a non-finite UV");
    for (uint32_t m : appearance.triangleMaterial)
        if (m >= appearance.materials.size()) invariantFailed("a material index out of range");
    for (const auto& image : appearance.images)
        if (image.rgba.size() != size_t(image.width) * image.height * 4) invariantFailed("an image of the wrong size");
}

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
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            invariantFailed("readMesh returned a non-finite vertex");
    for (const auto& t : mesh.triangles)
        if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size())
            invariantFailed("readMesh returned a triangle with a vertex out of range");
    ngi::MeshAppearance appearance;
    try {
        const ngi::TriangleMesh withAppearance =
            ngi::readMeshFromMemory(std::span(data, size), NGI_FUZZ_MESH_EXTENSION, "input", appearance);
        if (withAppearance.triangles != mesh.triangles) invariantFailed("the appearance reader read other triangles");
        checkAppearance(withAppearance, appearance);
    } catch (const ngi::Error&) {}
    return 0;
}
