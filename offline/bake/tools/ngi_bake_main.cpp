// ngi-bake: bakes a mesh file into an optimal-transport geometry-image asset (.ngi).
//   ngi-bake MESH -o OUT.ngi [--resolution 1024] [--store-res 128 | --target-bytes N]
//            [--param ot|ricci|harmonic|tutte|authalic] [--export-full DIR] [--json FILE]
//            [--export-mesh FILE] [--remesh-vertices N] [--feature-angle DEG] [--quiet]
//   ngi-bake --batch DIR_OR_LIST --out DIR [--jobs N] [--shard I/N] ...  (bake_batch.h)
// Prints one line per stage with its time. Outputs are all or nothing (ngi/output_files.h):
// each is written to a temporary file and all are renamed only when the whole run succeeded,
// so on any error (one message on stderr, exit code 1) every pre-existing file is as it was.
// Output paths are checked before the bake (directory exists, not a directory, not an
// input, not another output, a mesh format ngi-bake can write). Usage errors exit with 2.
#include "bake_batch.h"

#include "ngi/asset.h"
#include "ngi/bake/bake.h"
#include "ngi/bake/bake_report.h"
#include "ngi/bake/rate_control.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/mesh/mesh_io.h"
#include "ngi/bake/network_choice.h"
#include "ngi/network_catalog.h"
#include "ngi/nn/residual_gain.h"
#include "ngi/output_files.h"
#include "ngi/param/detail_density.h"
#include "ngi/png_io.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

const char* kUsage = "usage: ngi-bake MESH -o OUT.ngi [--resolution 1024] [--store-res 128 | --target-bytes N]\n"
                     "                [--param ot|ricci|harmonic|tutte|authalic] [--export-full DIR] [--json FILE]\n"
                     "                [--export-mesh FILE] [--remesh-vertices N] [--feature-angle DEG] [--free-seams]\n"
                     "                [--networks DIR | --no-network] [--quiet]\n"
                     "       ngi-bake --batch DIR_OR_LIST --out DIR [--jobs N] [--shard I/N] [--timeout SECONDS]\n"
                     "                [bake options]   (a data set, resumable; ngi-bake --batch --help)\n"
                     "  MESH               .obj .off .ply .stl .gltf .glb\n"
                     "  -o OUT.ngi         the asset to write (all outputs are written together, or none)\n"
                     "  --resolution R     full geometry image: R x R cells, (R+1)^2 samples (power of two)\n"
                     "  --store-res S      the mip level kept in the asset: (S+1)^2 samples (power of two <= R)\n"
                     "  --target-bytes N   the whole asset in at most N bytes: the stored level and the position\n"
                     "                     step with the smallest restore error (pyramid-coded; the asset\n"
                     "                     keeps a compact bake report, --json everything)\n"
                     "  --normal-bits B    with --target-bytes: normals as the positions' prediction plus a\n"
                     "                     B-bit octahedral residual (default 0: prediction only; the network's\n"
                     "                     restore gains from 4-8)\n"
                     "  --param METHOD     map to the square: ot (default), ricci, harmonic, tutte, authalic\n"
                     "  --export-full DIR  also write DIR/NAME_position.png and DIR/NAME_normal.png (16-bit RGB,\n"
                     "                     full resolution; positions normalized like the asset)\n"
                     "  --json FILE        write a JSON summary of the bake\n"
                     "  --networks DIR     where the shipped super-resolution networks (*.ngiw) are (default:\n"
                     "                     $NGI_NETWORK_DIR, then the assets/ beside the executable: build/bin ->\n"
                     "                     assets, prefix/bin -> share/ngi); the asset names the one whose factor\n"
                     "                     takes the largest chart's stored level to its full size, so the tools'\n"
                     "                     --sr finds it (ngi/network_catalog.h)\n"
                     "  --no-network       name no network in the asset\n"
                     "  --export-mesh FILE write the full-resolution geometry image as a mesh (.obj .off .ply),\n"
                     "                     in the input's coordinates (to measure the bake's own error)\n"
                     "  --remesh-vertices N  remeshing density (default: R^2/64 clamped to [1000, 150000])\n"
                     "  --feature-angle DEG  dihedral angle above which an edge is a crease the remesher keeps\n"
                     "                     in [0, 180] (default 60; 0 keeps none)\n"
                     "  --free-seams       keep the map's own border: seams may crack (default: matched border,\n"
                     "                     watertight at every LoD down to the coarsest watertight level)\n"
                     "  --no-appearance    bake the geometry only (default: the input's textures, vertex colours\n"
                     "                     and materials become each chart's base colour image)\n"
                     "  --no-detail-transfer  keep the samples on the remesh (default: moved to the closest\n"
                     "                     point of the input surface, so the remesh only carries the map)\n"
                     "  --detail-density S optimal transport to a measure that follows detail: each remesh\n"
                     "                     vertex gets its area times 1 + S * its mean curvature over the mean\n"
                     "                     (at most 8), so samples gather where the surface bends; S in [0, 64]\n"
                     "                     (default 0: area-preserving, the paper's map)\n"
                     "  --no-split         one chart per component, also where the cut search finds thin\n"
                     "                     parts (by default such a component is cut into about 8 x its area\n"
                     "                     share matched charts; without the split it is remeshed densely)\n"
                     "  --split-pieces K|auto  cut every component into about K x its area share geodesic\n"
                     "                     Voronoi pieces, one chart each, their shared borders matched\n"
                     "                     (watertight; 2-256); auto (with --target-bytes): bakes one chart per\n"
                     "                     component and the split into 8, keeps the one closer to the input\n"
                     "                     (the split alone where one chart per component is refused)\n"
                     "  --quiet            print only warnings and errors, not each stage's progress\n";

