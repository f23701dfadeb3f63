// Test support: hostile super-resolution networks. The bytes of a weights file (.ngiw, layout
// in ngi/network_weights.h) for ANY network, valid or not, with a correct header and CRC
// (what a mutated file looks like to the reader: serializeNetworkWeights refuses invalid
// networks); op lists of any length; a valid network the GPU kernels cannot hold.
#pragma once

#include "ngi/network_weights.h"
#include "tiny_network.h"

#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

namespace ngi::test {

// zlib's CRC32 (bitwise; the files of the tests are small).
inline uint32_t crc32Of(std::span<const uint8_t> bytes)
{
    uint32_t crc = 0xffffffffu;
    for (uint8_t b : bytes) {
        crc ^= b;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

inline std::vector<uint8_t> unvalidatedWeightsFile(const NetworkWeights& net)
{
    std::vector<uint8_t> body;
    auto put = [&](const auto& v) {
        const auto* p = reinterpret_cast<const uint8_t*>(&v);
        body.insert(body.end(), p, p + sizeof v);
    };
    auto putString = [&](const std::string& s) {
        put(uint32_t(s.size()));
        body.insert(body.end(), s.begin(), s.end());
    };
    put(net.scaleFactor);
    put(net.tensorCount);
    put(net.outputTensor);
    put(uint32_t(net.layers.size()));
    put(uint64_t(net.parameters.size()));
    putString(net.name);
    putString(net.metadata);
    while (body.size() % 4) body.push_back(0);
    for (const NetworkLayer& l : net.layers) {
        put(uint32_t(l.kind));
        for (uint32_t id : l.inputs) put(id);
        put(l.output);
        put(l.inChannels);
        put(l.outChannels);
        put(l.kernelSize);
        put(uint32_t(l.padding));
        put(uint32_t(l.activation));
        put(l.activationSlope);
        put(l.heads);
        put(l.attentionScale);
        put(l.factor);
        put(l.weightOffset);
        put(l.biasOffset);
    }
    for (float p : net.parameters) put(p);
    std::vector<uint8_t> file = {0x89, 'N', 'G', 'W', '\r', '\n', 0x1a, '\n'};
    auto putHeader = [&](const auto& v) {
        const auto* p = reinterpret_cast<const uint8_t*>(&v);
        file.insert(file.end(), p, p + sizeof v);
    };
    putHeader(kNetworkWeightsVersion);
    putHeader(uint32_t(0));
    putHeader(uint64_t(body.size()));
    putHeader(crc32Of(body));
    putHeader(uint32_t(0));
    file.insert(file.end(), body.begin(), body.end());
    return file;
}

// A chain of `convs` 1x1 convolutions 3 -> 3 (zero weights) on the positions, then the x`factor`
// tail of tiny_network.h (1x1 conv to 3 f^2 channels, pixel shuffle, bilinear skip): a valid
// op list of any length, e.g. 4000 layers for the resource limits.
inline NetworkWeights longNetwork(uint32_t convs, uint32_t factor)
{
    NetworkWeights net;
    net.name = "long";
    net.scaleFactor = factor;
    uint32_t tensor = kPositionInputTensor;
    auto conv = [&](uint32_t in, uint32_t out) {
        NetworkLayer l;
        l.kind = LayerKind::Conv;
        l.inputs = {tensor, kNoTensor, kNoTensor};
        l.output = uint32_t(net.layers.size()) + 2;
        l.inChannels = in;
        l.outChannels = out;
        l.kernelSize = 1;
        l.weightOffset = uint32_t(net.parameters.size());
        l.biasOffset = l.weightOffset + in * out;
        net.parameters.resize(net.parameters.size() + size_t(in) * out + out, 0.0f);
        net.layers.push_back(l);
        tensor = l.output;
    };
    for (uint32_t i = 0; i < convs; ++i) conv(3, 3);
    conv(3, 3 * factor * factor);
    NetworkLayer shuffle;
    shuffle.kind = LayerKind::PixelShuffle;
    shuffle.inputs = {tensor, kNoTensor, kNoTensor};
    shuffle.output = uint32_t(net.layers.size()) + 2;
    shuffle.inChannels = 3 * factor * factor;
    shuffle.outChannels = 3;
    shuffle.factor = factor;
    net.layers.push_back(shuffle);
    NetworkLayer skip;
    skip.kind = LayerKind::BilinearSkip;
    skip.inputs = {kPositionInputTensor, shuffle.output, kNoTensor};
    skip.output = uint32_t(net.layers.size()) + 2;
    skip.inChannels = skip.outChannels = 3;
    skip.factor = factor;
    net.layers.push_back(skip);
    net.tensorCount = skip.output + 1;
    net.outputTensor = skip.output;
    return net;
}

// tiny_network.h's x`factor` network behind a 1x1 conv 3 -> 500 and a 3x3 conv 500 -> 4:
// within every limit of the format, but layer 1's weights for one group of 4 output channels
// (500 * 9 * 4 floats) exceed the GPU convolution's 64 KiB window (at most 452 inputs at 3x3).
inline NetworkWeights wideConvNetwork(uint32_t factor)
{
    NetworkWeights net = tinyNetwork(factor, 0.0f);
    NetworkLayer wide = net.layers[0], narrow = net.layers[0];
    wide.output = 5;
    wide.outChannels = 500;
    narrow.inputs[0] = 5;
    narrow.output = 6;
    narrow.inChannels = 500;
    narrow.outChannels = 4;
    narrow.kernelSize = 3;
    net.layers[0].inputs[0] = 6;
    net.layers[0].inChannels = 4;
    net.layers.insert(net.layers.begin(), {wide, narrow});
    net.parameters.resize(500 * 4 * 9 + 3 * factor * factor * 4);
    net.tensorCount = 7;
    return net;
}

}  // namespace ngi::test
