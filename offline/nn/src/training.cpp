// Training data, patch sampling, loss and the Adam loop of the super-resolution network.
// Paper: "Neural Geometry Image-Based Representations with Optimal Transport", section 3.2
// (Eq. L_total = 0.5 L1 + 0.5 L_struct, Adam lr 5e-5, rotations and flips); conventions
// in ngi/nn/training.h.
#include "ngi/nn/training.h"

#include "ngi/asset.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/output_files.h"
#include "ngi/png_io.h"
#include "ngi/pyramid_codec.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace ngi::nn {
namespace {

torch::Tensor toTensor(const GeometryImage& image)
{
    torch::Tensor t = torch::empty({3, image.size, image.size}, torch::kFloat32);
    float* p = t.data_ptr<float>();
    const size_t plane = size_t(image.size) * image.size;
    for (size_t i = 0; i < plane; ++i)
        for (int c = 0; c < 3; ++c) p[c * plane + i] = image.texels[i][c];
    return t;
}

GeometryImage readGeometryPng(const std::filesystem::path& path, bool normals)
{
    const PngImage png = readPng(path);
    if (png.bitDepth != 16 || png.channels != 3)
        throw Error(path.string() + ": expected a 16-bit RGB geometry image, got " + std::to_string(png.bitDepth) +
                    "-bit with " + std::to_string(png.channels) + " channels");
    if (png.width != png.height || !isNestedGridSize(png.width))
        throw Error(path.string() + ": " + std::to_string(png.width) + "x" + std::to_string(png.height) +
                    " is not a square geometry image of 2^k + 1 samples per side");
    GeometryImage image(png.width);
    for (size_t i = 0; i < image.texels.size(); ++i) {
        glm::vec3 v;
        for (int c = 0; c < 3; ++c) v[c] = png.samples[i * 3 + c] / 65535.0f;
        if (normals) {
            v = v * 2.0f - 1.0f;
            const float len = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
            v = len > 0.0f ? v / len : glm::vec3(0.0f, 0.0f, 1.0f);
        }
        image.texels[i] = v;
    }
    return image;
}

uint32_t log2Exact(uint32_t f)
{
    uint32_t levels = 0;
    while ((1u << levels) < f) ++levels;
    if ((1u << levels) != f) throw Error("scale factor " + std::to_string(f) + " is not a power of two");
    return levels;
}

int64_t pickOrigin(int64_t range, float borderProbability, std::mt19937_64& rng)
{
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float r = u(rng);
    if (r < borderProbability) return 0;
    if (r < 2.0f * borderProbability) return range;
    return std::uniform_int_distribution<int64_t>(0, range)(rng);
}

// Metadata with the checkpoint step appended (replacing an earlier one).
std::string withStep(std::string metadata, uint64_t step, double loss)
{
    const size_t at = metadata.find(",\"step\":");
    if (at != std::string::npos)
        metadata.erase(at);
    else if (!metadata.empty() && metadata.back() == '}')
        metadata.pop_back();
    if (metadata.empty()) metadata = "{\"note\":\"ngi-train\"";
    char tail[96];
    std::snprintf(tail, sizeof tail, ",\"step\":%llu,\"loss\":%.6g}", static_cast<unsigned long long>(step), loss);
    return metadata + tail;
}

}  // namespace

void validateDecodedInputOptions(const DecodedInputOptions& o)
{
    for (uint32_t step : o.steps)
        if (step < 1 || step > kMaxPyramidStep)
            throw Error("decoded input step " + std::to_string(step) + " is outside [1, " +
                        std::to_string(kMaxPyramidStep) + "]");
    if (o.tangentScale > kMaxTangentScale)
        throw Error("decoded input tangent scale " + std::to_string(o.tangentScale) + " is outside [0, " +
                    std::to_string(kMaxTangentScale) + "]");
}