// --split-pieces auto: the split it tries against one chart per component.
constexpr uint32_t kAutoSplitPieces = 8;

struct Arguments {
    fs::path mesh, output, exportDir, json, exportMesh, networks;
    bool nameNetwork = true;
    bool readAppearance = true;  // textures, vertex colours and materials into base colour images
    ngi::BakeOptions options;
    size_t targetBytes = 0;   // 0: --store-res decides, zlib-coded samples
    bool splitAuto = false;   // --split-pieces auto: one chart or split, whichever is closer
    uint32_t normalBits = 0;  // with --target-bytes: the normals' residual bits
    bool quiet = false;
};

using ngi::UsageError;

// The documented range of --feature-angle: a dihedral angle in degrees.
constexpr double kMaxFeatureAngle = 180.0;

Arguments parseArguments(int argc, char** argv)
{
    Arguments a;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        const std::string& arg = args.flag();
        if (args.is("-h", "--help"))
            throw UsageError("");
        else if (args.is("-o", "--output"))
            a.output = ngi::parseOutputPathOption(arg, args.value());
        else if (args.is("--resolution"))
            a.options.resolution = ngi::parseUintOption(arg, args.value());
        else if (args.is("--store-res"))
            a.options.storeResolution = ngi::parseUintOption(arg, args.value());
        else if (args.is("--target-bytes")) {
            a.targetBytes = ngi::parseUintOption(arg, args.value());
            if (a.targetBytes == 0) throw UsageError("--target-bytes expects a positive byte count");
        } else if (args.is("--normal-bits")) {
            a.normalBits = ngi::parseUintOption(arg, args.value());
            if (a.normalBits > 16) throw UsageError("--normal-bits expects 0 to 16");
        } else if (args.is("--param")) {
            try {
                a.options.method = ngi::parseParameterizationMethod(args.value());
            } catch (const ngi::Error& e) {
                throw UsageError(e.what());
            }
        } else if (args.is("--export-full"))
            a.exportDir = ngi::parseOutputPathOption(arg, args.value());
        else if (args.is("--json"))
            a.json = ngi::parseOutputPathOption(arg, args.value());
        else if (args.is("--export-mesh"))
            a.exportMesh = ngi::parseOutputPathOption(arg, args.value());
        else if (args.is("--remesh-vertices"))
            a.options.remeshVertexCount = ngi::parseUintOption(arg, args.value());
        else if (args.is("--feature-angle"))
            a.options.featureAngleDegrees =
                ngi::parseFloatOptionInRange(arg, args.value(), 0.0, kMaxFeatureAngle, "degrees");
        else if (args.is("--free-seams"))
            a.options.matchSeams = false;
        else if (args.is("--no-detail-transfer"))
            a.options.transferDetail = false;
        else if (args.is("--no-appearance"))
            a.readAppearance = false;
        else if (args.is("--detail-density"))
            a.options.detailDensity =
                ngi::parseFloatOptionInRange(arg, args.value(), 0.0, ngi::kMaxDetailDensity, "a strength");
        else if (args.is("--split-pieces")) {
            const std::string pieces = args.value();
            if (pieces == "auto") {
                a.splitAuto = true;
                a.options.splitPieces = 0;
                a.options.splitThinParts = 0;  // its "one chart" is one chart per component
            } else {
                a.options.splitPieces = ngi::parseUintOption(arg, pieces);
                a.splitAuto = false;
                if (a.options.splitPieces < 2 || a.options.splitPieces > 256)
                    throw UsageError("--split-pieces expects 2 to 256 pieces, or auto");
            }
        } else if (args.is("--no-split"))
            a.options.splitThinParts = 0;
        else if (args.is("--networks"))
            a.networks = args.value();
        else if (args.is("--no-network"))
            a.nameNetwork = false;
        else if (args.is("--quiet"))
            a.quiet = true;
        else if (!args.positional())
            throw args.unknown();
        else if (a.mesh.empty())
            a.mesh = arg;
        else
            throw UsageError("more than one input mesh: " + a.mesh.string() + " and " + arg);
    }
    if (a.mesh.empty()) throw UsageError("no input mesh");
    if (a.splitAuto && a.targetBytes == 0)
        throw UsageError(
            "--split-pieces auto chooses by the distance to the input at a byte budget: give --target-bytes");
    if (a.output.empty()) throw UsageError("no output file (-o OUT.ngi)");
    // A mistyped directory would silently name no network: say so before anything is baked.
    if (!a.networks.empty() && !fs::is_directory(a.networks))
        throw UsageError("--networks " + a.networks.string() + ": not a directory");
    return a;
}

