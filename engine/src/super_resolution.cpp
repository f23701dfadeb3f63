// The super-resolution network's forward pass as GLSL compute. Paper: "Neural Geometry
// Image-Based Representations with Optimal Transport", section 3.2 (one forward pass from the
// stored level to the full-resolution geometry image). Op semantics: ngi/network_weights.h;
// executable spec: ngi::nn::referenceForward (offline/nn), which the tests compare against.
//
// This file: weights repacking into uniform windows, tensor allocation aliased by liveness,
// recording of the op list, the host paths for tests and tools, and timestamps per op.
#include "ngi/engine/super_resolution.h"

#include "sr_kernels.h"

#include "ngi/engine/vk_check.h"
#include "ngi/error.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ngi::vk {
namespace {

constexpr VkDeviceSize kWindowBytes = NGI_SR_UBO_VEC4S * 16;  // one conv dispatch's weights
constexpr VkFormat kTensorFormat = VK_FORMAT_R32G32B32A32_SFLOAT;

uint32_t groupsOf(uint32_t channels) { return (channels + 3) / 4; }

// The engine's conv kernel shape (ngi-bench-sr --micro on lavapipe): 4 pixels per
// invocation; 2 output groups per invocation while the unrolled body stays small (input
// groups x taps <= 36, e.g. 16 -> 192 3x3: 9.5 GFLOP/s vs 4.8 with 1 group), else 1 (32 -> 32
// 3x3: 9.5 GFLOP/s vs 4.3 with 2: the larger body spills registers and code cache).
SrConvShape resolveShape(SrConvShape s, uint32_t inGroups, uint32_t kernel)
{
    if (s.groupsPerInvocation == 0) s.groupsPerInvocation = inGroups * kernel * kernel <= 36 ? 2 : 1;
    if (s.pixelsPerInvocation == 0) s.pixelsPerInvocation = 4;
    if (s.groupsPerInvocation > 8 || s.pixelsPerInvocation > 16) throw Error("super-resolution: conv shape too large");
    return s;
}

struct TensorDims {
    uint32_t channels = 0, width = 0, height = 0;
    VkDeviceSize bytes() const { return VkDeviceSize(groupsOf(channels)) * width * height * 16; }
};

// Host CHW -> C4 planes (zero lanes past the channel count) and back.
void packTensor(const nn::FeatureMap& t, float* dst)
{
    const size_t plane = size_t(t.width) * t.height;
    std::memset(dst, 0, groupsOf(t.channels) * plane * 16);
    for (uint32_t c = 0; c < t.channels; ++c)
        for (size_t p = 0; p < plane; ++p) dst[((c / 4) * plane + p) * 4 + c % 4] = t.data[c * plane + p];
}

nn::FeatureMap unpackTensor(const float* src, const TensorDims& d)
{
    nn::FeatureMap t(d.channels, d.height, d.width);
    const size_t plane = size_t(d.width) * d.height;
    t.data.resize(d.channels * plane);
    for (uint32_t c = 0; c < d.channels; ++c)
        for (size_t p = 0; p < plane; ++p) t.data[c * plane + p] = src[((c / 4) * plane + p) * 4 + c % 4];
    return t;
}

void computeToComputeBarrier(VkCommandBuffer cmd)
{
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_SHADER_READ_BIT,
                  VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

std::string kindName(const NetworkLayer& l)
{
    switch (l.kind) {
    case LayerKind::Conv: return l.kernelSize == 3 ? "conv3x3" : "conv1x1";
    case LayerKind::NeighborhoodCrossAttention: return "attention";
    case LayerKind::PixelShuffle: return "pixel_shuffle";
    case LayerKind::BilinearSkip: return "bilinear_skip";
    case LayerKind::CubicSkip: return "cubic_skip";
    case LayerKind::HermiteSkip: return "hermite_skip";
    }
    return "?";
}

} // namespace

// Tensors and descriptor sets of one input size.
struct SuperResolution::Workspace {
    const Context* context = nullptr;
    uint32_t width = 0, height = 0;  // input (stored level) size
    std::vector<TensorDims> dims;    // per tensor
    std::vector<Buffer> buffers;     // aliased by liveness
    std::vector<uint32_t> bufferOf;  // per tensor
    std::vector<VkBufferView> views; // per tensor
    VkDescriptorPool pool = VK_NULL_HANDLE;
    std::vector<VkDescriptorSet> layerSets;  // per layer
    VkDescriptorSet inputSets[2]{};          // stored level -> tensor 0, 1
    VkDescriptorSet outputSet = VK_NULL_HANDLE;
    VkDeviceSize bytes = 0;

