// ngi offline: the bake report and seam description as JSON (see bake_report.h).
#include "ngi/bake/bake_report.h"

#include <cmath>

namespace ngi {
namespace {

// Rounds to 1e-7 so the metadata stays compact (uv in [0,1]; far below one 1024 texel).
double compact(double v) { return std::round(v * 1e7) / 1e7; }

} // namespace

nlohmann::json bakeReportJson(const BakeReport& report) {
    nlohmann::json j;
    j["input"] = {{"vertices", report.clean.inputVertices}, {"triangles", report.clean.inputTriangles}};
    j["clean"] = {{"vertices", report.cleaned.vertices},
                  {"triangles", report.cleaned.faces},
                  {"genus", report.cleaned.genus},
                  {"boundaryLoops", report.cleaned.boundaryLoops},
                  {"components", report.clean.components},
                  {"keptAreaFraction", report.clean.keptAreaFraction},
                  {"mergedDuplicateVertices", report.clean.mergedDuplicateVertices},
                  {"droppedDegenerateTriangles", report.clean.droppedDegenerateTriangles},
                  {"droppedDuplicateTriangles", report.clean.droppedDuplicateTriangles},
                  {"repairedZeroAreaTriangles", report.clean.repairedZeroAreaTriangles},
                  {"droppedZeroAreaTriangles", report.clean.droppedZeroAreaTriangles},
                  {"flippedTriangles", report.clean.flippedTriangles},
                  {"splitNonManifoldVertices", report.clean.splitNonManifoldVertices},
                  {"reversedToOutward", report.clean.reversedToOutward}};
    j["remesh"] = {{"verticesBefore", report.remesh.inputVertices},
                   {"trianglesBefore", report.remesh.inputTriangles},
                   {"verticesAfter", report.remesh.outputVertices},
                   {"trianglesAfter", report.remesh.outputTriangles},
                   {"targetEdgeLength", report.remesh.targetEdgeLength},
                   {"meanEdgeLength", report.remesh.meanEdgeLength},
                   {"minAngleDegrees", report.remesh.minAngleDegrees},
                   {"featureEdges", report.remesh.featureEdges},
                   {"droppedFeatureEdges", report.remesh.droppedFeatureEdges}};
    j["genus"] = report.cut.genus;
    j["boundaries"] = report.cut.boundaryLoops;
    j["cut"] = {{"method", report.cut.method},
                {"length", report.cut.cutLength},
                {"edges", report.cut.cutEdges},
                {"seamVertices", report.cut.seamVertices},
                {"diskBoundaryVertices", report.cut.diskBoundaryVertices},
                {"extremityPaths", report.cut.extremityPaths},
                {"extremityLength", report.cut.extremityLength},
                {"rounds", report.cutRounds},
                {"conformalShrink", report.cutConformalShrink}};
    const ParameterizeReport& p = report.parameterization;
    j["parameterization"] = {{"method", report.method},
                             {"ricciIterations", p.ricciIterations},
                             {"ricciResidual", p.ricciResidual},
                             {"otIterations", p.otIterations},
                             {"otResidual", p.otResidual},
                             {"areaDistortionMax", p.areaDistortionMax},
                             {"areaDistortionMean", p.areaDistortionMean},
                             {"angleDistortionMax", p.angleDistortionMax},
                             {"angleDistortionMean", p.angleDistortionMean},
                             {"flippedTriangles", p.flippedTriangles},
                             {"otStart", p.otStart},
                             {"undersampledAreaFraction", report.undersampledAreaFraction},
                             {"otStartAreaDistortionMax", p.otStartAreaDistortionMax},
                             {"otCentroidFlips", p.otCentroidFlips},
                             {"secondsConformal", p.secondsConformal},
                             {"secondsTransport", p.secondsTransport}};
    nlohmann::json stages = nlohmann::json::object();
    for (const StageTime& s : report.stages) stages[s.stage] = s.seconds;
    j["seconds"] = stages;
    j["totalSeconds"] = report.totalSeconds;
    j["warnings"] = report.warnings;
    return j;
}

nlohmann::json seamJson(const DiskMesh& disk, const SquareMap& map, const CutReport& cut) {
    nlohmann::json j;
    j["method"] = cut.method;
    j["genus"] = cut.genus;
    j["originalBoundaryLoops"] = cut.boundaryLoops;
    j["cutLength"] = cut.cutLength;
    j["cutEdges"] = cut.cutEdges;
    const SeamEdges seam = findSeamEdges(disk);
    std::vector<double> uv;
    uv.reserve(disk.boundaryLoop.size() * 2);
    for (uint32_t v : disk.boundaryLoop) {
        uv.push_back(v < map.uv.size() ? compact(map.uv[v].x) : 0.0);
        uv.push_back(v < map.uv.size() ? compact(map.uv[v].y) : 0.0);
    }
    std::vector<int64_t> corners;
    for (uint32_t c : map.corners) {
        auto it = std::find(disk.boundaryLoop.begin(), disk.boundaryLoop.end(), c);
        corners.push_back(it == disk.boundaryLoop.end() ? -1 : int64_t(it - disk.boundaryLoop.begin()));
    }
    j["boundaryUv"] = uv;               // x0, y0, x1, y1, ... per boundary vertex, in loop order
    j["corners"] = corners;             // boundary positions mapped to (0,0), (1,0), (1,1), (0,1)
    j["mates"] = seam.mates;            // [i, j]: boundary edges i and j are one edge of the surface
    j["openBoundaryEdges"] = seam.unmatched;  // edges of the mesh's own boundary (no mate)
    return j;
}

} // namespace ngi
