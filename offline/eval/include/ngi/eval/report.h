// ngi offline eval: the evaluation report (`ngi-eval report`). For each input mesh:
//
//   Table 1 (paper Table 1)  each parameterization is baked at the full resolution; the mesh
//            of the FULL geometry image (LoD 0 of an asset that stores level 0, i.e. the map's
//            own quality, no mip loss) is measured against the input.
//   Table 4 (paper Table 4)  the OT image stored at 32 .. 512 (CR (resolution / stored)^2:
//            1024 .. 4 at resolution 1024), restored without the network (bilinear,
//            ngi-eval mesh --lod 0) and measured; the real bytes of each asset on disk beside
//            CR. The report does not run the network: its "with SR" column names the
//            networkWeights given (or "no trained network"); the shipped network
//            (assets/sr-x8.ngiw) is measured by experiments/sr-quality.sh (ngi-eval mesh --sr).
//   Peers    at each stored resolution: meshoptimizer simplification to the triangle count
//            whose Draco encoding (14-bit) has the asset's bytes, and Loop / modified
//            Butterfly subdivision of that simplified mesh (same bytes: the coarse mesh is
//            what is stored); at equal triangle count: the stored level's grid drawn by the
//            renderer vs the input simplified to that count.
//   Budgets  rate-distortion at byte budgets (default 4, 8, 16, 32, 64 KB): ngi is
//            exactly the asset `ngi-bake MESH --target-bytes N` writes (its rate control,
//            network naming and residual gains, ngi/bake/rate_control.h, network_choice.h),
//            measured at LoD 0 restored bicubically and by the network it names; the peer is
//            the best CD of meshoptimizer + Draco at qp 10, 12 and 14 within the same budget.
//   Plots    SVG rate-distortion (CD and HD against bytes, log-log) per mesh, and CD/HD
//            against LoD for the first mesh.
//   Pictures one contact sheet PNG per mesh (input, every LoD, the peers).
//
// Metrics are docs/DESIGN.md's (surface_distance.h): CD x1e-4, HD x1e-2, in the input's frame.
#pragma once

#include "ngi/param/parameterize.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace ngi {

struct ReportProgress {
    double done = 0.0;   // work units finished (a bake counts as several units)
    double total = 0.0;  // work units in the whole report
    std::string step;    // what just finished, e.g. "elk: bake ot"
};

struct ReportOptions {
    std::vector<std::filesystem::path> meshes;  // input meshes (resolveMeshList)
    std::filesystem::path outDir;               // report.md, plots/, pictures/, assets/
    uint32_t resolution = 1024;                 // full geometry image
    std::vector<uint32_t> storedResolutions = {32, 64, 128, 256, 512};
    std::vector<ParameterizationMethod> parameterizations = {
        ParameterizationMethod::Tutte, ParameterizationMethod::Harmonic, ParameterizationMethod::RicciConformal,
        ParameterizationMethod::Authalic, ParameterizationMethod::OptimalTransport};
    uint32_t pictureStoredResolution = 128;  // the asset whose LoDs the pictures and the
                                             // LoD plot show (clamped to the stored list)
    unsigned jobs = 1;                       // meshes processed at once
    bool reuse = false;                      // reuse assets (and recorded bake failures)
                                             // found in outDir/assets from an earlier run
    uint32_t sampleCount = 200000;           // per surface (docs/DESIGN.md)
    uint32_t pictureSize = 200;              // contact-sheet tile side, pixels
    std::filesystem::path networkWeights;    // a trained SR network (.ngiw) or empty; named, not run
    // Byte budgets of the rate-distortion section (each > 0); empty: no such section.
    std::vector<size_t> budgets = {4096, 8192, 16384, 32768, 65536};
    // Where the shipped networks of the budget assets are (ngi::networkSearchPath: empty means
    // ngi-bake's default search path, $NGI_NETWORK_DIR then beside the executable).
    std::filesystem::path networks;
    std::string command;         // the command line, quoted in the report
    std::string resolutionNote;  // a note quoted in the report (e.g. why this resolution)
    // Called after every step (from worker threads, serialized by the report). Never prints.
    std::function<void(const ReportProgress&)> progress;
};

struct ReportResult {
    std::filesystem::path reportPath;  // outDir / "report.md"
    size_t meshCount = 0;
    size_t failedBakes = 0;  // rows reported as "failed: reason"
    size_t failedMeasurements = 0;
    double seconds = 0.0;
    std::vector<std::string> skippedNetworkFiles;  // network files that do not read ("FILE: PROBLEM"), skipped
};

// The meshes named by `dirOrList`: a directory (every .off .obj .ply .stl .gltf .glb file in
// it, sorted by name) or a comma-separated list of mesh files. Throws ngi::Error naming the
// path when the directory or a listed file does not exist, or when nothing is found.
std::vector<std::filesystem::path> resolveMeshList(const std::string& dirOrList);

// Runs the whole report and writes outDir/report.md (atomically, like every file it writes).
// Every input mesh is read first: an unreadable mesh is an ngi::Error before any work. A bake
// or a measurement that fails is a reported row "failed: reason", not an error. Throws
// ngi::Error on bad options (no meshes, resolution not a power of two in [32, 4096], a
// stored resolution not a power of two in [2, resolution], no parameterization, jobs == 0,
// sampleCount == 0, a budget of 0, `networks` given but not a directory) or when outDir
// cannot be written. A budget below the smallest asset a mesh makes is a reported row.
ReportResult runReport(const ReportOptions& options);

}  // namespace ngi