    SrTensorView tensor(uint32_t id) const { return {views[id], dims[id].channels, dims[id].width, dims[id].height}; }

    ~Workspace()
    {
        if (!context) return;
        if (pool) vkDestroyDescriptorPool(context->device, pool, nullptr);
        for (VkBufferView v : views)
            if (v) vkDestroyBufferView(context->device, v, nullptr);
        for (Buffer& b : buffers) destroyBuffer(*context, b);
    }
};

SuperResolution::SuperResolution(const Context& context, const NetworkWeights& network,
                                 const SuperResolutionOptions& options)
    : SuperResolution(context, network, options, validateNetwork(network, networkLabel(network)))
{
}

SuperResolution::SuperResolution(const Context& context, const NetworkWeights& network,
                                 const SuperResolutionOptions& options, std::vector<TensorShape> shapes,
                                 uint32_t extraQueries)
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
            skip.inputs[1] != conv.output ||
            conv.output == network_.outputTensor)
            continue;
        bool otherReader = false;
        for (size_t lj = 0; lj < network_.layers.size(); ++lj)
            for (uint32_t in : network_.layers[lj].inputs)
                otherReader |= lj != li + 1 && in == conv.output;
        fusedSkip_[li] = !otherReader;
    }
    try {
        // Repack every conv layer's weights: one uniform window per block of output groups
        // (see shaders/sr_conv.comp for the layout).
        const VkDeviceSize align = std::max<VkDeviceSize>(256, context.properties.limits.minUniformBufferOffsetAlignment);
        std::vector<float> packed;
        convPlans_.resize(network_.layers.size());
        for (size_t li = 0; li < network_.layers.size(); ++li) {
            const NetworkLayer& l = network_.layers[li];
            if (l.kind != LayerKind::Conv) continue;
            const uint32_t ig = groupsOf(l.inChannels), og = groupsOf(l.outChannels), taps = l.kernelSize * l.kernelSize;
            const SrConvShape shape =
                resolveShape(l.kernelSize == 3 ? options_.conv3x3 : options_.conv1x1, ig, l.kernelSize);
            const uint32_t perGroup = ig * taps * 4 + 1;  // vec4s: weights + bias
            uint32_t opg = std::min(shape.groupsPerInvocation, og);
            while (opg > 1 && opg * perGroup > NGI_SR_UBO_VEC4S) --opg;
            if (perGroup > NGI_SR_UBO_VEC4S)
                throw Error(label() + ": layer " + std::to_string(li) + " has too many input channels (" +
                            std::to_string(l.inChannels) + ") for the GPU convolution's 64 KiB weights window (at most " +
                            std::to_string((NGI_SR_UBO_VEC4S - 1) / (taps * 4) * 4) + " at " + std::to_string(l.kernelSize) +
                            "x" + std::to_string(l.kernelSize) + ")");
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
                                        network_.parameters[l.weightOffset + (size_t(out) * l.inChannels + in) * taps + t];
                                }
                        packed[base + (size_t(opg) * ig * taps * 4 + o) * 4 + lane] = network_.parameters[l.biasOffset + out];
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
        check_ = createBuffer(context, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT);

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
        destroyBuffer(context, check_);
        destroyBuffer(context, weights_);
        throw;
    }
}

SuperResolution::~SuperResolution()
{
    workspace_.reset();
    if (queries_) vkDestroyQueryPool(context_.device, queries_, nullptr);
    destroyBuffer(context_, check_);
    destroyBuffer(context_, weights_);
}