ngi::PngImage toPng(const ngi::GeometryImage& image, bool normals)
{
    ngi::PngImage png;
    png.width = png.height = image.size;
    png.channels = 3;
    png.bitDepth = 16;
    png.samples.resize(image.texels.size() * 3);
    for (size_t i = 0; i < image.texels.size(); ++i)
        for (int c = 0; c < 3; ++c) {
            float v = normals ? (image.texels[i][c] + 1.0f) * 0.5f : image.texels[i][c];
            png.samples[i * 3 + c] = uint16_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 65535.0f));
        }
    return png;
}

// The --export-full files: DIR/STEM_position.png and DIR/STEM_normal.png, STEM from -o.
fs::path exportedPositions(const Arguments& a) { return a.exportDir / (a.output.stem().string() + "_position.png"); }
fs::path exportedNormals(const Arguments& a) { return a.exportDir / (a.output.stem().string() + "_normal.png"); }

// Declares every output of the run and checks all that can be checked before the bake:
// each directory exists, no output is a directory, an input or another output, and
// --export-mesh names a format writeMesh writes.
ngi::OutputFiles declareOutputs(const Arguments& a)
{
    if (!a.exportDir.empty() && !fs::is_directory(a.exportDir))
        throw ngi::Error(a.exportDir.string() + ": the --export-full directory does not exist");
    std::vector<fs::path> outputs = {a.output, a.json, a.exportMesh};
    if (!a.exportDir.empty()) {
        outputs.push_back(exportedPositions(a));
        outputs.push_back(exportedNormals(a));
    }
    ngi::OutputFiles files(outputs, {a.mesh});
    // Checked now, naming the path given; the mesh is staged only after the bake.
    if (!a.exportMesh.empty()) ngi::checkMeshOutputFormat(a.exportMesh);
    return files;
}

// One bake of MESH to OUT.ngi (ngi-bake without --batch), stage by stage in the order main()
// calls them; what a stage makes is kept for the stages after it and for the summary.
struct SingleBake {
    using Clock = std::chrono::steady_clock;
    Arguments args;
    Clock::time_point start = Clock::now();
    ngi::OutputFiles outputs;
    ngi::MeshAppearance appearance;
    ngi::TriangleMesh mesh;
    double readSeconds = 0.0;
    ngi::BakeResult result;
    std::string oneChartRefusal;  // --split-pieces auto: why one chart per component was refused
    std::vector<fs::path> networkDirs;
    std::vector<ngi::ShippedNetwork> shipped;
    std::optional<ngi::RateControlReport> rate;
    // A choice between two bakes at the budget (--split-pieces auto; a split for thin
    // parts checked against one chart): each fitted to the budget, and the one whose chosen
    // restore is closer to the input kept (the rate control's own measure).
    std::optional<double> oneChartRms, splitRms;
    bool keptSplit = false;
    ngi::NetworkChoice network;
    double gainSeconds = 0.0;
    std::vector<uint8_t> assetFile;

