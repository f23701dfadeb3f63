// ngi-train: trains the geometry-image super-resolution network (paper section 3.2) with
// libtorch on CPU and exports the weights file the engine loads (ngi/network_weights.h).
//
//   ngi-train --data DIR [--scale 8] [--steps 20000] [--checkpoint-dir DIR] [--resume]
//             [--export model.ngiw] [architecture and patch options, see --help]
//
// DIR holds NAME_position.png / NAME_normal.png pairs from `ngi-bake --export-full DIR`
// (train only on the docs/DESIGN.md training set).
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/network_weights.h"
#include "ngi/output_files.h"
#include "ngi/nn/architecture.h"
#include "ngi/nn/torch_network.h"
#include "ngi/nn/training.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

namespace {

const char* kUsage = R"(usage: ngi-train --data DIR [options]
  --data DIR              training geometry images: NAME_position.png + NAME_normal.png (16-bit RGB,
                          as written by ngi-bake --export-full)
  --scale N               upsampling factor 2, 4, 8 (default), 16 or 32: one model per factor
                          (x32 upsamples in two sub-pixel stages, ngi/nn/architecture.h)
  --steps N               total optimizer steps (default 20000)
  --batch N               patches per step (default 8)
  --patch N               coarse samples per patch side (default 37)
  --context N             coarse context samples outside the loss window (default 6)
  --decoded-steps LIST    train on decoded inputs: comma-separated position steps (1/65536 of the box,
                          each in [1, 4096]); the input level is quantized to u16 and coded + decoded
                          by the asset codec at each step (normals predicted from the decoded
                          positions), one variant per step, a random one per patch (default: none,
                          the plain level)
  --decoded-tangent-scale T  the codec's tangent scale of those variants, 0..16 (default 0)
  --val-decoded-step Q    validation inputs decoded at step Q (default: the largest --decoded-steps)
  --lr X                  Adam learning rate (default 5e-5)
  --normal-l1 W           add W x the point-to-plane L1 (the error along the target's normal, the
                          part that moves the surface) to the paper's loss (default 0: the paper's)
  --seed N                seed of initialization and patch sampling (default 1)
  --threads N             libtorch intra-op threads (default 2)
  --features N --branch-convs N --heads N --window N --res-blocks N --upsample-features N
                          architecture (defaults 32, 2, 4, 3, 2, 16; see ngi/nn/architecture.h)
  --skip KIND             the skip's upsampling: hermite (default: Catmull-Rom tangents projected
                          on the stored normals' tangent planes), cubic (Catmull-Rom) or bilinear
  --checkpoint-dir DIR    write DIR/checkpoint.ngiw + DIR/checkpoint.optim.pt
  --checkpoint-every N    steps between checkpoints (default 500)
  --resume                continue from --checkpoint-dir (architecture from the checkpoint)
  --init NET.ngiw         start from a trained network of the same architecture, possibly of another
                          factor (transfer learning, e.g. x2 from the shipped x4): every layer of the
                          same shape is copied, the sub-pixel convolution takes the donor's channels
                          at the shared sub-sample positions (ngi/nn/architecture.h)
  --val-data DIR          validation geometry images (same layout as --data): the progress bar's
                          'val' is their mean restore L1 error (x1e-4) every --val-every steps,
                          and a per-image table network vs bilinear is printed at the end
  --val-every N           steps between validations (default 1000)
  --export FILE           write the trained weights file (.ngiw) at the end
  --name ID               network id stored in the weights file (default ngi-sr-xN)
)";

struct Arguments {
    std::string data, validationData, checkpointDir, exportPath, name, initPath;
    bool resume = false;
    uint32_t threads = 2;
    ngi::nn::DecodedInputOptions decoded;
    uint32_t validationStep = 0;  // 0: the largest decoded step
    ngi::nn::SuperResolutionConfig config;
    ngi::nn::TrainOptions train;
};

// The largest count a size flag takes (features, patch samples, batch, threads, ...) and the
// largest step count: beyond them a value is a typo, not a plan.
constexpr uint64_t kMaxCount = 1u << 20;
constexpr uint64_t kMaxSteps = uint64_t(1) << 40;

uint64_t parseNumber(const std::string& flag, const std::string& text, uint64_t max = kMaxCount, uint64_t min = 0)
{
    return ngi::parseIntegerOptionInRange(flag, text, min, max);
}

