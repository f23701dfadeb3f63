// ngi offline: the bake report and seam description as JSON (see bake_report.h).
#include "ngi/bake/bake_report.h"

#include <algorithm>

namespace ngi {
namespace {}  // namespace

nlohmann::json bakeReportJson(const BakeReport& report)
{
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
                  {"nonManifoldEdges", report.clean.nonManifoldEdges},
                  {"cutEdgeSides", report.clean.cutEdgeSides},
                  {"orientationCutEdges", report.clean.orientationCutEdges},
                  {"droppedNonManifoldTriangles", report.clean.droppedNonManifoldTriangles},
                  {"splitNonManifoldVertices", report.clean.splitNonManifoldVertices},
                  {"droppedComponentTriangles", report.clean.droppedComponentTriangles},
                  {"reversedComponents", report.clean.reversedComponents},
                  {"reversedToOutward", report.clean.reversedToOutward}};
    // Per chart; the top-level "parameterization" summarizes them (area-weighted means,
    // maxima, sums) so that one-chart readers keep working.
    nlohmann::json charts = nlohmann::json::array();
    double areaMean = 0.0, angleMean = 0.0, areaMax = 0.0, angleMax = 0.0, undersampled = 0.0;
    size_t flipped = 0;
    for (const ChartReport& c : report.charts) {
        nlohmann::json k;
        k["resolution"] = c.resolution;
        k["areaFraction"] = c.areaFraction;
        k["triangles"] = c.topology.faces;
        k["genus"] = c.cut.genus;
        k["boundaries"] = c.cut.boundaryLoops;
        k["remesh"] = {
            {"verticesBefore", c.remesh.inputVertices},           {"trianglesBefore", c.remesh.inputTriangles},
            {"verticesAfter", c.remesh.outputVertices},           {"trianglesAfter", c.remesh.outputTriangles},
            {"targetEdgeLength", c.remesh.targetEdgeLength},      {"meanEdgeLength", c.remesh.meanEdgeLength},
            {"minAngleDegrees", c.remesh.minAngleDegrees},        {"featureEdges", c.remesh.featureEdges},
            {"droppedFeatureEdges", c.remesh.droppedFeatureEdges}};
        k["cut"] = {{"method", c.cut.method},
                    {"length", c.cut.cutLength},
                    {"edges", c.cut.cutEdges},
                    {"seamVertices", c.cut.seamVertices},
                    {"diskBoundaryVertices", c.cut.diskBoundaryVertices},
                    {"extremityPaths", c.cut.extremityPaths},
                    {"extremityLength", c.cut.extremityLength},
                    {"rounds", c.cutRounds},
                    {"searchVertices", c.cutSearchVertices},
                    {"conformalShrink", c.cutConformalShrink}};
        const ParameterizeReport& p = c.parameterization;
        k["parameterization"] = {{"ricciIterations", p.ricciIterations},
                                 {"ricciResidual", p.ricciResidual},
                                 {"otIterations", p.otIterations},
                                 {"otResidual", p.otResidual},
                                 {"areaDistortionMax", p.areaDistortionMax},
                                 {"areaDistortionMean", p.areaDistortionMean},
                                 {"angleDistortionMax", p.angleDistortionMax},
                                 {"angleDistortionMean", p.angleDistortionMean},
                                 {"flippedTriangles", p.flippedTriangles},
                                 {"otStart", p.otStart},
                                 {"undersampledAreaFraction", c.undersampledAreaFraction},
                                 {"farFromImageArea", c.farFromImageArea},
                                 {"otStartAreaDistortionMax", p.otStartAreaDistortionMax},
                                 {"otCentroidFlips", p.otCentroidFlips},
                                 {"secondsConformal", p.secondsConformal},
                                 {"secondsTransport", p.secondsTransport}};
        k["seam"] = {{"matched", c.seam.matched},
                     {"problem", c.seam.problem},
                     {"cutPaths", c.seam.cutPaths},
                     {"movedCorners", c.seam.movedCorners},
                     {"retransported", c.seam.retransported},
                     {"transportIterations", c.seam.transportIterations},
                     {"areaDistortionMeanBeforeTransport", c.seam.areaDistortionMeanBefore},
                     {"transportRoundAreaDistortionMean", c.seam.roundAreaDistortionMean},
                     {"transportRoundSeconds", c.seam.roundSeconds},
                     {"openSegments", c.seam.openSegments},
                     {"coarsestWatertightLevel", c.seam.level},
                     {"lengthChange", c.seam.lengthChange},
                     {"sidesMismatch", c.seam.mismatch},
                     {"maxBorderMove", c.seam.maxBorderMove},
                     {"maxInteriorMove", c.seam.maxInteriorMove},
                     {"gapBeforeWeld", c.seamGapBeforeWeld},
                     {"areaDistortionMax", c.seamAreaDistortionMax},
                     {"areaDistortionMean", c.seamAreaDistortionMean}};
        if (c.colorLevel >= 0) k["colorLevel"] = c.colorLevel;
        if (c.splitGroup >= 0) {
            k["splitGroup"] = c.splitGroup;
            k["crossSeamGapBeforeWeld"] = c.crossSeamGapBeforeWeld;
            if (!c.splitForThinParts.empty()) k["splitForThinParts"] = c.splitForThinParts;
        }
        k["remeshFarArea"] = c.remeshFarArea;
        k["remeshDensified"] = c.remeshDensified;
        k["remeshForThinParts"] = c.remeshForThinParts;
        k["denseRemeshFailed"] = c.denseRemeshFailed;
        k["denseRemeshProblem"] = c.denseRemeshProblem;
        k["detail"] = {{"projected", c.detail.projected},
                       {"kept", c.detail.kept},
                       {"maxDistance", c.detail.maxDistance},
                       {"meanDistance", c.detail.meanDistance}};
        charts.push_back(std::move(k));
        areaMean += c.areaFraction * p.areaDistortionMean;
        angleMean += c.areaFraction * p.angleDistortionMean;
        areaMax = std::max(areaMax, p.areaDistortionMax);
        angleMax = std::max(angleMax, p.angleDistortionMax);
        undersampled += c.areaFraction * c.undersampledAreaFraction;
        flipped += p.flippedTriangles;
    }
    j["genus"] = report.charts.size() == 1 ? report.charts[0].cut.genus : report.cleaned.genus;
    j["boundaries"] = report.cleaned.boundaryLoops;
    j["parameterization"] = {{"method", report.method},
                             {"detailDensity", report.detailDensity},
                             {"colorSamplesPerArea", report.colorSamplesPerArea},
                             {"areaDistortionMax", areaMax},
                             {"areaDistortionMean", areaMean},
                             {"angleDistortionMax", angleMax},
                             {"angleDistortionMean", angleMean},
                             {"flippedTriangles", flipped},
                             {"undersampledAreaFraction", undersampled}};
    j["charts"] = std::move(charts);
    nlohmann::json stages = nlohmann::json::object();
    for (const StageTime& s : report.stages) stages[s.stage] = s.seconds;
    j["seconds"] = stages;
    j["totalSeconds"] = report.totalSeconds;
    j["warnings"] = report.warnings;
    return j;
}

}  // namespace ngi