std::pair<GeometryImage, GeometryImage> decodedStoredLevel(const GeometryImage& positions, const GeometryImage& normals,
                                                           uint32_t step, uint32_t tangentScale)
{
    validateDecodedInputOptions({{step}, tangentScale});
    if (positions.size != normals.size || !isNestedGridSize(positions.size))
        throw Error("decoded input: " + std::to_string(positions.size) + " samples per side is not a 2^k + 1 level");
    // One chart storing this level at full resolution, coded exactly as ngi-bake's --target-bytes
    // codes it (pyramid positions, predicted normals with 0 residual bits): applyAssetCoding
    // leaves the samples a reader decodes.
    Asset asset;
    asset.coding = {.pyramid = true,
                    .progressive = true,
                    .positionStep = step,
                    .positionTangentScale = tangentScale,
                    .normalBits = 0};
    AssetChart chart;
    chart.fullResolution = positions.size - 1;
    chart.storedLevel = 0;
    storeGeometryImage(chart, positions, normals);
    asset.charts.push_back(std::move(chart));
    applyAssetCoding(asset);
    return {storedPositions(asset.charts[0]), storedNormals(asset.charts[0])};
}

TrainingImage makeTrainingImage(const std::string& name, const GeometryImage& positions, const GeometryImage& normals,
                                uint32_t scaleFactor, const DecodedInputOptions& decoded)
{
    if (positions.size != normals.size) throw Error(name + ": position and normal images differ in size");
    const uint32_t levels = log2Exact(scaleFactor);
    if (!isNestedGridSize(positions.size) || mipLevelCount(positions.size) <= levels + 1)
        throw Error(name + ": " + std::to_string(positions.size) + " samples per side is too small for x" +
                    std::to_string(scaleFactor));
    TrainingImage t;
    t.name = name;
    t.positions = toTensor(positions);
    t.normals = toTensor(normals);
    const GeometryImage coarsePositions = downsampleNested(positions, levels);
    const GeometryImage coarseNormals = downsampleNested(normals, levels);
    t.coarsePositions = toTensor(coarsePositions);
    t.coarseNormals = toTensor(coarseNormals);
    for (uint32_t step : decoded.steps) {
        const auto [p, n] = decodedStoredLevel(coarsePositions, coarseNormals, step, decoded.tangentScale);
        t.decodedPositions.push_back(toTensor(p));
        t.decodedNormals.push_back(toTensor(n));
    }
    return t;
}

std::vector<TrainingImage> loadTrainingSet(const std::filesystem::path& dir, uint32_t scaleFactor,
                                           const DecodedInputOptions& decoded)
{
    validateDecodedInputOptions(decoded);
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) throw Error(dir.string() + ": no such training data directory");
    // ngi-bake --export-full writes NAME_position.png + NAME_normal.png; the plural
    // spelling is accepted too.
    struct Pair {
        std::string name;
        std::filesystem::path positions, normals;
    };
    std::vector<Pair> pairs;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        const std::string file = entry.path().filename().string();
        for (const auto& [positionSuffix, normalSuffix] :
             {std::pair<std::string, std::string>{"_position.png", "_normal.png"}, {"_positions.png", "_normals.png"}})
            if (file.size() > positionSuffix.size() &&
                file.compare(file.size() - positionSuffix.size(), positionSuffix.size(), positionSuffix) == 0) {
                const std::string name = file.substr(0, file.size() - positionSuffix.size());
                pairs.push_back({name, entry.path(), dir / (name + normalSuffix)});
            }
    }
    if (pairs.empty())
        throw Error(dir.string() +
                    ": no NAME_position.png / NAME_normal.png geometry image pairs "
                    "(write them with ngi-bake --export-full)");
    std::sort(pairs.begin(), pairs.end(), [](const Pair& a, const Pair& b) { return a.positions < b.positions; });
    std::vector<TrainingImage> images;
    for (const Pair& pair : pairs) {
        const std::filesystem::path& positionsPath = pair.positions;
        const std::filesystem::path& normalsPath = pair.normals;
        if (!std::filesystem::exists(normalsPath))
            throw Error(normalsPath.string() + ": missing (every " + positionsPath.filename().string() +
                        " needs its normal image)");
        const GeometryImage positions = readGeometryPng(positionsPath, false);
        const GeometryImage normals = readGeometryPng(normalsPath, true);
        if (positions.size != normals.size)
            throw Error(normalsPath.string() + ": size differs from " + positionsPath.filename().string());
        images.push_back(makeTrainingImage(positionsPath.string(), positions, normals, scaleFactor, decoded));
    }
    return images;
}

