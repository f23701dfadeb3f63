// The super-resolution network's forward pass as GLSL compute. Paper: "Neural Geometry
// Image-Based Representations with Optimal Transport", section 3.2 (one forward pass from the
// stored level to the full-resolution geometry image). Op semantics: ngi/network_weights.h;
// executable spec: ngi::nn::referenceForward (offline/nn), which the tests compare against.
//
// This file: weights repacking into uniform windows and the recording of the op list.
// sr_workspace.cpp allocates the tensors, sr_profile.cpp times the ops, sr_host.cpp runs the
// network on host tensors for tests and tools (sr_internal.h: what they share).
#include "ngi/engine/super_resolution.h"
#include "sr_internal.h"

#include "sr_kernels.h"

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"
#include "ngi/nn/reference_forward.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ngi::vk {

SuperResolution::SuperResolution(const Context& context, const NetworkWeights& network,
                                 const SuperResolutionOptions& options)
    : SuperResolution(context, network, options, validateNetwork(network, networkLabel(network)))
{}

SuperResolution::SuperResolution(const Context& context, const NetworkWeights& network,
                                 const SuperResolutionOptions& options, std::vector<TensorShape> shapes,
                                 uint32_t extraQueries, bool imagePasses)
    : context_(context), network_(network), options_(options), shapes_(std::move(shapes))
{
    if (context.properties.limits.maxUniformBufferRange < kWindowBytes)
        throw Error("super-resolution: the device's uniform buffers are smaller than 64 KiB");
    kernels_ = std::make_unique<Kernels>(context);
    fusedSkip_.assign(network_.layers.size(), false);
    for (size_t li = 0; li + 1 < network_.layers.size(); ++li) {
        const NetworkLayer &conv = network_.layers[li], &skip = network_.layers[li + 1];
        // HermiteSkip is not fused: it reads a third tensor (the normals) and 24 texels per sample.
        if (conv.kind != LayerKind::Conv || !isSkip(skip.kind) || skip.kind == LayerKind::HermiteSkip ||
            skip.inputs[1] != conv.output || conv.output == network_.outputTensor)
            continue;
        bool otherReader = false;
        for (size_t lj = 0; lj < network_.layers.size(); ++lj)
            for (uint32_t in : network_.layers[lj].inputs) otherReader |= lj != li + 1 && in == conv.output;
        fusedSkip_[li] = !otherReader;
    }
    try {
        // Repack every conv layer's weights: one uniform window per block of output groups
        // (see shaders/sr_conv.comp for the layout).
        const VkDeviceSize align =
            std::max<VkDeviceSize>(256, context.properties.limits.minUniformBufferOffsetAlignment);
        std::vector<float> packed;
        convPlans_.resize(network_.layers.size());
        for (size_t li = 0; li < network_.layers.size(); ++li) {
            const NetworkLayer& l = network_.layers[li];
            if (l.kind != LayerKind::Conv) continue;
            const uint32_t ig = groupsOf(l.inChannels), og = groupsOf(l.outChannels),
                           taps = l.kernelSize * l.kernelSize;
            const SrConvShape shape =
                resolveShape(l.kernelSize == 3 ? options_.conv3x3 : options_.conv1x1, ig, l.kernelSize);
            const uint32_t perGroup = ig * taps * 4 + 1;  // vec4s: weights + bias
            uint32_t opg = std::min(shape.groupsPerInvocation, og);
            while (opg > 1 && opg * perGroup > NGI_SR_UBO_VEC4S) --opg;
            if (perGroup > NGI_SR_UBO_VEC4S)
                throw Error(label() + ": layer " + std::to_string(li) + " has too many input channels (" +
                            std::to_string(l.inChannels) +
                            ") for the GPU convolution's 64 KiB weights window (at most " +
                            std::to_string((NGI_SR_UBO_VEC4S - 1) / (taps * 4) * 4) + " at " +
                            std::to_string(l.kernelSize) + "x" + std::to_string(l.kernelSize) + ")");
            ConvPlan& plan = convPlans_[li];
            plan.groupsPerInvocation = opg;
            plan.pixelsPerInvocation = shape.pixelsPerInvocation;
            for (uint32_t first = 0; first < og; first += opg) {
                const size_t base = packed.size();
                plan.blockOffsets.push_back(uint32_t(base * 4));
                packed.resize(base + (size_t(opg) * perGroup * 16 + align - 1) / align * align / 4, 0.0f);
                for (uint32_t o = 0; o < opg; ++o)
                    for (uint32_t lane = 0; lane < 4; ++lane) {
                        const uint32_t out = 4 * (first + o) + lane;
                        if (out >= l.outChannels) continue;
                        for (uint32_t i = 0; i < ig; ++i)
                            for (uint32_t t = 0; t < taps; ++t)
                                for (uint32_t j = 0; j < 4; ++j) {
                                    const uint32_t in = 4 * i + j;
                                    if (in >= l.inChannels) continue;
                                    packed[base + ((((size_t(o) * ig + i) * taps + t) * 4 + j) * 4) + lane] =
                                        network_
                                            .parameters[l.weightOffset + (size_t(out) * l.inChannels + in) * taps + t];
                                }
                        packed[base + (size_t(opg) * ig * taps * 4 + o) * 4 + lane] =
                            network_.parameters[l.biasOffset + out];
                    }
            }
        }
        packed.resize(packed.size() + kWindowBytes / 4, 0.0f);  // every window may bind 64 KiB
        const VkDeviceSize bytes = packed.size() * sizeof(float);
        weights_ = createBuffer(context, bytes, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
        Buffer staging = createBuffer(context, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                      VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        std::memcpy(staging.mapped, packed.data(), bytes);
        try {
            context.submitAndWait([&](VkCommandBuffer cmd) {
                const VkBufferCopy copy{0, 0, bytes};
                vkCmdCopyBuffer(cmd, staging.buffer, weights_.buffer, 1, &copy);
                memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                              VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_UNIFORM_READ_BIT);
            });
        } catch (...) {
            destroyBuffer(context, staging);
            throw;
        }
        destroyBuffer(context, staging);
        createPipelines(imagePasses);

        if (options_.profile) {
            uint32_t familyCount = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice, &familyCount, nullptr);
            std::vector<VkQueueFamilyProperties> families(familyCount);
            vkGetPhysicalDeviceQueueFamilyProperties(context.physicalDevice, &familyCount, families.data());
            if (families[context.queueFamily].timestampValidBits > 0) {
                VkQueryPoolCreateInfo q{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
                q.queryType = VK_QUERY_TYPE_TIMESTAMP;
                queryCount_ = q.queryCount = uint32_t(network_.layers.size()) + 4 + extraQueries;
                NGI_VK_CHECK(vkCreateQueryPool(context.device, &q, nullptr, &queries_));
            }
        }
    } catch (...) {
        if (queries_) vkDestroyQueryPool(context.device, queries_, nullptr);
        destroyBuffer(context, weights_);
        throw;
    }
}

SuperResolution::~SuperResolution()
{
    pending_.clear();
    spare_.clear();
    workspaces_.clear();
    if (queries_) vkDestroyQueryPool(context_.device, queries_, nullptr);
    destroyBuffer(context_, weights_);
}

void SuperResolution::releaseTensors()
{
    pending_.clear();
    spare_.clear();
    workspaces_.clear();
}

VkDeviceSize SuperResolution::gpuBytes() const
{
    VkDeviceSize total = weights_.size;
    for (const auto& w : workspaces_) total += w->bytes;
    return total;
}

size_t SuperResolution::pipelineCount() const { return kernels_->pipelineCount(); }

void SuperResolution::createPipelines(bool imagePasses)
{
    std::vector<SrPipelineKey> keys;
    for (size_t li = 0; li < network_.layers.size(); ++li) {
        if (li > 0 && fusedSkip_[li - 1]) continue;  // runs in the conv's epilogue
        keys.push_back(pipelineKey(li));
        // The output skip (or the conv it is fused into) also blends toward the cubic for a
        // chart whose residual gain is not 1.
        const uint32_t written = fusedSkip_[li] ? network_.layers[li + 1].output : network_.layers[li].output;
        if (written == network_.outputTensor && nn::outputSkipLayer(network_)) keys.push_back(pipelineKey(li, true));
    }
    if (imagePasses) {
        keys.push_back({SrShader::Input, {}});
        keys.push_back({SrShader::Output, {}});
    }
    kernels_->create(keys, options_.pipelineCache);
}

SrPipelineKey SuperResolution::pipelineKey(size_t li, bool blend) const
{
    const NetworkLayer& l = network_.layers[li];
    switch (l.kind) {
    case LayerKind::Conv: {
        const ConvPlan& plan = convPlans_[li];
        uint32_t epilogue = l.inputs[1] != kNoTensor ? NGI_SR_EPILOGUE_RESIDUAL : 0u;
        if (fusedSkip_[li])
            epilogue |= NGI_SR_EPILOGUE_SKIP |
                (network_.layers[li + 1].kind == LayerKind::CubicSkip ? NGI_SR_EPILOGUE_CUBIC : 0u) |
                (blend ? NGI_SR_EPILOGUE_BLEND : 0u);
        return {SrShader::Conv,
                {l.kernelSize, plan.groupsPerInvocation, plan.pixelsPerInvocation, groupsOf(l.inChannels), epilogue}};
    }
    case LayerKind::NeighborhoodCrossAttention: return {SrShader::Attention, {l.inChannels, l.heads, l.kernelSize / 2}};
    case LayerKind::PixelShuffle: return {SrShader::PixelShuffle, {l.factor}};
    case LayerKind::BilinearSkip: return {SrShader::BilinearSkip, {NGI_SR_SKIP_BILINEAR, blend ? 1u : 0u}};
    case LayerKind::CubicSkip: return {SrShader::BilinearSkip, {NGI_SR_SKIP_CUBIC, blend ? 1u : 0u}};
    case LayerKind::HermiteSkip: return {SrShader::BilinearSkip, {NGI_SR_SKIP_HERMITE, blend ? 1u : 0u}};
    }
    throw Error("super-resolution: unknown layer kind");
}

void SuperResolution::checkResidualGain(float gain) const
{
    if (!(gain >= 0.0f && gain <= 1.0f))
        throw Error(label() + ": residual gain " + std::to_string(gain) + " is not in [0, 1]");
    if (gain != 1.0f && !nn::outputSkipLayer(network_))
        throw Error(label() + ": a residual gain needs the network's output written by a skip layer");
}

void SuperResolution::recordLayers(VkCommandBuffer cmd, const Workspace& ws, float outputGain)
{
    Kernels& k = *kernels_;
    for (size_t li = 0; li < network_.layers.size(); ++li) {
        const NetworkLayer& l = network_.layers[li];
        if (li > 0 && fusedSkip_[li - 1]) continue;  // ran in the conv's epilogue
        const uint32_t written = fusedSkip_[li] ? network_.layers[li + 1].output : l.output;
        const SrTensorView out = ws.tensor(written), in = ws.tensor(l.inputs[0]);
        const VkDescriptorSet set = ws.layerSets[li];
        gpu::SrPushConstants pc{};
        // Only the skip that writes the network's output blends toward the cubic (referenceForward),
        // and only for a gain other than 1: its own pipeline variant.
        const bool blend = written == network_.outputTensor && outputGain != 1.0f;
        pc.residualGain = blend ? outputGain : 1.0f;
        pc.width = out.width;
        pc.height = out.height;
        pc.inWidth = in.width;
        pc.inHeight = in.height;
        pc.inGroups = in.groups();
        pc.outGroups = out.groups();
        std::string name = kindName(l) + " " + std::to_string(l.inChannels) + "->" + std::to_string(l.outChannels) +
            " " + std::to_string(out.width) + "x" + std::to_string(out.height);
        switch (l.kind) {
        case LayerKind::Conv: {
            const ConvPlan& plan = convPlans_[li];
            const VkPipeline p = k.pipeline(pipelineKey(li, blend));
            pc.flags = l.padding == Padding::Replicate ? NGI_SR_REPLICATE : 0u;  // the epilogue: pipelineKey
            pc.activation = uint32_t(l.activation);
            pc.slope = l.activationSlope;
            if (fusedSkip_[li]) {
                const SrTensorView coarse = ws.tensor(network_.layers[li + 1].inputs[0]);
                pc.factor = network_.layers[li + 1].factor;
                pc.inWidth = coarse.width;
                pc.inHeight = coarse.height;
                name += network_.layers[li + 1].kind == LayerKind::CubicSkip ? " +cubic skip" : " +bilinear skip";
            }
            for (size_t b = 0; b < plan.blockOffsets.size(); ++b) {
                pc.groupBase = uint32_t(b) * plan.groupsPerInvocation;
                k.dispatch(cmd, p, set, plan.blockOffsets[b], pc,
                           srGroups(srGroups(out.width, plan.pixelsPerInvocation), NGI_SR_LOCAL_X),
                           srGroups(out.height, NGI_SR_LOCAL_Y), 1);
            }
            if (l.inputs[1] != kNoTensor) name += " +residual";
            break;
        }
        case LayerKind::NeighborhoodCrossAttention: {
            const VkPipeline p = k.pipeline(pipelineKey(li, blend));
            pc.channels = l.inChannels;
            pc.scale = l.attentionScale;
            k.dispatch(cmd, p, set, 0, pc, srGroups(out.width, NGI_SR_LOCAL_X), srGroups(out.height, NGI_SR_LOCAL_Y),
                       1);
            name = "attention " + std::to_string(l.inChannels) + "ch " + std::to_string(l.heads) + " heads " +
                std::to_string(l.kernelSize) + "x" + std::to_string(l.kernelSize) + " " + std::to_string(out.width) +
                "x" + std::to_string(out.height);
            break;
        }
        case LayerKind::PixelShuffle:
            pc.factor = l.factor;
            pc.channels = l.outChannels;
            k.dispatch(cmd, k.pipeline(pipelineKey(li, blend)), set, 0, pc, srGroups(in.width, NGI_SR_LOCAL_X),
                       srGroups(out.height, NGI_SR_LOCAL_Y), 1);
            break;
        case LayerKind::BilinearSkip:
        case LayerKind::CubicSkip:
        case LayerKind::HermiteSkip:
            // Hermite: one invocation per (fine column, coarse row) (sr_bilinear_skip.comp).
            pc.factor = l.factor;
            k.dispatch(cmd, k.pipeline(pipelineKey(li, blend)), set, 0, pc, srGroups(out.width, NGI_SR_LOCAL_X),
                       srGroups(l.kind == LayerKind::HermiteSkip ? in.height : out.height, NGI_SR_LOCAL_Y), 1);
            break;
        }
        computeToComputeBarrier(cmd);
        uint64_t macs = 0;
        if (l.kind == LayerKind::Conv)
            macs = uint64_t(l.outChannels) * l.inChannels * l.kernelSize * l.kernelSize * out.width * out.height;
        if (l.kind == LayerKind::NeighborhoodCrossAttention)
            macs = uint64_t(2) * l.kernelSize * l.kernelSize * l.inChannels * out.width * out.height;
        markTimestamp(cmd, name, kindName(l), macs);
    }
}

void SuperResolution::record(VkCommandBuffer cmd, const Image& storedLevel, const Image& fullLevel, float residualGain)
{
    checkResidualGain(residualGain);
    if (!explicitDims_.empty()) throw Error("super-resolution: a single-layer runner has no image path");
    if (storedLevel.format != VK_FORMAT_R32G32B32A32_UINT || fullLevel.format != VK_FORMAT_R32G32B32A32_UINT)
        throw Error("super-resolution: the stored and full levels must be RGBA32UI geometry-image levels");
    if (storedLevel.width < 2 || storedLevel.height < 2 || fullLevel.width != outputSize(storedLevel.width) ||
        fullLevel.height != outputSize(storedLevel.height))
        throw Error(label() + ": a " + std::to_string(storedLevel.width) + "x" + std::to_string(storedLevel.height) +
                    " stored level restores to " + std::to_string(outputSize(storedLevel.width)) + "x" +
                    std::to_string(outputSize(storedLevel.height)) + ", not " + std::to_string(fullLevel.width) + "x" +
                    std::to_string(fullLevel.height) + " (scale factor " + std::to_string(scaleFactor()) + ")");
    const Workspace& ws = prepare(storedLevel.width, storedLevel.height);
    Restore& restore = acquireRestore(ws);
    const VkDescriptorImageInfo stored{VK_NULL_HANDLE, storedLevel.view, VK_IMAGE_LAYOUT_GENERAL};
    const VkDescriptorImageInfo full{VK_NULL_HANDLE, fullLevel.view, VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet writes[4];
    for (auto& w : writes) {
        w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    }
    writes[0].dstSet = restore.inputSets[0], writes[0].dstBinding = NGI_SR_BINDING_LEVEL,
    writes[0].pImageInfo = &stored;
    writes[1].dstSet = restore.inputSets[1], writes[1].dstBinding = NGI_SR_BINDING_LEVEL,
    writes[1].pImageInfo = &stored;
    writes[2].dstSet = restore.outputSet, writes[2].dstBinding = NGI_SR_BINDING_LEVEL, writes[2].pImageInfo = &full;
    writes[3].dstSet = restore.outputSet, writes[3].dstBinding = NGI_SR_BINDING_STORED, writes[3].pImageInfo = &stored;
    vkUpdateDescriptorSets(context_.device, 4, writes, 0, nullptr);
    restore.samples = uint64_t(fullLevel.width) * fullLevel.height;

    // An earlier restore of this size (this command buffer or an earlier submission on the
    // queue) may still read or write the shared tensors: the input pass overwrites them.
    computeToComputeBarrier(cmd);
    beginTimestamps(cmd);
    Kernels& k = *kernels_;
    gpu::SrPushConstants pc{};
    pc.width = ws.width;
    pc.height = ws.height;
    for (uint32_t i = 0; i < 2; ++i) {
        pc.channels = i;
        k.dispatch(cmd, k.pipeline({SrShader::Input, {}}), restore.inputSets[i], 0, pc,
                   srGroups(ws.width, NGI_SR_LOCAL_X), srGroups(ws.height, NGI_SR_LOCAL_Y), 1);
    }
    computeToComputeBarrier(cmd);
    markTimestamp(cmd, "input pass (texels -> tensors 0, 1)", "io", 0);
    recordLayers(cmd, ws, residualGain);
    const TensorDims& out = ws.dims[network_.outputTensor];
    pc = {};
    pc.width = out.width;
    pc.height = out.height;
    pc.inWidth = ws.width;
    pc.inHeight = ws.height;
    pc.factor = scaleFactor();
    // One invocation per (fine column, stored row) (sr_output.comp).
    k.dispatch(cmd, k.pipeline({SrShader::Output, {}}), restore.outputSet, 0, pc, srGroups(out.width, NGI_SR_LOCAL_X),
               srGroups(ws.height, NGI_SR_LOCAL_Y), 1);
    markTimestamp(cmd, "output pass (texels + interpolated normals)", "io", 0);
    // A fence wait alone does not make device writes visible to the host.
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                  VK_ACCESS_HOST_READ_BIT);
}

SuperResolution::Restore& SuperResolution::acquireRestore(const Workspace& ws)
{
    std::unique_ptr<Restore> r;
    if (!spare_.empty()) {
        r = std::move(spare_.back());
        spare_.pop_back();
    } else {
        r = std::make_unique<Restore>();
        r->context = &context_;
        r->check = createBuffer(context_, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);
        const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 1},
                                              {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, 2},
                                              {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, 3},
                                              {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 4},
                                              {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}};
        VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        poolInfo.maxSets = 3;
        poolInfo.poolSizeCount = uint32_t(std::size(sizes));
        poolInfo.pPoolSizes = sizes;
        NGI_VK_CHECK(vkCreateDescriptorPool(context_.device, &poolInfo, nullptr, &r->pool));
        const VkDescriptorSetLayout layouts[3] = {kernels_->setLayout, kernels_->setLayout, kernels_->setLayout};
        VkDescriptorSet sets[3];
        VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        alloc.descriptorPool = r->pool;
        alloc.descriptorSetCount = 3;
        alloc.pSetLayouts = layouts;
        NGI_VK_CHECK(vkAllocateDescriptorSets(context_.device, &alloc, sets));
        r->inputSets[0] = sets[0];
        r->inputSets[1] = sets[1];
        r->outputSet = sets[2];
        const VkDescriptorBufferInfo checkInfo{r->check.buffer, 0, 4};
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = r->outputSet;
        w.dstBinding = NGI_SR_BINDING_CHECK;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w.pBufferInfo = &checkInfo;
        vkUpdateDescriptorSets(context_.device, 1, &w, 0, nullptr);
    }
    // The tensor bindings: this restore's workspace (the sets may come from another size).
    const VkDescriptorBufferInfo weightsInfo{weights_.buffer, 0, kWindowBytes};
    writeTensorSet(context_.device, r->inputSets[0], ws.views, {kNoTensor, kNoTensor, kNoTensor}, kPositionInputTensor,
                   weightsInfo);
    writeTensorSet(context_.device, r->inputSets[1], ws.views, {kNoTensor, kNoTensor, kNoTensor}, kNormalInputTensor,
                   weightsInfo);
    writeTensorSet(context_.device, r->outputSet, ws.views, {network_.outputTensor, kNoTensor, kNoTensor}, kNoTensor,
                   weightsInfo);
    // Zeroed by the host: no earlier work uses this counter any more (checked or new), and
    // a submission makes host writes before it visible to the device.
    std::memset(r->check.mapped, 0, 4);
    pending_.push_back(std::move(r));
    return *pending_.back();
}

void SuperResolution::checkRestores()
{
    std::string problem;
    for (const auto& r : pending_) {
        uint32_t bad = 0;
        std::memcpy(&bad, r->check.mapped, sizeof bad);
        if (bad && problem.empty()) problem = nonFiniteMessage(label(), bad, r->samples);
    }
    for (auto& r : pending_) spare_.push_back(std::move(r));
    pending_.clear();
    if (!problem.empty()) throw Error(problem);
}

}  // namespace ngi::vk