    explicit SingleBake(Arguments arguments) : args(std::move(arguments)), outputs(declareOutputs(args))
    {
        args.options.stageDone = [this](const std::string& stage, double seconds, const std::string& summary) {
            stageLine(stage, seconds, summary);
        };
        if (!args.quiet)
            args.options.progress = [](const std::string& s) {
                std::printf("ngi-bake:        %s\n", s.c_str());
                std::fflush(stdout);
            };
    }
    SingleBake(const SingleBake&) = delete;  // the stage callback holds `this`
    SingleBake& operator=(const SingleBake&) = delete;

    // One stage's line. Stages 3-7 run once per chart: the number comes from the stage's name.
    void stageLine(const std::string& stage, double seconds, const std::string& summary) const
    {
        // Parameterize is stages 5-6 (Ricci flow + OT), match seams is 6b: shown as 6.
        const char* names[] = {"read", "clean", "remesh", "cut", "parameterize", "match seams", "rasterize", "store"};
        int stageNumber = 1;
        for (int i = 0; i < 8; ++i)
            if (stage == names[i]) stageNumber = i + 1;
        if (stage == "cut search") stageNumber = 4;  // the cut's search on a coarse remesh, before the remesh
        if (stage == "appearance") stageNumber = 7;  // the colours over the rasterized charts
        if (!args.quiet)
            std::printf("ngi-bake: [%d/8] %-12s %8.2f s  %s\n", stageNumber, stage.c_str(), seconds, summary.c_str());
        std::fflush(stdout);
    }

    // Stage 1: the mesh and its appearance.
    void readInput()
    {
        const auto readStart = Clock::now();
        mesh = args.readAppearance ? ngi::readMesh(args.mesh, appearance) : ngi::readMesh(args.mesh);
        for (const std::string& warning : appearance.warnings)
            std::fprintf(stderr, "ngi-bake: WARNING: %s\n", warning.c_str());
        if (!appearance.empty()) args.options.appearance = &appearance;
        const std::vector<uint8_t> bytes = ngi::readFileBytes(args.mesh);
        readSeconds = std::chrono::duration<double>(Clock::now() - readStart).count();
        stageLine("read", readSeconds,
                  std::to_string(mesh.positions.size()) + " vertices, " + std::to_string(mesh.triangles.size()) +
                      " triangles from " + args.mesh.filename().string() +
                      (appearance.empty() ? std::string()
                                          : ", " + std::to_string(appearance.materials.size()) + " materials, " +
                               std::to_string(appearance.images.size()) + " textures" +
                               (appearance.cornerColors.empty() ? "" : ", vertex colours")));
        args.options.sourceName = args.mesh.string();
        args.options.sourceHash = ngi::fnv1a64(bytes);
    }

    // Stages 2-8: the charts (--split-pieces auto: the split where one chart per component is refused).
    void bakeCharts()
    {
        if (!args.splitAuto) {
            result = ngi::bakeMesh(mesh, args.options);
        } else {
            try {
                result = ngi::bakeMesh(mesh, args.options);
            } catch (const ngi::Error& e) {
                // One chart refused (cheese, genus 133: its map is garbage): the split alone, whose
                // own refusal is then the error.
                oneChartRefusal = e.what();
                std::fprintf(stderr, "ngi-bake: split auto: one chart per component refused (%s): baking the split\n",
                             e.what());
                ngi::BakeOptions splitOptions = args.options;
                splitOptions.splitPieces = kAutoSplitPieces;
                result = ngi::bakeMesh(mesh, splitOptions);
            }
        }
    }

    // The shipped networks the asset may name; their fields reserved in the asset.
    void findNetworks()
    {
        for (const std::string& warning : result.report.warnings)
            std::fprintf(stderr, "ngi-bake: WARNING: %s\n", warning.c_str());
        result.asset.sourceName = args.mesh.filename().string();
        networkDirs = ngi::networkSearchPath(args.networks);
        std::vector<std::string> skipped;
        shipped =
            args.nameNetwork ? ngi::findShippedNetworks(networkDirs, skipped) : std::vector<ngi::ShippedNetwork>{};
        for (const std::string& file : skipped)
            std::fprintf(stderr, "ngi-bake: WARNING: skipped a network file that does not read: %s\n", file.c_str());
        // The rate control counts the longest name the asset may carry (the level it picks decides
        // which) and format 6's residual gains (placeholders; fitted below).
        ngi::reserveNetworkFields(result.asset, shipped);
    }

