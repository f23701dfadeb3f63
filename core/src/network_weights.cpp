// The super-resolution network's weights file: validation, writer, validating reader.
// Layout, op semantics and version history are documented in ngi/network_weights.h.
#include "ngi/network_weights.h"

#include "ngi/asset.h"
#include "byte_stream.h"
#include "crc32.h"
#include "ngi/error.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

static_assert(std::endian::native == std::endian::little, "ngi weights files are little-endian");

namespace ngi {
namespace {

constexpr uint8_t kMagic[8] = {0x89, 'N', 'G', 'W', '\r', '\n', 0x1a, '\n'};
constexpr size_t kHeaderBytes = 32;
constexpr size_t kLayerBytes = 64;
constexpr uint32_t kMaxTensors = kMaxNetworkLayers + 2;  // single assignment: one per layer + the inputs
constexpr uint32_t kMaxString = 1u << 20;
constexpr uint32_t kMaxFactor = 64;

using detail::crc32Of;

bool isPowerOfTwo(uint32_t v) { return v != 0 && (v & (v - 1)) == 0; }

using Writer = detail::ByteWriter;

struct Reader : detail::ByteReader {
    std::string getString(const char* what) { return ByteReader::getString(what, kMaxString); }
};

std::string layerName(size_t index) { return "layer " + std::to_string(index); }

std::string layerLimitMessage(uint64_t layers)
{
    return "the network has " + std::to_string(layers) + " layers; the limit is " + std::to_string(kMaxNetworkLayers) +
        " (kMaxNetworkLayers)";
}

std::string parameterLimitMessage(uint64_t parameters)
{
    return "the network has " + std::to_string(parameters) + " parameters; the limit is " +
        std::to_string(kMaxNetworkParameters) + " (kMaxNetworkParameters)";
}

std::string figure(double v)
{
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", v);
    return text;
}

}  // namespace

std::string networkLabel(const NetworkWeights& network)
{
    if (!network.source.empty()) return network.source;
    return network.name.empty() ? "network" : "network '" + network.name + "'";
}

NetworkFigures networkFigures(const NetworkWeights& net, const std::vector<TensorShape>& shape)
{
    NetworkFigures f;
    f.layers = uint32_t(net.layers.size());
    f.parameters = net.parameters.size();
    const double scale = double(net.scaleFactor);
    auto samplesPerOutputSample = [&](uint32_t gridFactor) { return (gridFactor / scale) * (gridFactor / scale); };
    for (const TensorShape& t : shape) {
        f.maxChannels = std::max(f.maxChannels, t.channels);
        if (t.gridFactor) f.activationsPerOutputSample += t.channels * samplesPerOutputSample(t.gridFactor);
    }
    for (const NetworkLayer& l : net.layers) {
        const double samples = samplesPerOutputSample(shape[l.inputs[0]].gridFactor);
        if (l.kind == LayerKind::Conv)
            f.multiplyAddsPerOutputSample += samples * l.outChannels * l.inChannels * l.kernelSize * l.kernelSize;
        else if (l.kind == LayerKind::NeighborhoodCrossAttention)
            f.multiplyAddsPerOutputSample += samples * 2.0 * l.inChannels * l.kernelSize * l.kernelSize;
    }
    return f;
}

std::vector<TensorShape> validateNetwork(const NetworkWeights& net, const std::string& where)
{
    auto fail = [&](const std::string& p) -> void { throw Error(where + ": " + p); };
    if (!isPowerOfTwo(net.scaleFactor) || net.scaleFactor < 2 || net.scaleFactor > kMaxFactor)
        fail("scale factor " + std::to_string(net.scaleFactor) + " is not a power of two in [2, 64]");
    if (net.layers.empty()) fail("the network has no layers");
    if (net.layers.size() > kMaxNetworkLayers) fail(layerLimitMessage(net.layers.size()));
    if (net.tensorCount < 3 || net.tensorCount > kMaxTensors)
        fail("tensor count " + std::to_string(net.tensorCount) + " is outside [3, " + std::to_string(kMaxTensors) +
             "] (each layer writes one new tensor)");
    if (net.parameters.size() > kMaxNetworkParameters) fail(parameterLimitMessage(net.parameters.size()));
    for (float p : net.parameters)
        if (!std::isfinite(p)) fail("a parameter is not finite");

    std::vector<TensorShape> shape(net.tensorCount);
    shape[kPositionInputTensor] = {3, 1};
    shape[kNormalInputTensor] = {3, 1};
    auto defined = [&](uint32_t id) { return id < net.tensorCount && shape[id].gridFactor != 0; };

    for (size_t li = 0; li < net.layers.size(); ++li) {
        const NetworkLayer& l = net.layers[li];
        const std::string at = layerName(li) + ": ";
        if (l.output >= net.tensorCount) fail(at + "output tensor id is out of range");
        if (shape[l.output].gridFactor != 0) fail(at + "output tensor is written twice");
        if (!defined(l.inputs[0])) fail(at + "input tensor is not defined before use");
        const TensorShape in = shape[l.inputs[0]];
        if (l.inChannels != in.channels)
            fail(at + "declares " + std::to_string(l.inChannels) + " input channels, its input has " +
                 std::to_string(in.channels));
        if (l.outChannels == 0) fail(at + "has no output channels");
        if (l.outChannels > kMaxNetworkChannels)
            fail(at + "has " + std::to_string(l.outChannels) + " output channels; the limit is " +
                 std::to_string(kMaxNetworkChannels) + " (kMaxNetworkChannels)");
        TensorShape out{l.outChannels, in.gridFactor};
        switch (l.kind) {
        case LayerKind::Conv: {
            if (l.kernelSize != 1 && l.kernelSize != 3) fail(at + "convolution kernel is not 1x1 or 3x3");
            if (l.padding != Padding::Zero && l.padding != Padding::Replicate) fail(at + "unknown padding mode");
            if (l.activation != Activation::None && l.activation != Activation::ReLU &&
                l.activation != Activation::LeakyReLU)
                fail(at + "unknown activation");
            if (!std::isfinite(l.activationSlope)) fail(at + "activation slope is not finite");
            const uint64_t weights = uint64_t(l.outChannels) * l.inChannels * l.kernelSize * l.kernelSize;
            if (uint64_t(l.weightOffset) + weights > net.parameters.size() ||
                uint64_t(l.biasOffset) + l.outChannels > net.parameters.size())
                fail(at + "weights or biases lie outside the parameter array");
            if (l.inputs[1] != kNoTensor) {
                if (!defined(l.inputs[1])) fail(at + "residual tensor is not defined before use");
                if (shape[l.inputs[1]].channels != l.outChannels || shape[l.inputs[1]].gridFactor != in.gridFactor)
                    fail(at + "residual tensor's shape differs from the output's");
            }
            if (l.inputs[2] != kNoTensor) fail(at + "convolution has a third input");
            break;
        }
        case LayerKind::NeighborhoodCrossAttention: {
            for (int k = 1; k < 3; ++k) {
                if (!defined(l.inputs[k])) fail(at + "key/value tensor is not defined before use");
                if (shape[l.inputs[k]].channels != in.channels || shape[l.inputs[k]].gridFactor != in.gridFactor)
                    fail(at + "query, key and value shapes differ");
            }
            if (l.outChannels != l.inChannels) fail(at + "attention must keep the channel count");
            if (l.heads == 0 || l.inChannels % l.heads != 0) fail(at + "head count does not divide the channels");
            if (l.kernelSize % 2 == 0 || l.kernelSize > 15) fail(at + "attention window is not odd and <= 15");
            if (!std::isfinite(l.attentionScale)) fail(at + "attention scale is not finite");
            break;
        }
        case LayerKind::PixelShuffle: {
            if (!isPowerOfTwo(l.factor) || l.factor < 2 || l.factor > kMaxFactor)
                fail(at + "pixel shuffle factor is not a power of two in [2, 64]");
            if (uint64_t(l.outChannels) * l.factor * l.factor != l.inChannels)
                fail(at + "pixel shuffle input channels are not output channels * factor^2");
            if (l.inputs[1] != kNoTensor || l.inputs[2] != kNoTensor) fail(at + "pixel shuffle has extra inputs");
            out.gridFactor = in.gridFactor * l.factor;
            break;
        }
        case LayerKind::BilinearSkip:
        case LayerKind::CubicSkip:
        case LayerKind::HermiteSkip: {
            if (!isPowerOfTwo(l.factor) || l.factor < 2 || l.factor > kMaxFactor)
                fail(at + "skip upsampling factor is not a power of two in [2, 64]");
            if (!defined(l.inputs[1])) fail(at + "fine tensor is not defined before use");
            out.gridFactor = in.gridFactor * l.factor;
            if (shape[l.inputs[1]].channels != l.inChannels || shape[l.inputs[1]].gridFactor != out.gridFactor)
                fail(at + "fine tensor's shape does not match the upsampled coarse tensor");
            if (l.outChannels != l.inChannels) fail(at + "skip must keep the channel count");
            if (l.kind == LayerKind::HermiteSkip) {
                if (!defined(l.inputs[2])) fail(at + "normal tensor is not defined before use");
                if (l.inChannels != 3 || shape[l.inputs[2]].channels != 3 ||
                    shape[l.inputs[2]].gridFactor != in.gridFactor)
                    fail(at + "Hermite skip needs 3-channel positions and normals on the same grid");
            } else if (l.inputs[2] != kNoTensor) {
                fail(at + "skip has a third input");
            }
            break;
        }
        default: fail(at + "unknown layer kind " + std::to_string(uint32_t(l.kind)));
        }
        if (out.gridFactor > kMaxFactor) fail(at + "grid factor exceeds 64");
        shape[l.output] = out;
    }
    if (!defined(net.outputTensor)) fail("output tensor is not produced by any layer");
    if (shape[net.outputTensor].channels != 3 || shape[net.outputTensor].gridFactor != net.scaleFactor)
        fail("output tensor is not 3 channels at the network's scale factor");
    const NetworkFigures figures = networkFigures(net, shape);
    if (figures.multiplyAddsPerOutputSample > kMaxMultiplyAddsPerOutputSample)
        fail("the network costs " + figure(figures.multiplyAddsPerOutputSample) +
             " multiply-adds per output sample; the limit is " + figure(kMaxMultiplyAddsPerOutputSample) +
             " (kMaxMultiplyAddsPerOutputSample)");
    if (figures.activationsPerOutputSample > kMaxActivationsPerOutputSample)
        fail("the network's tensors hold " + figure(figures.activationsPerOutputSample) +
             " values per output sample; the limit is " + figure(kMaxActivationsPerOutputSample) +
             " (kMaxActivationsPerOutputSample)");
    return shape;
}

std::vector<uint8_t> serializeNetworkWeights(const NetworkWeights& net)
{
    const std::string where = net.name.empty() ? "network weights" : net.name;
    validateNetwork(net, where);
    if (net.name.size() > kMaxString || net.metadata.size() > kMaxString)
        throw Error(where + ": name or metadata is longer than 1 MiB");

    Writer body;
    body.put<uint32_t>(net.scaleFactor);
    body.put<uint32_t>(net.tensorCount);
    body.put<uint32_t>(net.outputTensor);
    body.put<uint32_t>(uint32_t(net.layers.size()));
    body.put<uint64_t>(net.parameters.size());
    body.putString(net.name);
    body.putString(net.metadata);
    while (body.bytes.size() % 4) body.put<uint8_t>(0);
    for (const NetworkLayer& l : net.layers) {
        body.put<uint32_t>(uint32_t(l.kind));
        for (uint32_t id : l.inputs) body.put<uint32_t>(id);
        body.put<uint32_t>(l.output);
        body.put<uint32_t>(l.inChannels);
        body.put<uint32_t>(l.outChannels);
        body.put<uint32_t>(l.kernelSize);
        body.put<uint32_t>(uint32_t(l.padding));
        body.put<uint32_t>(uint32_t(l.activation));
        body.put<float>(l.activationSlope);
        body.put<uint32_t>(l.heads);
        body.put<float>(l.attentionScale);
        body.put<uint32_t>(l.factor);
        body.put<uint32_t>(l.weightOffset);
        body.put<uint32_t>(l.biasOffset);
    }
    const size_t at = body.bytes.size();
    body.bytes.resize(at + net.parameters.size() * sizeof(float));
    if (!net.parameters.empty())
        std::memcpy(body.bytes.data() + at, net.parameters.data(), net.parameters.size() * sizeof(float));

    Writer file;
    file.bytes.assign(kMagic, kMagic + 8);
    file.put<uint32_t>(kNetworkWeightsVersion);
    file.put<uint32_t>(0);
    file.put<uint64_t>(body.bytes.size());
    file.put<uint32_t>(crc32Of(body.bytes));
    file.put<uint32_t>(0);
    file.bytes.insert(file.bytes.end(), body.bytes.begin(), body.bytes.end());
    return file.bytes;
}

NetworkWeights parseNetworkWeights(std::span<const uint8_t> bytes, const std::string& name)
{
    Reader h{bytes, 0, name};
    if (bytes.size() < 8 || std::memcmp(bytes.data(), kMagic, 8) != 0)
        h.fail(bytes.size() < 8 ? "not an ngi weights file (too short)" : "not an ngi weights file (bad magic bytes)");
    h.at = 8;
    const uint32_t version = h.get<uint32_t>("header");
    if (version != kNetworkWeightsVersion)
        h.fail("unsupported weights format version " + std::to_string(version) + " (this build reads version " +
               std::to_string(kNetworkWeightsVersion) + ")");
    if (h.get<uint32_t>("header") != 0) h.fail("reserved header field is not zero");
    const uint64_t bodyBytes = h.get<uint64_t>("header");
    const uint32_t crc = h.get<uint32_t>("header");
    if (h.get<uint32_t>("header") != 0) h.fail("reserved header field is not zero");
    if (bodyBytes != bytes.size() - kHeaderBytes)
        h.fail("file is " + std::to_string(bytes.size()) + " bytes but its header declares " +
               std::to_string(bodyBytes + kHeaderBytes) + " (truncated or padded)");
    const std::span<const uint8_t> bodySpan = bytes.subspan(kHeaderBytes);
    if (crc32Of(bodySpan) != crc) h.fail("body fails its CRC32 check (corrupt file)");

    Reader r{bodySpan, 0, name};
    NetworkWeights net;
    net.scaleFactor = r.get<uint32_t>("body");
    net.tensorCount = r.get<uint32_t>("body");
    net.outputTensor = r.get<uint32_t>("body");
    const uint32_t layerCount = r.get<uint32_t>("body");
    const uint64_t parameterCount = r.get<uint64_t>("body");
    if (layerCount > kMaxNetworkLayers) r.fail(layerLimitMessage(layerCount));
    if (parameterCount > kMaxNetworkParameters) r.fail(parameterLimitMessage(parameterCount));
    net.name = r.getString("network name");
    net.metadata = r.getString("metadata");
    while (r.at % 4) r.get<uint8_t>("padding");
    if (bodySpan.size() - r.at != uint64_t(layerCount) * kLayerBytes + parameterCount * sizeof(float))
        r.fail("layer and parameter sizes disagree with the file size");
    net.layers.resize(layerCount);
    for (NetworkLayer& l : net.layers) {
        l.kind = LayerKind(r.get<uint32_t>("layer"));
        for (uint32_t& id : l.inputs) id = r.get<uint32_t>("layer");
        l.output = r.get<uint32_t>("layer");
        l.inChannels = r.get<uint32_t>("layer");
        l.outChannels = r.get<uint32_t>("layer");
        l.kernelSize = r.get<uint32_t>("layer");
        l.padding = Padding(r.get<uint32_t>("layer"));
        l.activation = Activation(r.get<uint32_t>("layer"));
        l.activationSlope = r.get<float>("layer");
        l.heads = r.get<uint32_t>("layer");
        l.attentionScale = r.get<float>("layer");
        l.factor = r.get<uint32_t>("layer");
        l.weightOffset = r.get<uint32_t>("layer");
        l.biasOffset = r.get<uint32_t>("layer");
    }
    net.parameters.resize(parameterCount);
    if (parameterCount) std::memcpy(net.parameters.data(), bodySpan.data() + r.at, parameterCount * sizeof(float));
    validateNetwork(net, name);
    net.source = name;
    return net;
}

NetworkWeights readNetworkWeights(const std::filesystem::path& path)
{
    const std::vector<uint8_t> bytes = readFileBytes(path);
    return parseNetworkWeights(bytes, path.string());
}

void writeNetworkWeights(const NetworkWeights& network, const std::filesystem::path& path)
{
    writeFileAtomic(path, serializeNetworkWeights(network));
}

uint64_t networkHash(const NetworkWeights& network) { return fnv1a64(serializeNetworkWeights(network)); }

uint64_t networkMultiplyAdds(const NetworkWeights& network, uint32_t storedSamples)
{
    const std::vector<TensorShape> shape = validateNetwork(network, networkLabel(network));
    if (storedSamples < 2) throw Error("network: an input needs at least 2 samples per side");
    uint64_t total = 0;
    for (const NetworkLayer& l : network.layers) {
        const uint64_t side = uint64_t(storedSamples - 1) * shape[l.inputs[0]].gridFactor + 1;
        const uint64_t pixels = side * side;
        if (l.kind == LayerKind::Conv)
            total += pixels * l.outChannels * l.inChannels * l.kernelSize * l.kernelSize;
        else if (l.kind == LayerKind::NeighborhoodCrossAttention)
            total += pixels * 2ull * l.inChannels * l.kernelSize * l.kernelSize;  // q.k and weights * v
    }
    return total;
}

}  // namespace ngi
