// `ngi-eval distance`: CD and HD (DESIGN.md "Metrics") and the colour PSNR of one mesh against another.
#include "eval_commands.h"

#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/eval/colour_distance.h"
#include "ngi/eval/distance_heat_map.h"
#include "ngi/eval/report_picture.h"
#include "ngi/eval/surface_distance.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/output_files.h"
#include "ngi/param/detail_transfer.h"

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace ngi::eval_cli {
namespace {

namespace fs = std::filesystem;

// `v` as 0x and 16 hex digits (the sampling seed).
std::string hex(uint64_t v)
{
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "0x%016llx", static_cast<unsigned long long>(v));
    return buffer;
}

// --seed's value: decimal digits, or 0x and up to 16 hex digits as the report prints it.
uint64_t parseSeed(const std::string& flag, const std::string& value)
{
    if (value.rfind("0x", 0) != 0) return ngi::parseIntegerOptionInRange(flag, value, 0, UINT64_MAX);
    const std::string digits = value.substr(2);
    bool ok = !digits.empty() && digits.size() <= 16;
    for (const char c : digits) ok = ok && std::isxdigit(static_cast<unsigned char>(c));
    if (!ok) throw UsageError(flag + " expects an integer (decimal, or 0x and hex digits), got '" + value + "'");
    return std::strtoull(digits.c_str(), nullptr, 16);
}

}  // namespace

