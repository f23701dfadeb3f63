// ngi offline: the ngi-bake pipeline, stages 2-8 (see bake.h). Paper section 3.1 ("Optimal
// Transport for Geometry Images") and section 3.2 "Input Precondition": remesh, cut, conformal
// start, OT refinement, rasterize into a 16-bit geometry image, keep one mip level.
#include "ngi/bake/bake.h"

#include "ngi/bake/bake_report.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/param/extremity_cut.h"
#include "ngi/param/rasterize.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace ngi {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string format(const char* fmt, auto... args) {
    char buffer[512];
    std::snprintf(buffer, sizeof buffer, fmt, args...);
    return buffer;
}

// Runs one stage: times it, records it, and prefixes errors with the source and stage.
template <typename Function>
auto runStage(const char* stage, const BakeOptions& options, BakeReport& report, Function&& function) {
    const Clock::time_point start = Clock::now();
    try {
        auto result = function();
        report.stages.push_back({stage, secondsSince(start)});
        return result;
    } catch (const Error& e) {
        const std::string message = e.what();
        if (message.rfind(options.sourceName + ":", 0) == 0) throw;  // already names the file
        throw Error(options.sourceName + ": " + stage + ": " + message);
    }
}

void announce(const BakeOptions& options, const BakeReport& report, const std::string& summary) {
    if (options.stageDone) options.stageDone(report.stages.back().stage, report.stages.back().seconds, summary);
}

} // namespace

double undersampledAreaFraction(const TriangleMesh& mesh, const std::vector<glm::dvec2>& uv, double factor) {
    double total3d = 0.0, totalUv = 0.0;
    std::vector<double> a3(mesh.triangles.size()), a2(mesh.triangles.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const glm::uvec3 f = mesh.triangles[t];
        a3[t] = 0.5 * glm::length(glm::cross(mesh.positions[f.y] - mesh.positions[f.x], mesh.positions[f.z] - mesh.positions[f.x]));
        const glm::dvec2 e1 = uv[f.y] - uv[f.x], e2 = uv[f.z] - uv[f.x];
        a2[t] = std::abs(0.5 * (e1.x * e2.y - e1.y * e2.x));
        total3d += a3[t], totalUv += a2[t];
    }
    if (!(total3d > 0.0) || !(totalUv > 0.0)) return 0.0;
    double squeezed = 0.0;
    for (size_t t = 0; t < a3.size(); ++t)
        if (a2[t] / totalUv * factor < a3[t] / total3d) squeezed += a3[t];
    return squeezed / total3d;
}

size_t remeshVertexCountFor(uint32_t resolution) {
    return std::clamp<size_t>(size_t(resolution) * resolution / 16, 1000, 150000);
}

void normalizationFor(const GeometryImage& image, glm::vec3& offset, glm::vec3& scale) {
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::vec3& p : image.texels) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
    const glm::dvec3 extent = hi - lo;
    const double side = std::max({extent.x, extent.y, extent.z});
    if (!(side > 0.0) || !std::isfinite(side)) throw Error("the geometry image has a zero-size or non-finite bounding box");
    offset = glm::vec3((lo + hi) * 0.5 - glm::dvec3(side * 0.5));
    scale = glm::vec3(float(side));
}

TriangleMesh geometryImageMesh(const GeometryImage& image) {
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

size_t peakResidentBytes() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line))
        if (line.rfind("VmHWM:", 0) == 0) return size_t(std::stoull(line.substr(6))) * 1024;  // "VmHWM:  1234 kB"
    return 0;
}

