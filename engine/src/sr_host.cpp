// ngi engine: the super-resolution network and single layers run on host tensors, with
// upload and readback: the paths the parity tests and ngi-bench-sr use, not frames.
#include "sr_internal.h"

#include "ngi/engine/super_resolution.h"
#include "sr_kernels.h"
#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include <algorithm>
#include <cmath>
#include <cstring>

namespace ngi::vk {

nn::FeatureMap SuperResolution::run(const nn::FeatureMap& positions, const nn::FeatureMap& normals, float residualGain)
{
    checkResidualGain(residualGain);
    if (!explicitDims_.empty()) throw Error("super-resolution: run() needs a whole network");
    if (positions.channels != 3 || normals.channels != 3 || positions.width != normals.width ||
        positions.height != normals.height || positions.width < 2 || positions.height < 2 ||
        positions.data.size() != size_t(3) * positions.width * positions.height ||
        normals.data.size() != positions.data.size())
        throw Error("super-resolution: inputs must be 3 x H x W position and normal maps of equal size, H, W >= 2");
    const Workspace& ws = prepare(positions.width, positions.height);
    const nn::FeatureMap inputs[2] = {positions, normals};
    nn::FeatureMap out = runHost(ws, inputs, 1, residualGain);
    const size_t plane = size_t(out.width) * out.height;
    uint64_t bad = 0;
    for (size_t p = 0; p < plane; ++p)
        bad += !(std::isfinite(out.data[p]) && std::isfinite(out.data[plane + p]) &&
                 std::isfinite(out.data[2 * plane + p]));
    if (bad) throw Error(nonFiniteMessage(label(), bad, plane));
    return out;
}

nn::FeatureMap SuperResolution::runHost(const Workspace& ws, std::span<const nn::FeatureMap> inputs, uint32_t repeats,
                                        float outputGain)
{
    VkDeviceSize uploadBytes = 0;
    for (uint32_t t = 0; t < inputs.size(); ++t) uploadBytes += ws.dims[t].bytes();
    const TensorDims& outDims = ws.dims[network_.outputTensor];
    const VkMemoryPropertyFlags host = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    Buffer upload = createBuffer(context_, uploadBytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, host);
    Buffer readback;
    try {
        readback = createBuffer(context_, outDims.bytes(), VK_BUFFER_USAGE_TRANSFER_DST_BIT, host);
        VkDeviceSize at = 0;
        for (uint32_t t = 0; t < inputs.size(); ++t) {
            packTensor(inputs[t], reinterpret_cast<float*>(static_cast<char*>(upload.mapped) + at));
            at += ws.dims[t].bytes();
        }
        context_.submitAndWait([&](VkCommandBuffer cmd) {
            VkDeviceSize src = 0;
            for (uint32_t t = 0; t < inputs.size(); ++t) {
                const VkBufferCopy copy{src, 0, ws.dims[t].bytes()};
                vkCmdCopyBuffer(cmd, upload.buffer, ws.buffers[ws.bufferOf[t]].buffer, 1, &copy);
                src += copy.size;
            }
            memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
            beginTimestamps(cmd);
            for (uint32_t r = 0; r < repeats; ++r) recordLayers(cmd, ws, outputGain);
            memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                          VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
            const VkBufferCopy copy{0, 0, outDims.bytes()};
            vkCmdCopyBuffer(cmd, ws.buffers[ws.bufferOf[network_.outputTensor]].buffer, readback.buffer, 1, &copy);
            memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                          VK_ACCESS_HOST_READ_BIT);
        });
    } catch (...) {
        destroyBuffer(context_, readback);
        destroyBuffer(context_, upload);
        throw;
    }
    nn::FeatureMap result = unpackTensor(static_cast<const float*>(readback.mapped), outDims);
    destroyBuffer(context_, readback);
    destroyBuffer(context_, upload);
    return result;
}

nn::FeatureMap runSuperResolutionLayer(const Context& context, const NetworkLayer& layer,
                                       std::span<const float> parameters, std::span<const nn::FeatureMap> inputs,
                                       uint32_t outputWidth, uint32_t outputHeight,
                                       const SuperResolutionOptions& options, std::vector<double>* gpuMilliseconds)
{
    // A one-layer "network": tensors 0..n-1 are the inputs, tensor n the output.
    const uint32_t n = uint32_t(inputs.size());
    if (n == 0 || n > 3) throw Error("super-resolution layer: 1 to 3 inputs");
    NetworkWeights net;
    net.name = "single layer";
    net.tensorCount = n + 1;
    net.outputTensor = n;
    net.parameters.assign(parameters.begin(), parameters.end());
    NetworkLayer l = layer;
    for (uint32_t k = 0; k < 3; ++k) l.inputs[k] = k < n ? k : kNoTensor;
    l.output = n;
    net.layers = {l};
    std::vector<TensorShape> shapes(n + 1, TensorShape{0, 1});
    SuperResolutionOptions timed = options;
    const uint32_t repeats = gpuMilliseconds ? uint32_t(std::max<size_t>(1, gpuMilliseconds->size())) : 0;
    timed.profile = options.profile || gpuMilliseconds;
    SuperResolution sr(context, net, timed, shapes, repeats + 4, false);
    sr.hostInputs_ = n;
    for (const nn::FeatureMap& t : inputs) {
        if (t.data.size() != size_t(t.channels) * t.width * t.height)
            throw Error("super-resolution layer: bad input size");
        sr.explicitDims_.push_back({t.channels, t.width, t.height});
    }
    sr.explicitDims_.push_back({layer.outChannels, outputWidth, outputHeight});
    const SuperResolution::Workspace& ws = sr.prepare(inputs[0].width, inputs[0].height);
    nn::FeatureMap result = sr.runHost(ws, inputs, repeats + 1);
    if (gpuMilliseconds) {
        const std::vector<SrOpTiming> ops = sr.profile();
        if (ops.size() != repeats + 1) throw Error("super-resolution layer: this device has no timestamps");
        gpuMilliseconds->clear();
        for (size_t i = 1; i < ops.size(); ++i) gpuMilliseconds->push_back(ops[i].milliseconds);
    }
    return result;
}

}  // namespace ngi::vk