void SuperResolution::releaseTensors() { workspace_.reset(); }

VkDeviceSize SuperResolution::gpuBytes() const { return weights_.size + (workspace_ ? workspace_->bytes : 0); }

void SuperResolution::prepare(uint32_t width, uint32_t height)
{
    if (workspace_ && workspace_->width == width && workspace_->height == height) return;
    workspace_.reset();
    auto ws = std::make_unique<Workspace>();
    ws->context = &context_;
    ws->width = width;
    ws->height = height;
    const uint32_t tensorCount = uint32_t(shapes_.size());
    ws->dims.resize(tensorCount);
    for (uint32_t t = 0; t < tensorCount; ++t) {
        if (!explicitDims_.empty()) {
            ws->dims[t] = {explicitDims_[t][0], explicitDims_[t][1], explicitDims_[t][2]};
        } else {
            const uint32_t g = shapes_[t].gridFactor;
            ws->dims[t] = {shapes_[t].channels, (width - 1) * g + 1, (height - 1) * g + 1};
        }
    }
    const uint32_t maxTexels = context_.properties.limits.maxTexelBufferElements;
    for (uint32_t t = 0; t < tensorCount; ++t)
        if (ws->dims[t].bytes() / 16 > maxTexels)
            throw Error(label() + ": tensor " + std::to_string(t) + " (" + std::to_string(ws->dims[t].channels) +
                        " channels, " + std::to_string(ws->dims[t].width) + "x" + std::to_string(ws->dims[t].height) +
                        ") exceeds this device's texel buffer limit (" + std::to_string(maxTexels) + " texels)");

    // Liveness: a tensor is live from the layer that writes it (inputs: before layer 0) to
    // its last reader (the output tensor: to the end).
    const int layerCount = int(network_.layers.size());
    std::vector<int> lastUse(tensorCount, -1), firstDef(tensorCount, -1);
    for (int li = 0; li < layerCount; ++li) {
        const NetworkLayer& l = network_.layers[li];
        for (uint32_t in : l.inputs)
            if (in != kNoTensor) lastUse[in] = li;
        firstDef[l.output] = li;
    }
    lastUse[network_.outputTensor] = layerCount;
    // Slots first (a free slot that grows least, then the smallest), buffers sized after.
    ws->bufferOf.assign(tensorCount, UINT32_MAX);
    std::vector<VkDeviceSize> slotBytes;
    std::vector<int> slotFreeAfter;  // per slot: last use of the tensor it holds
    auto place = [&](uint32_t t, int def) {
        const VkDeviceSize need = ws->dims[t].bytes();
        uint32_t best = UINT32_MAX;
        VkDeviceSize bestGrowth = 0;
        for (uint32_t b = 0; b < slotBytes.size(); ++b) {
            if (slotFreeAfter[b] >= def) continue;
            const VkDeviceSize growth = need > slotBytes[b] ? need - slotBytes[b] : 0;
            if (best == UINT32_MAX || growth < bestGrowth || (growth == bestGrowth && slotBytes[b] < slotBytes[best])) {
                best = b;
                bestGrowth = growth;
            }
        }
        if (best == UINT32_MAX || bestGrowth >= need) {  // growing would cost as much as a new slot
            best = uint32_t(slotBytes.size());
            slotBytes.push_back(0);
            slotFreeAfter.push_back(0);
        }
        slotBytes[best] = std::max(slotBytes[best], need);
        slotFreeAfter[best] = std::max(lastUse[t], def);
        ws->bufferOf[t] = best;
    };
    for (uint32_t t = 0; t < hostInputs_; ++t) place(t, -1);
    for (int li = 0; li < layerCount; ++li) {
        if (li > 0 && fusedSkip_[li - 1]) continue;  // placed with its conv
        // A conv with a fused skip writes the skip's output (its own output never exists).
        place(fusedSkip_[li] ? network_.layers[li + 1].output : network_.layers[li].output, li);
    }
    for (VkDeviceSize bytes : slotBytes) {
        ws->buffers.push_back(createBuffer(context_, bytes,
                                           VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_TEXEL_BUFFER_BIT |
                                               VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                           VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT));
        ws->bytes += bytes;
    }
    ws->views.assign(tensorCount, VK_NULL_HANDLE);
    for (uint32_t t = 0; t < tensorCount; ++t) {
        if (ws->bufferOf[t] == UINT32_MAX) continue;
        VkBufferViewCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO};
        info.buffer = ws->buffers[ws->bufferOf[t]].buffer;
        info.format = kTensorFormat;
        info.range = ws->dims[t].bytes();
        NGI_VK_CHECK(vkCreateBufferView(context_.device, &info, nullptr, &ws->views[t]));
    }

    // One descriptor set per layer and per input/output pass.
    const uint32_t setCount = uint32_t(layerCount) + 3;
    const VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, 3 * setCount},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER, setCount},
                                          {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC, setCount},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 2 * setCount},
                                          {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1}};
    VkDescriptorPoolCreateInfo poolInfo{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    poolInfo.maxSets = setCount;
    poolInfo.poolSizeCount = uint32_t(std::size(sizes));
    poolInfo.pPoolSizes = sizes;
    NGI_VK_CHECK(vkCreateDescriptorPool(context_.device, &poolInfo, nullptr, &ws->pool));
    std::vector<VkDescriptorSetLayout> layouts(setCount, kernels_->setLayout);
    std::vector<VkDescriptorSet> sets(setCount);
    VkDescriptorSetAllocateInfo alloc{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    alloc.descriptorPool = ws->pool;
    alloc.descriptorSetCount = setCount;
    alloc.pSetLayouts = layouts.data();
    NGI_VK_CHECK(vkAllocateDescriptorSets(context_.device, &alloc, sets.data()));
    ws->layerSets.assign(sets.begin(), sets.begin() + layerCount);
    ws->inputSets[0] = sets[layerCount];
    ws->inputSets[1] = sets[layerCount + 1];
    ws->outputSet = sets[layerCount + 2];

    const VkDescriptorBufferInfo weightsInfo{weights_.buffer, 0, kWindowBytes};
    auto writeSet = [&](VkDescriptorSet set, std::array<uint32_t, 3> in, uint32_t out) {
        std::vector<VkWriteDescriptorSet> writes;
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = set;
        w.descriptorCount = 1;
        for (uint32_t k = 0; k < 3; ++k)
            if (in[k] != kNoTensor) {
                w.dstBinding = NGI_SR_BINDING_IN0 + k;
                w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
                w.pTexelBufferView = &ws->views[in[k]];
                writes.push_back(w);
            }
        if (out != kNoTensor) {
            w.dstBinding = NGI_SR_BINDING_OUT;
            w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
            w.pTexelBufferView = &ws->views[out];
            writes.push_back(w);
        }
        w.dstBinding = NGI_SR_BINDING_WEIGHTS;
        w.descriptorType = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER_DYNAMIC;
        w.pTexelBufferView = nullptr;
        w.pBufferInfo = &weightsInfo;
        writes.push_back(w);
        vkUpdateDescriptorSets(context_.device, uint32_t(writes.size()), writes.data(), 0, nullptr);
    };
    for (int li = 0; li < layerCount; ++li) {
        const NetworkLayer& l = network_.layers[li];
        if (li > 0 && fusedSkip_[li - 1]) continue;
        // Statically used but unread bindings (a conv's residual when it has none) hold the input.
        std::array<uint32_t, 3> in = l.inputs;
        if (fusedSkip_[li]) in[2] = network_.layers[li + 1].inputs[0];
        for (uint32_t& t : in)
            if (t == kNoTensor) t = l.inputs[0];
        writeSet(ws->layerSets[li], in, fusedSkip_[li] ? network_.layers[li + 1].output : l.output);
    }
    if (hostInputs_ == 2 && explicitDims_.empty()) {
        writeSet(ws->inputSets[0], {kNoTensor, kNoTensor, kNoTensor}, kPositionInputTensor);
        writeSet(ws->inputSets[1], {kNoTensor, kNoTensor, kNoTensor}, kNormalInputTensor);
        writeSet(ws->outputSet, {network_.outputTensor, kNoTensor, kNoTensor}, kNoTensor);
        const VkDescriptorBufferInfo checkInfo{check_.buffer, 0, 4};
        VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.dstSet = ws->outputSet;
        w.dstBinding = NGI_SR_BINDING_CHECK;
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        w.pBufferInfo = &checkInfo;
        vkUpdateDescriptorSets(context_.device, 1, &w, 0, nullptr);
    }
    workspace_ = std::move(ws);
}

void SuperResolution::recordLayers(VkCommandBuffer cmd)
{
    Workspace& ws = *workspace_;
    Kernels& k = *kernels_;
    for (size_t li = 0; li < network_.layers.size(); ++li) {
        const NetworkLayer& l = network_.layers[li];
        if (li > 0 && fusedSkip_[li - 1]) continue;  // ran in the conv's epilogue
        const uint32_t written = fusedSkip_[li] ? network_.layers[li + 1].output : l.output;
        const SrTensorView out = ws.tensor(written), in = ws.tensor(l.inputs[0]);
        const VkDescriptorSet set = ws.layerSets[li];
        gpu::SrPushConstants pc{};
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
            const VkPipeline p = k.pipeline(SrShader::Conv, {l.kernelSize, plan.groupsPerInvocation,
                                                             plan.pixelsPerInvocation, in.groups()});
            pc.flags = (l.padding == Padding::Replicate ? NGI_SR_REPLICATE : 0u) |
                       (l.inputs[1] != kNoTensor ? NGI_SR_RESIDUAL : 0u);
            pc.activation = uint32_t(l.activation);
            pc.slope = l.activationSlope;
            if (fusedSkip_[li]) {
                const SrTensorView coarse = ws.tensor(network_.layers[li + 1].inputs[0]);
                pc.flags |= NGI_SR_BILINEAR_SKIP;
                if (network_.layers[li + 1].kind == LayerKind::CubicSkip) pc.flags |= NGI_SR_CUBIC;
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
            const VkPipeline p = k.pipeline(SrShader::Attention, {l.inChannels, l.heads, l.kernelSize / 2});
            pc.channels = l.inChannels;
            pc.scale = l.attentionScale;
            k.dispatch(cmd, p, set, 0, pc, srGroups(out.width, NGI_SR_LOCAL_X), srGroups(out.height, NGI_SR_LOCAL_Y), 1);
            name = "attention " + std::to_string(l.inChannels) + "ch " + std::to_string(l.heads) + " heads " +
                   std::to_string(l.kernelSize) + "x" + std::to_string(l.kernelSize) + " " + std::to_string(out.width) +
                   "x" + std::to_string(out.height);
            break;
        }
        case LayerKind::PixelShuffle:
            pc.factor = l.factor;
            pc.channels = l.outChannels;
            k.dispatch(cmd, k.pipeline(SrShader::PixelShuffle), set, 0, pc, srGroups(in.width, NGI_SR_LOCAL_X),
                       srGroups(out.height, NGI_SR_LOCAL_Y), 1);
            break;
        case LayerKind::BilinearSkip:
        case LayerKind::CubicSkip:
        case LayerKind::HermiteSkip:
            pc.factor = l.factor;
            pc.flags = l.kind == LayerKind::CubicSkip ? NGI_SR_CUBIC : l.kind == LayerKind::HermiteSkip ? NGI_SR_HERMITE : 0u;
            k.dispatch(cmd, k.pipeline(SrShader::BilinearSkip), set, 0, pc, srGroups(out.width, NGI_SR_LOCAL_X),
                       srGroups(out.height, NGI_SR_LOCAL_Y), 1);
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

void SuperResolution::record(VkCommandBuffer cmd, const Image& storedLevel, const Image& fullLevel)
{
    if (!explicitDims_.empty()) throw Error("super-resolution: a single-layer runner has no image path");
    if (storedLevel.format != VK_FORMAT_R32G32B32A32_UINT || fullLevel.format != VK_FORMAT_R32G32B32A32_UINT)
        throw Error("super-resolution: the stored and full levels must be RGBA32UI geometry-image levels");
    if (storedLevel.width < 2 || storedLevel.height < 2 || fullLevel.width != outputSize(storedLevel.width) ||
        fullLevel.height != outputSize(storedLevel.height))
        throw Error(label() + ": a " + std::to_string(storedLevel.width) + "x" + std::to_string(storedLevel.height) +
                    " stored level restores to " + std::to_string(outputSize(storedLevel.width)) + "x" +
                    std::to_string(outputSize(storedLevel.height)) + ", not " + std::to_string(fullLevel.width) + "x" +
                    std::to_string(fullLevel.height) + " (scale factor " + std::to_string(scaleFactor()) + ")");
    prepare(storedLevel.width, storedLevel.height);
    Workspace& ws = *workspace_;
    const VkDescriptorImageInfo stored{VK_NULL_HANDLE, storedLevel.view, VK_IMAGE_LAYOUT_GENERAL};
    const VkDescriptorImageInfo full{VK_NULL_HANDLE, fullLevel.view, VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet writes[4];
    for (auto& w : writes) {
        w = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
        w.descriptorCount = 1;
        w.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    }
    writes[0].dstSet = ws.inputSets[0], writes[0].dstBinding = NGI_SR_BINDING_LEVEL, writes[0].pImageInfo = &stored;
    writes[1].dstSet = ws.inputSets[1], writes[1].dstBinding = NGI_SR_BINDING_LEVEL, writes[1].pImageInfo = &stored;
    writes[2].dstSet = ws.outputSet, writes[2].dstBinding = NGI_SR_BINDING_LEVEL, writes[2].pImageInfo = &full;
    writes[3].dstSet = ws.outputSet, writes[3].dstBinding = NGI_SR_BINDING_STORED, writes[3].pImageInfo = &stored;
    vkUpdateDescriptorSets(context_.device, 4, writes, 0, nullptr);

    // The count of non-finite restored samples starts at 0 (the output pass adds to it).
    vkCmdFillBuffer(cmd, check_.buffer, 0, 4, 0);
    memoryBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                  VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    lastRestoreSamples_ = uint64_t(fullLevel.width) * fullLevel.height;
    beginTimestamps(cmd);
    Kernels& k = *kernels_;
    gpu::SrPushConstants pc{};
    pc.width = ws.width;
    pc.height = ws.height;
    for (uint32_t i = 0; i < 2; ++i) {
        pc.channels = i;
        k.dispatch(cmd, k.pipeline(SrShader::Input), ws.inputSets[i], 0, pc, srGroups(ws.width, NGI_SR_LOCAL_X),
                   srGroups(ws.height, NGI_SR_LOCAL_Y), 1);
    }
    computeToComputeBarrier(cmd);
    markTimestamp(cmd, "input pass (texels -> tensors 0, 1)", "io", 0);
    recordLayers(cmd);
    const TensorDims& out = ws.dims[network_.outputTensor];
    pc = {};
    pc.width = out.width;
    pc.height = out.height;
    pc.inWidth = ws.width;
    pc.inHeight = ws.height;
    pc.factor = scaleFactor();
    k.dispatch(cmd, k.pipeline(SrShader::Output), ws.outputSet, 0, pc, srGroups(out.width, NGI_SR_LOCAL_X),
               srGroups(out.height, NGI_SR_LOCAL_Y), 1);
    markTimestamp(cmd, "output pass (texels + interpolated normals)", "io", 0);
    // A fence wait alone does not make device writes visible to the host.
    memoryBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                  VK_ACCESS_HOST_READ_BIT);
}

namespace {

std::string nonFiniteMessage(const std::string& label, uint64_t bad, uint64_t total)
{
    return label + ": the restore produced non-finite values (" + std::to_string(bad) + " of " + std::to_string(total) +
           " restored samples)";
}

} // namespace

void SuperResolution::checkLastRestore() const
{
    if (lastRestoreSamples_ == 0) return;
    uint32_t bad = 0;
    std::memcpy(&bad, check_.mapped, sizeof bad);
    if (bad) throw Error(nonFiniteMessage(label(), bad, lastRestoreSamples_));
}

void SuperResolution::beginTimestamps(VkCommandBuffer cmd)
{
    profiledOps_.clear();
    if (!queries_) return;
    vkCmdResetQueryPool(cmd, queries_, 0, queryCount_);
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_, 0);
}

void SuperResolution::markTimestamp(VkCommandBuffer cmd, std::string name, std::string kind, uint64_t multiplyAdds)
{
    if (!queries_) return;
    profiledOps_.push_back({std::move(name), std::move(kind), 0.0, multiplyAdds});
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, uint32_t(profiledOps_.size()));
}

std::vector<SrOpTiming> SuperResolution::profile() const
{
    if (!queries_ || profiledOps_.empty()) return {};
    std::vector<uint64_t> ticks(profiledOps_.size() + 1);
    NGI_VK_CHECK(vkGetQueryPoolResults(context_.device, queries_, 0, uint32_t(ticks.size()), ticks.size() * 8,
                                       ticks.data(), 8, VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    std::vector<SrOpTiming> ops = profiledOps_;
    const double period = context_.properties.limits.timestampPeriod;
    for (size_t i = 0; i < ops.size(); ++i) ops[i].milliseconds = double(ticks[i + 1] - ticks[i]) * period * 1e-6;
    return ops;
}

nn::FeatureMap SuperResolution::run(const nn::FeatureMap& positions, const nn::FeatureMap& normals)
{
    if (!explicitDims_.empty()) throw Error("super-resolution: run() needs a whole network");
    if (positions.channels != 3 || normals.channels != 3 || positions.width != normals.width ||
        positions.height != normals.height || positions.width < 2 || positions.height < 2 ||
        positions.data.size() != size_t(3) * positions.width * positions.height ||
        normals.data.size() != positions.data.size())
        throw Error("super-resolution: inputs must be 3 x H x W position and normal maps of equal size, H, W >= 2");
    prepare(positions.width, positions.height);
    const nn::FeatureMap inputs[2] = {positions, normals};
    nn::FeatureMap out = runHost(inputs);
    const size_t plane = size_t(out.width) * out.height;
    uint64_t bad = 0;
    for (size_t p = 0; p < plane; ++p)
        bad += !(std::isfinite(out.data[p]) && std::isfinite(out.data[plane + p]) && std::isfinite(out.data[2 * plane + p]));
    if (bad) throw Error(nonFiniteMessage(label(), bad, plane));
    return out;
}

nn::FeatureMap SuperResolution::runHost(std::span<const nn::FeatureMap> inputs, uint32_t repeats)
{
    Workspace& ws = *workspace_;
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
            for (uint32_t r = 0; r < repeats; ++r) recordLayers(cmd);
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

nn::FeatureMap runSuperResolutionLayer(const Context& context, const NetworkLayer& layer, std::span<const float> parameters,
                                     std::span<const nn::FeatureMap> inputs, uint32_t outputWidth, uint32_t outputHeight,
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
    SuperResolution sr(context, net, timed, shapes, repeats + 4);
    sr.hostInputs_ = n;
    for (const nn::FeatureMap& t : inputs) {
        if (t.data.size() != size_t(t.channels) * t.width * t.height) throw Error("super-resolution layer: bad input size");
        sr.explicitDims_.push_back({t.channels, t.width, t.height});
    }
    sr.explicitDims_.push_back({layer.outChannels, outputWidth, outputHeight});
    sr.prepare(inputs[0].width, inputs[0].height);
    nn::FeatureMap result = sr.runHost(inputs, repeats + 1);
    if (gpuMilliseconds) {
        const std::vector<SrOpTiming> ops = sr.profile();
        if (ops.size() != repeats + 1) throw Error("super-resolution layer: this device has no timestamps");
        gpuMilliseconds->clear();
        for (size_t i = 1; i < ops.size(); ++i) gpuMilliseconds->push_back(ops[i].milliseconds);
    }
    return result;
}

} // namespace ngi::vk