int64_t lossWindowSize(const PatchOptions& o, uint32_t f)
{
    const int64_t full = int64_t(o.patchSamples - 1) * f + 1;
    const int64_t loss = full - 2 * int64_t(o.contextSamples) * f;
    if (o.patchSamples < 2 || loss < 1) throw Error("patch options: the context leaves no loss window");
    return loss;
}

PatchBatch samplePatches(const std::vector<TrainingImage>& images, uint32_t f, const PatchOptions& o,
                         std::mt19937_64& rng)
{
    if (images.empty()) throw Error("training: no images");
    const int64_t p = o.patchSamples, t = (p - 1) * f + 1, l = lossWindowSize(o, f);
    const int64_t interior = int64_t(o.contextSamples) * f;
    std::vector<torch::Tensor> positions, normals, targets, targetNormals;
    PatchBatch batch;
    batch.lossSize = l;
    for (uint32_t b = 0; b < o.batchSize; ++b) {
        const TrainingImage& image = images[std::uniform_int_distribution<size_t>(0, images.size() - 1)(rng)];
        const int64_t s = image.coarsePositions.size(1);
        if (s < p)
            throw Error(image.name + ": its " + std::to_string(s) + "-sample input level is smaller than a " +
                        std::to_string(p) + "-sample patch");
        std::array<int64_t, 2> window{}, origin{};
        for (int axis = 0; axis < 2; ++axis) {
            window[axis] = pickOrigin(s - p, o.borderProbability, rng);
            origin[axis] = window[axis] == 0 ? 0 : window[axis] == s - p ? t - l : interior;
        }
        auto crop = [](const torch::Tensor& x, int64_t y0, int64_t x0, int64_t n) {
            return x.narrow(1, y0, n).narrow(2, x0, n);
        };
        // Without variants no draw is made, so plain training keeps its random sequence.
        const torch::Tensor* inputPositions = &image.coarsePositions;
        const torch::Tensor* inputNormals = &image.coarseNormals;
        if (!image.decodedPositions.empty()) {
            const size_t v = std::uniform_int_distribution<size_t>(0, image.decodedPositions.size() - 1)(rng);
            inputPositions = &image.decodedPositions[v];
            inputNormals = &image.decodedNormals[v];
        }
        torch::Tensor pos = crop(*inputPositions, window[0], window[1], p);
        torch::Tensor nrm = crop(*inputNormals, window[0], window[1], p);
        torch::Tensor target = crop(image.positions, window[0] * f, window[1] * f, t);
        torch::Tensor targetNormal = crop(image.normals, window[0] * f, window[1] * f, t);
        // One of the 8 symmetries of the square: transpose, then vertical/horizontal flips.
        const unsigned symmetry = unsigned(rng() & 7u);
        auto apply = [&](torch::Tensor x) {
            if (symmetry & 1u) x = x.transpose(1, 2);
            if (symmetry & 2u) x = x.flip({1});
            if (symmetry & 4u) x = x.flip({2});
            return x;
        };
        if (symmetry & 1u) std::swap(origin[0], origin[1]);
        if (symmetry & 2u) origin[0] = t - l - origin[0];
        if (symmetry & 4u) origin[1] = t - l - origin[1];
        positions.push_back(apply(pos));
        normals.push_back(apply(nrm));
        targets.push_back(crop(apply(target), origin[0], origin[1], l));
        targetNormals.push_back(crop(apply(targetNormal), origin[0], origin[1], l));
        batch.lossOrigin.push_back(origin);
    }
    batch.positions = torch::stack(positions).contiguous();
    batch.normals = torch::stack(normals).contiguous();
    batch.target = torch::stack(targets).contiguous();
    batch.targetNormals = torch::stack(targetNormals).contiguous();
    return batch;
}