    // --target-bytes: the asset fitted to the budget (of two bakes, the closer to the input).
    void fitToBudget()
    {
        if (!args.targetBytes) return;
        // The other bake of a choice, quiet, ready for the rate control.
        auto bakeOther = [&](ngi::BakeOptions other) {
            other.stageDone = nullptr;
            other.progress = nullptr;
            ngi::BakeResult bake = ngi::bakeMesh(mesh, other);
            bake.asset.sourceName = result.asset.sourceName;
            ngi::reserveNetworkFields(bake.asset, shipped);
            return bake;
        };
        // fitCloserOfTwoBakes with `result` first; `other` replaces it where it is kept.
        auto choose = [&](ngi::BakeResult* other, bool mayKeepOther = true) {
            ngi::BudgetChoice choice = ngi::fitCloserOfTwoBakes(
                result.asset, result.charts, other ? &other->asset : nullptr, other ? &other->charts : nullptr,
                args.targetBytes, args.normalBits, shipped, mesh);
            choice.keptFirst = choice.keptFirst || !mayKeepOther;
            for (const std::string& warning : choice.warnings)
                std::fprintf(stderr, "ngi-bake: WARNING: %s: %s\n", result.asset.sourceName.c_str(), warning.c_str());
            if (choice.keptFirst) {
                rate = choice.first;
            } else {
                for (const std::string& warning : other->report.warnings)
                    std::fprintf(stderr, "ngi-bake: WARNING: %s\n", warning.c_str());
                result = std::move(*other);
                rate = *choice.second;
            }
            return choice;
        };
        if (args.splitAuto && oneChartRefusal.empty()) {
            ngi::BakeOptions splitOptions = args.options;
            splitOptions.splitPieces = kAutoSplitPieces;
            ngi::BakeResult split = bakeOther(splitOptions);
            const size_t oneChartCharts = result.asset.charts.size(), splitCharts = split.asset.charts.size();
            // A split that cut nothing more is measured but not kept.
            const ngi::BudgetChoice choice = choose(&split, splitCharts > oneChartCharts);
            oneChartRms = std::sqrt(choice.first.chosen.inputError);
            splitRms = std::sqrt(choice.second->chosen.inputError);
            keptSplit = !choice.keptFirst;
            std::fprintf(stderr,
                         "ngi-bake: split auto: one chart per component %.4g, split into %zu charts %.4g RMS to the "
                         "input: kept %s\n",
                         *oneChartRms, splitCharts, *splitRms, keptSplit ? "the split" : "one chart per component");
        } else if (!args.splitAuto && ngi::anyComponentSplitForThinParts(result.report)) {
            // On a compact body whose thin part is small, eight pieces can cost more bytes than
            // they give back: the closer of the two bakes is kept.
            ngi::BakeOptions wholeOptions = args.options;
            wholeOptions.splitThinParts = 0;
            std::optional<ngi::BakeResult> one;
            try {
                one = bakeOther(wholeOptions);
            } catch (const ngi::Error& e) {
                oneChartRefusal = e.what();  // cheese: the split stays
            }
            const ngi::BudgetChoice choice = choose(one ? &*one : nullptr);
            splitRms = std::sqrt(choice.first.chosen.inputError);
            if (choice.second) oneChartRms = std::sqrt(choice.second->chosen.inputError);
            keptSplit = choice.keptFirst;
            std::string whole = "refused";
            if (choice.second) {
                const std::string broken = ngi::brokenInputMeasurement(choice.second->chosen);
                char rms[32];
                std::snprintf(rms, sizeof rms, "%.4g", *oneChartRms);
                whole = broken.empty() ? std::string(rms) : "unmeasured (" + broken + ")";
            }
            std::fprintf(stderr,
                         "ngi-bake: thin parts at %zu bytes: split %.4g, one chart per component %s RMS to the input: "
                         "kept %s\n",
                         args.targetBytes, *splitRms, whole.c_str(),
                         keptSplit ? "the split" : "one chart per component");
        } else {
            choose(nullptr);
            if (args.splitAuto) {  // one chart was refused: the split is the only bake
                splitRms = std::sqrt(rate->chosen.inputError);
                keptSplit = true;
            }
        }
    }