Arguments parse(int argc, char** argv)
{
    Arguments a;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        const std::string& flag = args.flag();
        auto u32 = [&]() { return uint32_t(parseNumber(flag, args.value())); };  // kMaxCount fits 32 bits
        if (args.is("--help", "-h")) {
            std::fputs(kUsage, stdout);
            std::exit(0);
        } else if (args.is("--resume"))
            a.resume = true;
        else if (args.is("--data"))
            a.data = args.value();
        else if (args.is("--scale"))
            a.config.scaleFactor = uint32_t(parseNumber(flag, args.value(), 1024, 2));
        else if (args.is("--steps"))
            a.train.steps = parseNumber(flag, args.value(), kMaxSteps);
        else if (args.is("--batch"))
            a.train.patches.batchSize = u32();
        else if (args.is("--patch"))
            a.train.patches.patchSamples = u32();
        else if (args.is("--context"))
            a.train.patches.contextSamples = u32();
        else if (args.is("--decoded-steps")) {
            const std::string list = args.value();
            size_t at = 0;
            while (true) {
                const size_t comma = list.find(',', at);
                const std::string item = list.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
                a.decoded.steps.push_back(uint32_t(parseNumber(flag, item)));
                if (comma == std::string::npos) break;
                at = comma + 1;
            }
        } else if (args.is("--decoded-tangent-scale"))
            a.decoded.tangentScale = u32();
        else if (args.is("--val-decoded-step"))
            a.validationStep = u32();
        else if (args.is("--lr"))
            a.train.learningRate = ngi::parseFloatOption(flag, args.value());
        else if (args.is("--normal-l1")) {
            const char* v = args.value().c_str();
            char* end = nullptr;
            a.train.normalL1Weight = std::strtod(v, &end);
            if (end == v || *end != '\0') throw ngi::Error(std::string("--normal-l1: '") + v + "' is not a number");
        } else if (args.is("--seed"))
            a.train.seed = parseNumber(flag, args.value(), UINT64_MAX);
        else if (args.is("--threads"))
            a.threads = u32();
        else if (args.is("--features"))
            a.config.features = u32();
        else if (args.is("--branch-convs"))
            a.config.branchConvs = u32();
        else if (args.is("--heads"))
            a.config.attentionHeads = u32();
        else if (args.is("--window"))
            a.config.attentionWindow = u32();
        else if (args.is("--res-blocks"))
            a.config.resBlocks = u32();
        else if (args.is("--skip")) {
            const std::string kind = args.value();
            if (kind == "hermite")
                a.config.skip = ngi::LayerKind::HermiteSkip;
            else if (kind == "cubic")
                a.config.skip = ngi::LayerKind::CubicSkip;
            else if (kind == "bilinear")
                a.config.skip = ngi::LayerKind::BilinearSkip;
            else
                throw ngi::Error("--skip: '" + kind + "' is not hermite, cubic or bilinear");
        } else if (args.is("--upsample-features"))
            a.config.upsampleFeatures = u32();
        else if (args.is("--checkpoint-dir"))
            a.checkpointDir = args.value();
        else if (args.is("--checkpoint-every"))
            a.train.checkpointEvery = parseNumber(flag, args.value(), kMaxSteps);
        else if (args.is("--export"))
            a.exportPath = ngi::parseOutputPathOption(flag, args.value());
        else if (args.is("--val-data"))
            a.validationData = args.value();
        else if (args.is("--val-every"))
            a.train.validateEvery = parseNumber(flag, args.value(), kMaxSteps);
        else if (args.is("--name"))
            a.name = args.value();
        else if (args.is("--init"))
            a.initPath = args.value();
        else
            throw args.unknown();
    }
    if (a.data.empty()) throw ngi::Error("--data DIR is required (see --help)");
    if (a.resume && a.checkpointDir.empty()) throw ngi::Error("--resume needs --checkpoint-dir");
    if (a.resume && !a.initPath.empty())
        throw ngi::Error("--init and --resume exclude each other: a resumed run continues its checkpoint");
    if (!(a.train.learningRate > 0.0)) throw ngi::Error("--lr must be positive");
    if (!(a.train.normalL1Weight >= 0.0 && a.train.normalL1Weight <= 1e3))
        throw ngi::Error("--normal-l1 must be in [0, 1000]");
    try {
        ngi::nn::validateDecodedInputOptions(a.decoded);
        if (a.validationStep) ngi::nn::validateDecodedInputOptions({{a.validationStep}, a.decoded.tangentScale});
    } catch (const ngi::Error& e) {
        throw ngi::Error(std::string("--decoded-steps / --decoded-tangent-scale / --val-decoded-step: ") + e.what());
    }
    if (a.validationStep && a.decoded.steps.empty()) throw ngi::Error("--val-decoded-step needs --decoded-steps");
    if (!a.decoded.steps.empty() && !a.validationStep)
        a.validationStep = *std::max_element(a.decoded.steps.begin(), a.decoded.steps.end());
    return a;
}

