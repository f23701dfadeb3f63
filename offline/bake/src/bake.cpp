// ngi offline: the ngi-bake pipeline, stages 2-8 (see bake.h), run in DESIGN.md's order: repair
// -> connected components (split where asked) -> per chart: remesh -> cut -> flow -> OT ->
// border -> sample -> the handed-over split -> order -> appearance -> store. This
// file holds the repair and the components (stage 2), the public helpers and bakeMesh, which
// calls the stages of bake_split.cpp, bake_chart.cpp and bake_store.cpp (bake_stages.h).
#include "ngi/bake/bake.h"

#include "bake_stages.h"
#include "ngi/mesh/chart_split.h"
#include "ngi/param/sampling_check.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <bit>
#include <fstream>
#include <limits>

namespace ngi {

double undersampledAreaFraction(const TriangleMesh& mesh, const std::vector<glm::dvec2>& uv, double factor)
{
    return mapUndersampledAreaFraction(mesh, uv, factor);  // one definition (sampling_check.h)
}

size_t remeshVertexCountFor(uint32_t resolution)
{
    return std::clamp<size_t>(size_t(resolution) * resolution / 64, 1000, 150000);
}

size_t remeshVertexCountForThinParts(uint32_t resolution)
{
    return std::clamp<size_t>(size_t(resolution) * resolution / 16, 1000, 150000);
}

TriangleMesh geometryImageMesh(const GeometryImage& image)
{
    TriangleMesh mesh;
    const uint32_t n = image.size;
    mesh.positions.reserve(image.texels.size());
    for (const glm::vec3& p : image.texels) mesh.positions.push_back(glm::dvec3(p));
    if (n < 2) return mesh;
    mesh.triangles.reserve(size_t(n - 1) * (n - 1) * 2);
    for (uint32_t y = 0; y + 1 < n; ++y)
        for (uint32_t x = 0; x + 1 < n; ++x) {
            const uint32_t a = y * n + x, b = a + 1, c = a + n + 1, d = a + n;
            mesh.triangles.push_back({a, b, c});
            mesh.triangles.push_back({a, c, d});
        }
    return mesh;
}

size_t peakResidentBytes()
{
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return size_t(std::stoull(line.substr(6))) * 1024;  // "VmHWM:  1234 kB"
    return 0;
}

uint32_t chartResolutionFor(uint32_t resolution, uint32_t storedLevel, double areaFraction)
{
    const double ideal = double(resolution) * std::sqrt(std::clamp(areaFraction, 0.0, 1.0));
    uint32_t r = ideal >= 1.0 ? 1u << uint32_t(std::lround(std::log2(ideal))) : 1u;
    r = std::max({r, kMinChartResolution, 1u << storedLevel});
    return std::min(r, resolution);
}

namespace detail {

double surfaceArea(const TriangleMesh& mesh)
{
    double area = 0.0;
    for (const glm::uvec3& t : mesh.triangles)
        area += 0.5 *
            glm::length(
                    glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]));
    return area;
}

namespace {

// Throws unless BakeOptions::resolution and storeResolution are powers of two with
// 1 <= storeResolution <= resolution, 2 <= resolution <= kMaxFullResolution.
void checkResolutions(const BakeOptions& options)
{
    const std::string& name = options.sourceName;
    if (!std::has_single_bit(options.resolution) || options.resolution < 2 || options.resolution > kMaxFullResolution)
        throw Error(name + ": --resolution " + std::to_string(options.resolution) + " is not a power of two in [2, " +
                    std::to_string(kMaxFullResolution) + "] (the largest image every tool renders)");
    if (!std::has_single_bit(options.storeResolution) || options.storeResolution < 1 ||
        options.storeResolution > options.resolution)
        throw Error(name + ": --store-res " + std::to_string(options.storeResolution) +
                    " is not a power of two in [1, resolution = " + std::to_string(options.resolution) + "]");
}

// Stage 2: repairs the input (cleanMesh: non-manifold edges and vertices split, every component
// with a surface kept), moves it to its bounding box centre (Components::centre) and splits it
// into its connected components, one chart each, each with its area. Records the repair in the report. Throws where there are
// more components than an asset holds charts (kMaxCharts).
Components repairIntoComponents(const TriangleMesh& input, const BakeOptions& options, BakeReport& report)
{
    const std::string& name = options.sourceName;
    CleanResult cleaned = runStage("clean", options, report, [&] { return cleanMesh(input, {.sourceName = name}); });
    report.clean = cleaned.report;
    report.cleaned = analyzeTopology(cleaned.mesh);
    report.warnings = cleaned.report.warnings;
    Components components;
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::dvec3& p : cleaned.mesh.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
    components.centre = 0.5 * (lo + hi);
    for (glm::dvec3& p : cleaned.mesh.positions) p -= components.centre;
    std::vector<TriangleMesh>& parts = components.parts;
    parts = splitComponents(cleaned.mesh);
    if (parts.size() > kMaxCharts)
        throw Error(name + ": the mesh has " + std::to_string(parts.size()) + " connected components, more than the " +
                    std::to_string(kMaxCharts) + " charts an asset holds");
    announce(options, "clean",
             format("%zu vertices, %zu triangles, %zu component%s, genus %ld, %zu boundary loops",
                    report.cleaned.vertices, report.cleaned.faces, parts.size(),
                    parts.size() == 1 ? "" : "s (one chart each)", parts.size() == 1 ? report.cleaned.genus : long(0),
                    report.cleaned.boundaryLoops));
    for (const TriangleMesh& part : parts) components.totalArea += components.areas.emplace_back(surfaceArea(part));
    return components;
}

}  // namespace
}  // namespace detail

BakeResult bakeMesh(const TriangleMesh& input, const BakeOptions& options)
{
    using namespace detail;
    checkResolutions(options);
    const StopwatchClock::time_point bakeStart = StopwatchClock::now();
    BakeResult result;
    result.report.method = parameterizationName(options.method);
    result.report.detailDensity =
        options.method == ParameterizationMethod::OptimalTransport ? options.detailDensity : 0.0;
    const uint32_t storedLevel = uint32_t(std::countr_zero(options.resolution / options.storeResolution));

    // Stage 2: repair, then the connected components (the tool has read the file: stage 1).
    Components components = repairIntoComponents(input, options, result.report);

    // Stages 3-7 per chart. With BakeOptions::splitPieces, components are first split into
    // groups of matched charts; the rest become one chart each (remesh -> cut -> flow -> OT ->
    // sample), except those whose one-chart bake finds thin parts or too high a genus: it hands
    // them over to the split (BakeOptions::splitThinParts), which bakes them after the others.
    BakedCharts baked;
    baked.centre = components.centre;
    if (options.splitPieces > 1) splitEveryComponent(components, storedLevel, options, result, baked);
    std::vector<HandOver> handedOver;
    for (size_t c = 0; c < components.parts.size(); ++c)
        bakeComponentAsOneChart(components, c, storedLevel, options, result, baked, &handedOver);
    splitHandedOver(handedOver, components, storedLevel, options, result, baked);

    // Stage 8: the largest resolution first (split pieces may be smaller than an unsplit
    // component), one normalization for all charts, the nested stored level, the asset.
    orderChartsByResolution(result, baked);
    bakeAppearance(input, options, result, baked);
    storeAsset(storedLevel, options, bakeStart, result, baked);
    return result;
}

}  // namespace ngi