    // The rate control's candidates and choice.
    void printRateControl() const
    {
        if (!rate) return;
        if (!args.quiet)
            std::printf("ngi-bake:        rate control: %zu candidates in %.2f s (distances to the input %.2f s)\n",
                        rate->candidates.size(), rate->seconds, rate->inputSeconds);
        if (!rate->colorWarning.empty())
            std::fprintf(stderr, "ngi-bake: WARNING: %s: %s\n", args.mesh.c_str(), rate->colorWarning.c_str());
        if (!args.quiet && rate->color.present)
            std::printf(
                "ngi-bake:        base colours: %zu bytes (of %.0f%% of the budget), WebP quality %u, %u level%s "
                "coarser than baked, RMS %.2f of 255\n",
                rate->color.bytes, 100.0 * ngi::kColorBudgetShare, rate->color.quality, rate->color.levelsCoarser,
                rate->color.levelsCoarser == 1 ? "" : "s", rate->color.rms);
        if (!args.quiet)
            for (const ngi::RateCandidate& c : rate->candidates) {
                std::printf("ngi-bake:        %s level %u (%u^2) step %u/65536 tangents x%u grade %.3g: %zu bytes, RMS "
                            "point-to-plane restore error %.3g",
                            c.storedLevel == rate->chosen.storedLevel && c.tangentScale == rate->chosen.tangentScale &&
                                    c.step == rate->chosen.step && c.stepGrade == rate->chosen.stepGrade
                                ? "->"
                                : "  ",
                            c.storedLevel, (result.asset.fullResolution() >> c.storedLevel) + 1, c.step, c.tangentScale,
                            c.stepGrade, c.bytes, std::sqrt(c.error));
                if (c.networkError >= 0.0)
                    std::printf(", %.3g with %s", std::sqrt(c.networkError), c.networkId.c_str());
                if (c.inputError >= 0.0) std::printf("; to the input %.3g", std::sqrt(c.inputError));
                std::printf("\n");
            }
    }

    // The network the asset names and each chart's residual gain.
    void nameNetwork()
    {
        // The shipped network that restores the largest chart, named in HEAD, and per chart it
        // restores the gain alpha of its blend with the bicubic (ngi/bake/network_choice.h).
        network = ngi::nameNetworkAndFitGains(result.asset, result.charts, shipped);
        const ngi::ShippedNetwork* named = network.named;
        const std::vector<std::optional<ngi::nn::ResidualGainFit>>& gains = network.gains;
        for (size_t c = 0; c < result.asset.charts.size(); ++c) {
            gainSeconds += network.gainSeconds[c];
            if (gains[c] && !args.quiet)
                std::printf("ngi-bake:        chart %zu residual gain %.3f (surface-weighted RMS point-to-plane to the "
                            "full image x1e-4: bicubic %.3f, network %.3f, "
                            "blended %.3f; reference forward %.1f s)\n",
                            c, double(gains[c]->gain), 1e4 * gains[c]->rmsCubic, 1e4 * gains[c]->rmsNetwork,
                            1e4 * gains[c]->rmsGained, network.gainSeconds[c]);
        }
        if (!args.quiet) {
            if (named) {
                std::printf("ngi-bake:        network: %s (x%u, hash %s, %s)\n", named->network.name.c_str(),
                            named->network.scaleFactor, ngi::networkHashText(named->hash).c_str(),
                            named->path.string().c_str());
                for (size_t c = 1; c < result.asset.charts.size(); ++c)
                    if (!ngi::networkRestoresChart(named->network, result.asset.charts[c]))
                        std::printf(
                            "ngi-bake:        chart %zu stores x%u: not restored by %s (the tools' --sr restores it "
                            "without a network)\n",
                            c, 1u << result.asset.charts[c].storedLevel, named->network.name.c_str());
            } else if (args.nameNetwork) {
                std::string dirs;
                for (const fs::path& d : networkDirs) dirs += (dirs.empty() ? "" : ", ") + d.string();
                std::printf("ngi-bake:        network: none (no x%u network in %s)\n",
                            1u << result.asset.charts[0].storedLevel, dirs.empty() ? "no directory" : dirs.c_str());
            }
        }
    }