torch::Tensor pointToPlaneL1(const torch::Tensor& restored, const torch::Tensor& target,
                             const torch::Tensor& targetNormals)
{
    if (restored.sizes() != target.sizes() || target.sizes() != targetNormals.sizes() || target.dim() != 4 ||
        target.size(1) != 3)
        throw Error("point-to-plane loss: restored, target and normals must be B x 3 x H x W of one size");
    return ((restored - target) * targetNormals).sum(1).abs().mean();
}

LossTerms trainingLoss(SuperResolutionNet& net, const PatchBatch& batch, const MsSsimOptions& msSsimOptions,
                       double normalL1Weight)
{
    const torch::Tensor output = net->forward(batch.positions, batch.normals);
    std::vector<torch::Tensor> crops;
    for (size_t b = 0; b < batch.lossOrigin.size(); ++b)
        crops.push_back(output[int64_t(b)]
                            .narrow(1, batch.lossOrigin[b][0], batch.lossSize)
                            .narrow(2, batch.lossOrigin[b][1], batch.lossSize));
    const torch::Tensor restored = torch::stack(crops);
    const torch::Tensor l1 = (restored - batch.target).abs().mean();
    const torch::Tensor ms = msSsim(restored, batch.target, msSsimOptions);
    LossTerms terms;
    terms.total = 0.5 * l1 + 0.5 * (1.0 - ms);
    if (normalL1Weight > 0.0) {
        const torch::Tensor plane = pointToPlaneL1(restored, batch.target, batch.targetNormals);
        terms.total = terms.total + normalL1Weight * plane;
        terms.pointToPlaneL1 = plane.item<double>();
    }
    terms.l1 = l1.item<double>();
    terms.msSsim = ms.item<double>();
    return terms;
}

std::vector<RestoreError> evaluateRestore(SuperResolutionNet& net, const std::vector<TrainingImage>& images)
{
    torch::NoGradGuard noGrad;
    const int64_t f = net->layout().scaleFactor;
    std::vector<RestoreError> errors;
    for (const TrainingImage& image : images) {
        const torch::Tensor coarse = image.coarsePositions.unsqueeze(0);
        const torch::Tensor restored = net->forward(coarse, image.coarseNormals.unsqueeze(0))[0];
        const torch::Tensor bilinear = bilinearUpsample(coarse, f)[0];
        if (restored.sizes() != image.positions.sizes())
            throw Error(image.name + ": the network's output does not match the full image's size");
        RestoreError e;
        e.name = image.name;
        e.networkL1 = (restored - image.positions).abs().mean().item<double>();
        e.bilinearL1 = (bilinear - image.positions).abs().mean().item<double>();
        e.networkMax = (restored - image.positions).abs().max().item<double>();
        e.bilinearMax = (bilinear - image.positions).abs().max().item<double>();
        const torch::Tensor bicubic = cubicUpsample(coarse, f)[0];
        e.bicubicL1 = (bicubic - image.positions).abs().mean().item<double>();
        e.bicubicMax = (bicubic - image.positions).abs().max().item<double>();
        const torch::Tensor hermite = hermiteUpsample(coarse, image.coarseNormals.unsqueeze(0), f)[0];
        e.hermiteL1 = (hermite - image.positions).abs().mean().item<double>();
        e.hermiteMax = (hermite - image.positions).abs().max().item<double>();
        errors.push_back(e);
    }
    return errors;
}