BakeResult bakeMesh(const TriangleMesh& input, const BakeOptions& options) {
    const std::string& name = options.sourceName;
    if (!std::has_single_bit(options.resolution) || options.resolution < 2 || options.resolution > 16384)
        throw Error(name + ": --resolution " + std::to_string(options.resolution) + " is not a power of two in [2, 16384]");
    if (!std::has_single_bit(options.storeResolution) || options.storeResolution < 1 || options.storeResolution > options.resolution)
        throw Error(name + ": --store-res " + std::to_string(options.storeResolution) +
                    " is not a power of two in [1, resolution = " + std::to_string(options.resolution) + "]");
    const Clock::time_point bakeStart = Clock::now();
    BakeResult result;
    BakeReport& report = result.report;
    report.method = parameterizationName(options.method);

    // Stage 2: clean.
    CleanResult cleaned = runStage("clean", options, report, [&] { return cleanMesh(input, {.sourceName = name}); });
    report.clean = cleaned.report;
    report.cleaned = analyzeTopology(cleaned.mesh);
    report.warnings = cleaned.report.warnings;
    announce(options, report,
             format("%zu vertices, %zu triangles, genus %ld, %zu boundary loops%s", report.cleaned.vertices,
                    report.cleaned.faces, report.cleaned.genus, report.cleaned.boundaryLoops,
                    report.clean.components > 1 ? format(" (kept the largest of %zu components!)", report.clean.components).c_str() : ""));

    // Stage 3: isotropic remeshing to the target density.
    RemeshOptions remeshOptions;
    remeshOptions.targetVertexCount = options.remeshVertexCount ? options.remeshVertexCount : remeshVertexCountFor(options.resolution);
    remeshOptions.featureAngleDegrees = options.featureAngleDegrees;
    RemeshResult remeshed = runStage("remesh", options, report, [&] { return remeshIsotropic(cleaned.mesh, remeshOptions); });
    report.remesh = remeshed.report;
    announce(options, report,
             format("%zu -> %zu vertices, %zu triangles, edge %.4g, min angle %.1f deg, %zu feature edges%s",
                    report.remesh.inputVertices, report.remesh.outputVertices, report.remesh.outputTriangles,
                    report.remesh.targetEdgeLength, report.remesh.minAngleDegrees, report.remesh.featureEdges,
                    report.remesh.droppedFeatureEdges
                        ? format(" (%zu creases dropped: they made %.1f deg slivers)", report.remesh.droppedFeatureEdges,
                                 report.remesh.minAngleWithFeaturesDegrees).c_str()
                        : ""));

    // Stage 4: cut to a disk.
    // Cut through extremities (Gu et al. 2002) so the conformal start of OT does not shrink
    // an uncut protrusion beyond what the power diagram separates.
    ExtremityCutOptions cutOptions;
    cutOptions.progress = options.progress;
    ExtremityCutResult cut = runStage("cut", options, report, [&] { return cutThroughExtremities(remeshed.mesh, cutOptions); });
    report.cut = cut.cut.report;
    report.cutConformalShrink = cut.conformalShrink;
    report.cutRounds = cut.rounds.size();
    result.disk = std::move(cut.cut.disk);
    announce(options, report,
             format("%s + %zu extremity paths: genus %ld, %zu boundary loops, cut length %.4g (%zu edges), %zu boundary "
                    "vertices, conformal shrink e^%.3g",
                    report.cut.method.c_str(), report.cut.extremityPaths, report.cut.genus, report.cut.boundaryLoops,
                    report.cut.cutLength, report.cut.cutEdges, report.cut.diskBoundaryVertices, cut.conformalShrink));

    // Stages 5-6: map to the square.
    ParameterizeOptions mapOptions;
    mapOptions.method = options.method;
    mapOptions.progress = options.progress;
    if (cut.conformalStart) mapOptions.conformalStart = &*cut.conformalStart;  // measured by the cut stage
    result.map = runStage("parameterize", options, report, [&] { return parameterizeToSquare(result.disk, mapOptions); });
    report.parameterization = result.map.report;
    const ParameterizeReport& p = report.parameterization;
    if (p.flippedTriangles != 0)
        throw Error(name + ": parameterize: the " + report.method + " map flips " + std::to_string(p.flippedTriangles) +
                    " triangles (not bijective)");
    announce(options, report,
             format("%s: ricci %d it (residual %.2g), ot %d it (residual %.2g), area distortion mean %.3f max %.3f, "
                    "angle distortion mean %.3f, %zu flipped",
                    report.method.c_str(), p.ricciIterations, p.ricciResidual, p.otIterations, p.otResidual,
                    p.areaDistortionMean, p.areaDistortionMax, p.angleDistortionMean, p.flippedTriangles));

    // Where the map squeezes the surface, the geometry image has almost no samples: say so.
    report.undersampledAreaFraction = undersampledAreaFraction(result.disk.mesh, result.map.uv, kUndersampling);
    if (report.undersampledAreaFraction > 1e-3)
        report.warnings.push_back(format("%s: %.2f%% of the surface gets less than 1/%.0f of its fair share of samples "
                                         "(max area distortion e^%.1f): expect holes or streaks there",
                                         name.c_str(), 100.0 * report.undersampledAreaFraction, kUndersampling,
                                         p.areaDistortionMax));

    // Stage 7: rasterize.
    RasterizedGeometryImage full = runStage("rasterize", options, report, [&] {
        return rasterizeGeometryImage(result.disk, result.map.uv, options.resolution);
    });
    announce(options, report, format("%ux%u samples", full.positions.size, full.positions.size));

    // Stage 8: normalize, nested mip level, asset.
    runStage("store", options, report, [&] {
        Asset& asset = result.asset;
        asset.sourceName = name;
        asset.sourceHash = options.sourceHash;
        normalizationFor(full.positions, asset.offset, asset.scale);
        result.fullPositions = full.positions;
        for (glm::vec3& t : result.fullPositions.texels)
            t = glm::clamp((t - asset.offset) / asset.scale, glm::vec3(0.0f), glm::vec3(1.0f));
        result.fullNormals = std::move(full.normals);
        asset.fullResolution = options.resolution;
        asset.storedLevel = uint32_t(std::countr_zero(options.resolution / options.storeResolution));
        asset.parameterization = report.method;
        const GeometryImage storedPositions = downsampleNested(result.fullPositions, asset.storedLevel);
        const GeometryImage storedNormals = downsampleNested(result.fullNormals, asset.storedLevel);
        storeGeometryImage(asset, storedPositions, storedNormals);
        report.totalSeconds = secondsSince(bakeStart);
        nlohmann::json metadata;
        metadata["bake"] = bakeReportJson(report);
        metadata["seam"] = seamJson(result.disk, result.map, report.cut);
        asset.metadataJson = metadata.dump();
        return 0;
    });
    report.totalSeconds = secondsSince(bakeStart);
    announce(options, report,
             format("level %u kept: %ux%u samples (CR %.0f)", result.asset.storedLevel, result.asset.storedSize(),
                    result.asset.storedSize(), double(options.resolution) * options.resolution /
                                                   (double(options.storeResolution) * options.storeResolution)));
    return result;
}

} // namespace ngi