    // The asset and the exports, staged beside their destinations (nothing replaced before commit).
    void writeOutputs()
    {
        assetFile = ngi::serializeAsset(result.asset);
        if (args.targetBytes && assetFile.size() > args.targetBytes)
            throw ngi::Error(args.mesh.string() + ": the asset takes " + std::to_string(assetFile.size()) +
                             " bytes, above --target-bytes " + std::to_string(args.targetBytes));
        outputs.write(args.output, assetFile);
        if (!args.exportDir.empty()) {
            // Chart 0 (the largest) takes the declared names; chart K of a multi-part mesh
            // NAME_chartK_position.png / NAME_chartK_normal.png beside them.
            for (size_t c = 0; c < result.charts.size(); ++c) {
                fs::path positions = exportedPositions(args), normals = exportedNormals(args);
                if (c > 0) {
                    const std::string name = args.output.stem().string() + "_chart" + std::to_string(c);
                    positions = args.exportDir / (name + "_position.png");
                    normals = args.exportDir / (name + "_normal.png");
                    outputs.add(positions);
                    outputs.add(normals);
                }
                outputs.writeWith(positions, [&](const fs::path& staged) {
                    ngi::writePng(staged, toPng(result.charts[c].fullPositions, false));
                });
                outputs.writeWith(normals, [&](const fs::path& staged) {
                    ngi::writePng(staged, toPng(result.charts[c].fullNormals, true));
                });
            }
        }
        if (!args.exportMesh.empty()) {
            ngi::TriangleMesh all;  // every chart's full-resolution grid, in the input's coordinates
            for (const ngi::ChartBake& chart : result.charts) {
                // Normalized -> object space in double: far from the origin a float sum rounds.
                const ngi::TriangleMesh part = ngi::geometryImageMesh(chart.fullPositions);
                const uint32_t base = uint32_t(all.positions.size());
                for (const glm::dvec3& p : part.positions)
                    all.positions.push_back(glm::dvec3(result.asset.offset) + glm::dvec3(result.asset.scale) * p);
                for (const glm::uvec3& t : part.triangles) all.triangles.push_back(t + glm::uvec3(base));
            }
            outputs.writeWith(args.exportMesh, [&](const fs::path& staged) { ngi::writeMesh(staged, all); });
        }
    }