NetworkWeights readCheckpoint(const std::filesystem::path& dir, uint64_t& step)
{
    const auto path = dir / "checkpoint.ngiw";
    if (!std::filesystem::exists(path)) throw Error(path.string() + ": no checkpoint to resume from");
    NetworkWeights weights = readNetworkWeights(path);
    const size_t at = weights.metadata.find("\"step\":");
    if (at == std::string::npos) throw Error(path.string() + ": checkpoint metadata has no step");
    step = std::strtoull(weights.metadata.c_str() + at + 7, nullptr, 10);
    return weights;
}

TrainProgress train(SuperResolutionNet& net, const std::vector<TrainingImage>& images, const TrainOptions& options,
                    const std::function<void(const TrainProgress&)>& progress)
{
    const uint32_t f = net->layout().scaleFactor;
    if (lossWindowSize(options.patches, f) < msSsimMinimumSize(options.msSsim))
        throw Error("training: the loss window of " + std::to_string(lossWindowSize(options.patches, f)) +
                    " samples is smaller than MS-SSIM's minimum of " +
                    std::to_string(msSsimMinimumSize(options.msSsim)) + " (increase --patch or reduce --context)");
    torch::optim::Adam optimizer(net->parameters(), torch::optim::AdamOptions(options.learningRate));
    TrainProgress state;
    state.totalSteps = options.steps;
    const auto optimizerPath = options.checkpointDirectory / "checkpoint.optim.pt";
    if (options.resume) {
        readCheckpoint(options.checkpointDirectory, state.step);
        try {
            torch::load(optimizer, optimizerPath.string());
        } catch (const c10::Error& e) {
            throw Error(optimizerPath.string() + ": cannot load the optimizer state (missing or corrupt)");
        }
    }
    state.firstStep = state.step;
    // Patch order depends on the seed and the step resumed from (not bit-identical to an
    // uninterrupted run, but deterministic).
    std::mt19937_64 rng(options.seed * 0x9E3779B97F4A7C15ull + state.step);
    torch::manual_seed(options.seed + state.step);
    const auto start = std::chrono::steady_clock::now();

    auto checkpoint = [&]() {
        if (options.checkpointDirectory.empty()) return;
        std::filesystem::create_directories(options.checkpointDirectory);
        // Through the one output stager: never renamed over a link or a device, and an
        // interrupted run leaves no temporary file.
        OutputFiles optimizerFile({optimizerPath});
        optimizerFile.writeWith(optimizerPath, [&](const std::filesystem::path& staged) {
            try {
                torch::save(optimizer, staged.string());
            } catch (const c10::Error&) {
                throw Error(staged.string() + ": cannot write the optimizer state");
            }
        });
        optimizerFile.commit();
        NetworkWeights weights = net->exportWeights();
        weights.metadata = withStep(weights.metadata, state.step, state.loss);
        writeNetworkWeights(weights, options.checkpointDirectory / "checkpoint.ngiw");
    };

    net->train();
    while (state.step < options.steps) {
        const PatchBatch batch = samplePatches(images, f, options.patches, rng);
        optimizer.zero_grad();
        const LossTerms terms = trainingLoss(net, batch, options.msSsim, options.normalL1Weight);
        (terms.total * kOptimizerLossScale).backward();
        optimizer.step();
        net->projectConstrainedWeights();
        ++state.step;
        state.loss = terms.total.item<double>();
        state.l1 = terms.l1;
        state.msSsim = terms.msSsim;
        state.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (options.validate && options.validateEvery > 0 &&
            (state.step % options.validateEvery == 0 || state.step == options.steps)) {
            torch::NoGradGuard noGrad;
            state.validation = options.validate(net->exportWeights());
        }
        if (options.checkpointEvery > 0 && (state.step % options.checkpointEvery == 0 || state.step == options.steps))
            checkpoint();
        if (progress) progress(state);
    }
    return state;
}

}  // namespace ngi::nn