std::string clock(double seconds)
{
    if (!std::isfinite(seconds) || seconds < 0) return "--:--:--";
    const long s = long(seconds + 0.5);
    char text[32];
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
    return text;
}

// One progress line, redrawn in place on stderr at most ~4 times a second.
void printProgress(const ngi::nn::TrainProgress& p)
{
    static double lastPrint = -1.0;
    const bool last = p.step == p.totalSteps;
    if (!last && p.seconds - lastPrint < 0.25) return;
    lastPrint = p.seconds;
    const uint64_t done = p.step - p.firstStep, todo = p.totalSteps - p.step;
    const double rate = p.seconds > 0 ? double(done) / p.seconds : 0.0;
    const int width = 24, filled = int(width * double(p.step) / double(std::max<uint64_t>(p.totalSteps, 1)));
    std::string bar(size_t(filled), '#');
    bar.resize(width, '.');
    char validation[32] = "n/a";
    if (std::isfinite(p.validation)) std::snprintf(validation, sizeof validation, "%.4g", p.validation);
    std::fprintf(stderr, "\r[%s] step %llu/%llu  loss %.5f (L1 %.2e, MS-SSIM %.5f)  val %s  %.2f step/s  ETA %s ",
                 bar.c_str(), static_cast<unsigned long long>(p.step), static_cast<unsigned long long>(p.totalSteps),
                 p.loss, p.l1, p.msSsim, validation, rate, clock(rate > 0 ? double(todo) / rate : NAN).c_str());
    if (last) std::fputc('\n', stderr);
    std::fflush(stderr);
}

}  // namespace