    // --json: the bake report with the rate control, the split choice, the network and the times.
    void writeSummary(double writeSeconds, double totalSeconds, size_t peak)
    {
        if (args.json.empty()) return;
        const ngi::ShippedNetwork* named = network.named;
        const std::vector<std::optional<ngi::nn::ResidualGainFit>>& gains = network.gains;
        nlohmann::json summary = ngi::bakeReportJson(result.report);
        summary["source"] = args.mesh.string();
        summary["output"] = args.output.string();
        summary["resolution"] = args.options.resolution;
        summary["storeResolution"] = result.asset.fullResolution() >> result.asset.charts[0].storedLevel;
        const double storedResolution = double(result.asset.fullResolution() >> result.asset.charts[0].storedLevel);
        summary["compressionRatio"] =
            double(args.options.resolution) * args.options.resolution / (storedResolution * storedResolution);
        summary["assetBytes"] = assetFile.size();
        // Bytes per chunk name (summed over charts), and "header": the header, the chunk table
        // and the alignment between payloads.
        std::map<std::string, uint64_t> chunkBytes;
        uint64_t payload = 0;
        for (const ngi::AssetChunkSize& chunk : ngi::assetChunkSizes(assetFile, args.output.string())) {
            chunkBytes[chunk.name] += chunk.bytes;
            payload += chunk.bytes;
        }
        chunkBytes["header"] = assetFile.size() - payload;
        for (const auto& [chunk, bytes] : chunkBytes) summary["chunkBytes"][chunk] = bytes;
        if (rate) {
            summary["rateControl"]["targetBytes"] = rate->targetBytes;
            summary["rateControl"]["storedLevel"] = rate->chosen.storedLevel;
            summary["rateControl"]["positionStep"] = rate->chosen.step;
            summary["rateControl"]["tangentScale"] = rate->chosen.tangentScale;
            summary["rateControl"]["stepGrade"] = rate->chosen.stepGrade;
            // The chosen restore's RMS distance to the input (normalized units), where measured.
            if (rate->chosen.inputError >= 0.0)
                summary["rateControl"]["rmsToInput"] = std::sqrt(rate->chosen.inputError);
            summary["rateControl"]["normalBits"] = args.normalBits;
            if (rate->color.present)
                summary["rateControl"]["color"] = {{"bytes", rate->color.bytes},
                                                   {"quality", rate->color.quality},
                                                   {"levelsCoarser", rate->color.levelsCoarser},
                                                   {"rms", rate->color.rms}};
            for (const ngi::RateCandidate& c : rate->candidates) {
                nlohmann::json j = {
                    {"storedLevel", c.storedLevel}, {"positionStep", c.step}, {"tangentScale", c.tangentScale},
                    {"stepGrade", c.stepGrade},     {"bytes", c.bytes},       {"rmsPointToPlane", std::sqrt(c.error)}};
                if (c.networkError >= 0.0)
                    j["network"] = {{"id", c.networkId}, {"rmsPointToPlane", std::sqrt(c.networkError)}};
                if (c.inputError >= 0.0) j["rmsToInput"] = std::sqrt(c.inputError);
                summary["rateControl"]["candidates"].push_back(std::move(j));
            }
        }
        size_t samples = 0;
        for (const ngi::AssetChart& c : result.asset.charts) samples += c.positions.size() + c.normals.size();
        if (splitRms) {
            summary["splitChoice"] = {{"splitRmsToInput", *splitRms},
                                      {"kept", keptSplit ? "split" : "one chart per component"}};
            if (oneChartRms)
                summary["splitChoice"]["oneChartRmsToInput"] = *oneChartRms;
            else
                summary["splitChoice"]["oneChartRefused"] = oneChartRefusal;
        }
        summary["chartCount"] = result.asset.charts.size();
        // Per chart: the residual gain the restore applies (1: no network for it) and its fit.
        for (size_t c = 0; c < result.asset.charts.size() && c < summary["charts"].size(); ++c) {
            summary["charts"][c]["residualGain"] = result.asset.charts[c].residualGain;
            if (gains[c])
                summary["charts"][c]["residualGainFit"] = {{"rmsCubic", gains[c]->rmsCubic},
                                                           {"rmsNetwork", gains[c]->rmsNetwork},
                                                           {"rmsGained", gains[c]->rmsGained}};
        }
        if (named) {
            summary["network"] = {{"id", named->network.name},
                                  {"hash", ngi::networkHashText(named->hash)},
                                  {"factor", named->network.scaleFactor},
                                  {"path", named->path.string()}};
            for (const ngi::AssetChart& c : result.asset.charts)
                summary["network"]["chartsRestored"].push_back(ngi::networkRestoresChart(named->network, c));
            summary["network"]["residualGainSeconds"] = gainSeconds;
        } else {
            summary["network"] = nullptr;
        }
        summary["geometryBytes"] = samples * sizeof(uint16_t);
        summary["seconds"]["read"] = readSeconds;
        summary["seconds"]["write"] = writeSeconds;
        summary["totalSeconds"] = totalSeconds;
        summary["peakMemoryBytes"] = peak;
        const std::string text = summary.dump(2) + "\n";
        outputs.write(args.json, std::span(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
    }
};

}  // namespace

int main(int argc, char** argv)
{
    if (ngi::isBatchCommand(argc, argv)) return ngi::runBatch(argc, argv);
    Arguments args;
    try {
        args = parseArguments(argc, argv);
    } catch (const UsageError& e) {
        if (*e.what()) std::fprintf(stderr, "ngi-bake: %s\n", e.what());
        std::fputs(kUsage, *e.what() ? stderr : stdout);
        return *e.what() ? 2 : 0;
    }
    try {
        SingleBake bake(std::move(args));
        bake.readInput();
        bake.bakeCharts();
        bake.findNetworks();
        bake.fitToBudget();
        bake.printRateControl();
        bake.nameNetwork();
        const auto writeStart = SingleBake::Clock::now();
        bake.writeOutputs();
        const double writeSeconds = std::chrono::duration<double>(SingleBake::Clock::now() - writeStart).count();
        const double totalSeconds = std::chrono::duration<double>(SingleBake::Clock::now() - bake.start).count();
        const size_t peak = ngi::peakResidentBytes();
        bake.writeSummary(writeSeconds, totalSeconds, peak);
        bake.outputs.commit();
        const ngi::Asset& asset = bake.result.asset;
        if (!bake.args.quiet)
            std::printf(
                "ngi-bake: wrote %s (%zu bytes, %zu chart%s, largest %ux%u stored of %u^2) in %.2f s total, peak "
                "memory %.0f MiB\n",
                bake.args.output.string().c_str(), bake.assetFile.size(), asset.charts.size(),
                asset.charts.size() == 1 ? "" : "s", asset.charts[0].storedSize(), asset.charts[0].storedSize(),
                asset.charts[0].fullResolution, totalSeconds, double(peak) / (1024.0 * 1024.0));
        return 0;
    } catch (const std::exception& e) {
        // `outputs` has removed its temporary files: every pre-existing file is unchanged.
        std::fprintf(stderr, "ngi-bake: error: %s\n", e.what());
        return 1;
    }
}