int distanceCommand(const std::vector<std::string>& arguments)
{
    std::vector<std::string> paths;
    bool jsonToStdout = false;
    std::optional<std::string> jsonPath;
    ngi::SurfaceDistanceOptions options;
    bool withColour = true;
    std::optional<fs::path> heatMapPath;
    std::optional<double> heatMax;  // x1e-2 of the size
    ngi::ArgReader args(arguments);
    while (args.next()) {
        const std::string& a = args.flag();
        if (args.is("--json"))
            jsonToStdout = true;
        else if (!args.positional() && a == "--json=")
            throw UsageError("--json=: the output path is empty");
        else if (!args.positional() && a.rfind("--json=", 0) == 0)
            jsonPath = a.substr(7);
        else if (args.is("--samples"))
            options.sampleCount = uint32_t(ngi::parseIntegerOptionInRange(a, args.value(), 0, 100000000));
        else if (args.is("--seed"))
            options.seed = parseSeed(a, args.value());
        else if (args.is("--threads"))
            options.threadCount = unsigned(ngi::parseIntegerOptionInRange(a, args.value(), 0, 256));
        else if (args.is("--no-colour"))
            withColour = false;
        else if (args.is("--heat-map"))
            heatMapPath = args.value();
        else if (args.is("--heat-max"))
            heatMax = ngi::parseFloatOptionInRange(a, args.value(), 1e-6, 100.0, "a distance (x1e-2 of the size)");
        else if (args.positional())
            paths.push_back(a);
        else
            throw args.unknown();
    }
    if (paths.size() != 2)
        throw UsageError("distance expects REFERENCE and CANDIDATE, got " + std::to_string(paths.size()) + " path(s)");
    if (options.sampleCount == 0) throw UsageError("--samples must be at least 1");
    if (jsonPath && jsonPath->empty()) throw UsageError("--json= expects a path");
    if (heatMapPath && heatMapPath->empty()) throw UsageError("--heat-map expects a path");
    if (heatMax && !heatMapPath) throw UsageError("--heat-max needs --heat-map");

    std::vector<fs::path> outputPaths;
    if (jsonPath) outputPaths.push_back(*jsonPath);
    if (heatMapPath) outputPaths.push_back(*heatMapPath);
    ngi::OutputFiles outputs(outputPaths, {paths[0], paths[1]});
    // With appearance where it reads; a texture that does not read costs the colour, not CD/HD.
    std::string noColour = withColour ? "" : "--no-colour";
    auto read = [&](const std::string& path, ngi::MeshAppearance& appearance) {
        if (!withColour) return ngi::readMesh(path);
        std::string why;
        try {
            return ngi::readMesh(path, appearance);
        } catch (const ngi::Error& e) {
            why = e.what();
            appearance = {};
        }
        ngi::TriangleMesh mesh = ngi::readMesh(path);  // a geometry error is the command's error
        std::fprintf(stderr, "ngi-eval: warning: colour not measured: %s\n", why.c_str());
        noColour = why;
        return mesh;
    };
    ngi::MeshAppearance referenceLook, candidateLook;
    const ngi::TriangleMesh reference = read(paths[0], referenceLook);
    const ngi::TriangleMesh candidate = read(paths[1], candidateLook);
    if (noColour.empty() && (referenceLook.empty() || candidateLook.empty()))
        noColour = paths[referenceLook.empty() ? 0 : 1] + " has no appearance";
    const auto start = std::chrono::steady_clock::now();
    const ngi::SurfaceDistance r = ngi::surfaceDistance(reference, candidate, options);
    std::optional<ngi::ColourDistance> colour;
    if (noColour.empty())
        colour = ngi::colourDistance(reference, referenceLook, candidate, candidateLook,
                                     {options.sampleCount, options.seed, options.threadCount});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    const double cd = r.chamfer * ngi::kChamferReportScale;
    const double hd = r.hausdorff * ngi::kHausdorffReportScale;
    nlohmann::json j;
    j["reference"] = {
        {"path", paths[0]}, {"vertices", reference.positions.size()}, {"triangles", reference.triangles.size()}};
    j["candidate"] = {
        {"path", paths[1]}, {"vertices", candidate.positions.size()}, {"triangles", candidate.triangles.size()}};
    j["frame"] = {{"centre", {r.frame.centre.x, r.frame.centre.y, r.frame.centre.z}}, {"scale", r.frame.scale}};
    j["samples_per_surface"] = r.sampleCount;
    j["seed"] = options.seed;
    j["chamfer_x1e-4"] = cd;
    j["hausdorff_x1e-2"] = hd;
    j["chamfer"] = r.chamfer;
    j["hausdorff"] = r.hausdorff;
    j["mean_squared_reference_to_candidate"] = r.meanSquaredReferenceToCandidate;
    j["mean_squared_candidate_to_reference"] = r.meanSquaredCandidateToReference;
    j["max_reference_to_candidate"] = r.maxReferenceToCandidate;
    j["max_candidate_to_reference"] = r.maxCandidateToReference;
    j["p99_reference_to_candidate"] = r.p99ReferenceToCandidate;
    j["p99_candidate_to_reference"] = r.p99CandidateToReference;
    const glm::dvec3 fa = r.farthestReferenceSample, fb = r.farthestCandidateSample;
    j["farthest_reference_sample"] = {fa.x, fa.y, fa.z};
    j["farthest_candidate_sample"] = {fb.x, fb.y, fb.z};
    if (colour) {
        // JSON has no infinity: an infinite PSNR (identical colours) is the string "inf".
        auto db = [](double v) { return std::isinf(v) ? nlohmann::json("inf") : nlohmann::json(v); };
        j["colour"] = {{"psnr_y", db(colour->psnrY)},
                       {"psnr_cb", db(colour->psnrCb)},
                       {"psnr_cr", db(colour->psnrCr)},
                       {"mse_y", colour->mseY},
                       {"mse_cb", colour->mseCb},
                       {"mse_cr", colour->mseCr},
                       {"footprint", colour->footprint},
                       {"samples", colour->sampleCount},
                       {"definition",
                        "colour_distance.h: base colour at reference samples against the candidate's "
                        "closest point, 8-bit sRGB, BT.709 YCbCr full range, PSNR = 10 log10(255^2/MSE)"}};
    } else {
        j["colour"] = nullptr;
        j["colour_not_measured"] = noColour;
    }
    j["seconds"] = seconds;
    j["definition"] = "DESIGN.md Metrics: reference frame (bbox centre, longest side 1), "
                      "point-to-surface, CD = mean d(a,B)^2 + mean d(b,A)^2, HD = max";
    // Red at --heat-max, else at the measured HD (a map of where the worst spots are).
    const double heatRed = heatMax ? *heatMax / ngi::kHausdorffReportScale : std::max(r.hausdorff, 1e-9);
    if (heatMapPath) {
        const ngi::RgbImage map =
            ngi::distanceHeatMap(reference, candidate, r.frame, heatRed, options.threadCount).image;
        outputs.writeWith(*heatMapPath, [&](const fs::path& temporary) { ngi::writeRgbPng(temporary, map); });
        j["heat_map"] = {{"path", heatMapPath->string()},
                         {"red_at_x1e-2", heatRed * ngi::kHausdorffReportScale},
                         {"definition",
                          "each reference triangle coloured by its largest distance (corners, "
                          "centroid) to the candidate, log scale: blue at red_at / 100, red at red_at"}};
    }
    const std::string text = j.dump(2) + "\n";
    if (jsonPath) outputs.write(*jsonPath, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    if (jsonPath || heatMapPath) outputs.commit();
    if (jsonToStdout) {
        std::cout << text;
        return 0;
    }
    std::printf("reference  %s  (%zu vertices, %zu triangles)\n", paths[0].c_str(), reference.positions.size(),
                reference.triangles.size());
    std::printf("candidate  %s  (%zu vertices, %zu triangles)\n", paths[1].c_str(), candidate.positions.size(),
                candidate.triangles.size());
    std::printf("frame      reference bbox centre (%.6g, %.6g, %.6g), longest side %.6g -> 1\n", r.frame.centre.x,
                r.frame.centre.y, r.frame.centre.z, 1.0 / r.frame.scale);
    std::printf("samples    %u per surface, seed %s, point-to-surface (AABB tree)\n", r.sampleCount,
                hex(options.seed).c_str());
    std::printf("CD = %.4f x1e-4   (mean d(ref,cand)^2 %.4f + mean d(cand,ref)^2 %.4f, x1e-4)\n", cd,
                r.meanSquaredReferenceToCandidate * ngi::kChamferReportScale,
                r.meanSquaredCandidateToReference * ngi::kChamferReportScale);
    std::printf("HD = %.4f x1e-2   (max d(ref,cand) %.4f, max d(cand,ref) %.4f, x1e-2)\n", hd,
                r.maxReferenceToCandidate * ngi::kHausdorffReportScale,
                r.maxCandidateToReference * ngi::kHausdorffReportScale);
    std::printf("99th pct   d(ref,cand) %.4f, d(cand,ref) %.4f, x1e-2\n",
                r.p99ReferenceToCandidate * ngi::kHausdorffReportScale,
                r.p99CandidateToReference * ngi::kHausdorffReportScale);
    std::printf("farthest   reference sample at (%.6g, %.6g, %.6g), candidate sample at (%.6g, %.6g, %.6g)"
                " (input coordinates)\n",
                fa.x, fa.y, fa.z, fb.x, fb.y, fb.z);
    if (colour)
        std::printf("colour     PSNR Y %.2f dB, Cb %.2f dB, Cr %.2f dB   (BT.709 8-bit, reference samples against the "
                    "candidate's closest points, footprint %.4g)\n",
                    colour->psnrY, colour->psnrCb, colour->psnrCr, colour->footprint);
    else
        std::printf("colour     not measured (%s)\n", noColour.c_str());
    if (heatMapPath)
        std::printf("heat map   %s: the reference from two sides, each triangle by its distance to the candidate, "
                    "log scale, blue at 1/100 of red, red at %.4f x1e-2%s\n",
                    heatMapPath->c_str(), heatRed * ngi::kHausdorffReportScale, heatMax ? "" : " (the HD)");
    std::printf("time       %.2f s (sampling + trees + queries, %u thread%s)\n", seconds, options.threadCount,
                options.threadCount == 1 ? "" : "s");
    return 0;
}

}  // namespace ngi::eval_cli