int main(int argc, char** argv)
{
    try {
        Arguments a = parse(argc, argv);
        // --export is checked now, not after hours of training: its directory exists, it is not
        // a directory, and it is not the checkpoint this run reads or rewrites.
        std::vector<std::filesystem::path> checkpoint;
        if (!a.checkpointDir.empty())
            checkpoint = {std::filesystem::path(a.checkpointDir) / "checkpoint.ngiw",
                          std::filesystem::path(a.checkpointDir) / "checkpoint.optim.pt"};
        ngi::OutputFiles outputs({a.exportPath}, checkpoint);
        torch::set_num_threads(int(a.threads));
        a.train.checkpointDirectory = a.checkpointDir;
        a.train.resume = a.resume;

        ngi::NetworkWeights initial;
        bool initialize = true;
        if (a.resume) {
            uint64_t step = 0;
            initial = ngi::nn::readCheckpoint(a.checkpointDir, step);
            initialize = false;
            std::fprintf(stderr, "resuming %s at step %llu\n", initial.name.c_str(),
                         static_cast<unsigned long long>(step));
        } else {
            initial = ngi::nn::buildSuperResolutionNetwork(
                a.config, a.name.empty() ? "ngi-sr-x" + std::to_string(a.config.scaleFactor) : a.name);
        }
        // Read now, not after the training set loads: a bad --init file fails at once.
        const ngi::NetworkWeights donor =
            a.initPath.empty() ? ngi::NetworkWeights{} : ngi::readNetworkWeights(a.initPath);
        const uint32_t scale = initial.scaleFactor;
        const std::vector<ngi::nn::TrainingImage> images = ngi::nn::loadTrainingSet(a.data, scale, a.decoded);
        if (!a.decoded.steps.empty()) {
            std::string steps;
            for (uint32_t q : a.decoded.steps) steps += (steps.empty() ? "" : ",") + std::to_string(q);
            std::fprintf(stderr, "inputs decoded at steps %s (tangent scale %u); validation at step %u\n",
                         steps.c_str(), a.decoded.tangentScale, a.validationStep);
        }
        std::fprintf(
            stderr,
            "%zu training geometry images from %s; network %s (%zu parameters, %.2f GFLOP per %u->%u restore)\n",
            images.size(), a.data.c_str(), initial.metadata.c_str(), initial.parameters.size(),
            2e-9 * double(ngi::networkMultiplyAdds(initial, 1024 / scale + 1)), 1024 / scale, 1024);

        ngi::nn::SuperResolutionNet net(initial, initialize, a.train.seed);
        if (!a.initPath.empty()) {
            // The seed's initialization stays for any layer the donor cannot supply.
            ngi::NetworkWeights start = net->exportWeights();
            const size_t copied = ngi::nn::transferParameters(start, donor);
            net = ngi::nn::SuperResolutionNet(start, false, a.train.seed);
            std::fprintf(stderr, "initialized from %s (%s, x%u): %zu convolutions copied\n", a.initPath.c_str(),
                         donor.name.c_str(), donor.scaleFactor, copied);
        }
        // Validation hook. Today: the mean whole-image restore L1 of --val-data. Once
        // ngi-eval exists: the Chamfer distance of one development mesh restored with the
        // current weights (docs/DESIGN.md "Metrics"), set here the same way.
        std::vector<ngi::nn::TrainingImage> validation;
        if (!a.validationData.empty()) {
            // With decoded inputs the validation restores the input decoded at one step, as an
            // asset at that step gives it (the table's baselines upsample the same input).
            validation = ngi::nn::loadTrainingSet(
                a.validationData, scale,
                a.decoded.steps.empty() ? ngi::nn::DecodedInputOptions{}
                                        : ngi::nn::DecodedInputOptions{{a.validationStep}, a.decoded.tangentScale});
            for (ngi::nn::TrainingImage& v : validation)
                if (!v.decodedPositions.empty()) {
                    v.coarsePositions = v.decodedPositions[0];
                    v.coarseNormals = v.decodedNormals[0];
                    v.decodedPositions.clear();
                    v.decodedNormals.clear();
                }
            a.train.validate = [&](const ngi::NetworkWeights& weights) {
                ngi::nn::SuperResolutionNet copy(weights, false);
                double sum = 0.0;
                for (const auto& e : ngi::nn::evaluateRestore(copy, validation)) sum += e.networkL1;
                return 1e4 * sum / double(validation.size());
            };
        }
        const ngi::nn::TrainProgress last = ngi::nn::train(net, images, a.train, printProgress);
        std::fprintf(stderr, "trained to step %llu in %s (loss %.5f)\n", static_cast<unsigned long long>(last.step),
                     clock(last.seconds).c_str(), last.loss);
        if (!validation.empty()) {
            // cubic: Catmull-Rom (ngi-eval's bicubic baseline); hermite: the default skip alone.
            std::printf("%-40s %12s %12s %12s %12s %9s %9s %9s %9s\n", "validation image", "net L1 e-4", "bilin L1",
                        "cubic L1", "hermite L1", "net max", "bilin max", "cubic max", "herm max");
            for (const auto& e : ngi::nn::evaluateRestore(net, validation))
                std::printf("%-40s %12.3f %12.3f %12.3f %12.3f %9.2e %9.2e %9.2e %9.2e\n", e.name.c_str(),
                            1e4 * e.networkL1, 1e4 * e.bilinearL1, 1e4 * e.bicubicL1, 1e4 * e.hermiteL1, e.networkMax,
                            e.bilinearMax, e.bicubicMax, e.hermiteMax);
        }
        if (!a.exportPath.empty()) {
            ngi::NetworkWeights weights = net->exportWeights();
            if (!a.name.empty()) weights.name = a.name;
            outputs.writeWith(a.exportPath,
                              [&](const std::filesystem::path& staged) { ngi::writeNetworkWeights(weights, staged); });
            outputs.commit();
            std::fprintf(stderr, "wrote %s (%zu parameters, hash %016llx)\n", a.exportPath.c_str(),
                         weights.parameters.size(), static_cast<unsigned long long>(ngi::networkHash(weights)));
        }
        return 0;
    } catch (const ngi::Error& e) {
        std::fprintf(stderr, "\nngi-train: %s\n", e.what());
    } catch (const c10::Error& e) {
        std::fprintf(stderr, "\nngi-train: libtorch error: %s\n", e.what_without_backtrace());
    } catch (const std::exception& e) {
        std::fprintf(stderr, "\nngi-train: %s\n", e.what());
    }
    return 1;
}
