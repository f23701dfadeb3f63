// ngi engine: the super-resolution network as GLSL compute (paper section 3.2: the CNN
// restores the full-resolution geometry image from the stored low-resolution level in one
// forward pass, on the GPU).
//
// A SuperResolution executes any network of the weights file (ngi/network_weights.h): one
// small compute kernel per op kind (shaders/sr_conv.comp, sr_attention.comp,
// sr_pixel_shuffle.comp, sr_bilinear_skip.comp) plus an input pass (stored RGBA32UI level ->
// tensors 0 and 1) and an output pass (output tensor -> level-0 RGBA32UI texels; normals are
// the stored normals interpolated by Catmull-Rom: shaders/sr_output.comp). Activation tensors are fp32
// "C4 planes" in texel buffers (ngi_shared.h); conv weights are uploaded once, repacked as
// one mat4 per (4 output channels, 4 input channels, tap) in 64 KiB uniform-buffer windows.
// Tensors are allocated per input size and aliased by liveness (a buffer is reused as soon
// as the tensor it holds has had its last reader). A BilinearSkip whose fine input is the
// output of the conv just before it (and read by nothing else) runs in that conv's epilogue.
//
// Hostile weights: the network is validated (ngi/network_weights.h, resource limits included)
// before anything is built, and every error names it (networkLabel: the weights path, or
// the asset's WGHT chunk). Finite but extreme parameters can still overflow to NaN or
// infinity at run time; the output pass counts the restored samples that are not finite and
// checkRestores() turns any into an ngi::Error, so a broken network never silently
// yields a blank image. Only the restored positions are checked on the GPU (counting every
// layer's tensor would cost a pass each); the CPU reference checks every layer.
//
// Several restores, one command buffer: record() may be called many times before any of
// the work runs (e.g. every chart of an asset in one submission, or in several command
// buffers submitted in order to ONE queue). Each restore gets its own descriptor sets (its
// images) and its own non-finite counter; the tensors are kept per input size and shared by
// the restores of that size, which a barrier at the start of each restore orders. All of it
// stays until checkRestores() (or releaseTensors()), which must come after the recorded work
// has completed, as must the destruction of the object. Not thread-safe: one thread records.
#pragma once

#include "ngi/engine/context.h"
#include "ngi/engine/resources.h"
#include "ngi/network_weights.h"
#include "ngi/nn/feature_map.h"

#include <vulkan/vulkan.h>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace ngi::vk {

struct SrPipelineKey;  // shader + specialization constants (engine/src/sr_kernels.h)

// Conv kernel shape (shaders/sr_conv.comp): output channel groups of 4 and pixels per
// invocation. 0 = the engine's choice (measured, see ngi-bench-sr --sweep).
struct SrConvShape {
    uint32_t groupsPerInvocation = 0;
    uint32_t pixelsPerInvocation = 0;
};

struct SuperResolutionOptions {
    SrConvShape conv3x3;
    SrConvShape conv1x1;
    // Records a timestamp after every dispatch (see SuperResolution::profile).
    bool profile = false;
    // The pipelines are created through this cache when it is not VK_NULL_HANDLE (owned by
    // the caller, e.g. a PipelineCacheFile kept on disk; ngi/engine/pipeline_cache.h).
    VkPipelineCache pipelineCache = VK_NULL_HANDLE;
};

// GPU time of one op of the last profiled record(), read back with profile().
struct SrOpTiming {
    std::string name;  // "conv3x3 32->32 129x129", "attention", "input", "output", ...
    std::string kind;  // "conv3x3", "conv1x1", "attention", "pixel_shuffle", "bilinear_skip", "io"
    double milliseconds = 0.0;
    uint64_t multiplyAdds = 0;  // conv and attention; 0 for data movement
};

class SuperResolution {
public:
    // Validates `network` (ngi::Error "LABEL: problem", LABEL = networkLabel(network)), builds
    // the pipelines and uploads the weights (waits for the upload). ngi::Error naming the
    // network and the layer if a conv layer's weights for one group of 4 output channels
    // exceed a 64 KiB uniform window (more than 452 input channels at 3x3).
    // Every pipeline the network needs (specialized per conv shape: input groups, kernel,
    // block) is created here, through options.pipelineCache when given. Drivers that
    // compile at creation then cost the first record() nothing. Lavapipe does not: it
    // compiles at the first dispatch, so the first restore is slow until Mesa's own shader
    // cache ($XDG_CACHE_HOME/mesa_shader_cache) is warm (docs/performance.md measures it).
    SuperResolution(const Context& context, const NetworkWeights& network, const SuperResolutionOptions& options = {});
    ~SuperResolution();
    SuperResolution(const SuperResolution&) = delete;
    SuperResolution& operator=(const SuperResolution&) = delete;

    uint32_t scaleFactor() const { return network_.scaleFactor; }
    const NetworkWeights& network() const { return network_; }
    // What error messages call the network (networkLabel: its path or "A.ngi (WGHT chunk)").
    std::string label() const { return networkLabel(network_); }

    // Samples per side of the output for `stored` samples per side: (stored - 1) * f + 1.
    uint32_t outputSize(uint32_t stored) const { return (stored - 1) * network_.scaleFactor + 1; }

    // Records the forward pass: `storedLevel` is a geometry-image level (RGBA32UI, xyz =
    // position bits in [0,1]^3, w = octahedral normal; GeometryImageSurface's level format),
    // W x H >= 2 x 2, in VK_IMAGE_LAYOUT_GENERAL and readable by compute shaders (the caller
    // orders its upload before this). `fullLevel` (RGBA32UI, GENERAL, ((W-1)f+1) x ((H-1)f+1))
    // receives the restored positions and the interpolated stored normals; it is written by a
    // compute shader and the caller orders its later reads with a compute-write barrier.
    // Allocates (or reuses) the tensors for this input size. ngi::Error on wrong formats or
    // sizes, or tensors beyond the device's texel buffer limit (naming the network).
    // Any number of restores may be recorded before their work runs (see the top of this
    // file); each keeps its descriptor sets and counter until checkRestores().
    // fullLevel holds non-finite positions if the weights overflow: call checkRestores()
    // once this work has completed, before using fullLevel.
    // `residualGain` (the chart's AssetChart::residualGain, in [0, 1]) blends the output toward
    // the Catmull-Rom cubic of the stored level, c + g (network - c), as ngi::nn::referenceForward
    // does (1: the network as trained, the same pipelines; 0: the bicubic); ngi::Error outside
    // [0, 1] or, when not 1, for a network whose output is not written by a skip layer.
    void record(VkCommandBuffer cmd, const Image& storedLevel, const Image& fullLevel, float residualGain = 1.0f);

    // After the work of every record() so far has completed (e.g. after
    // Context::submitAndWait): throws ngi::Error "LABEL: the restore produced non-finite
    // values (N of M restored samples)" if any of those restores wrote a NaN or infinite
    // position (N, M: the first such restore's counts), and in every case recycles their
    // descriptor sets and counters for the next record(). Does nothing when nothing was
    // recorded since the last check. Cost: one 4-byte host read per restore.
    void checkRestores();
    // The earlier name of checkRestores() (one restore per submission).
    void checkLastRestore() { checkRestores(); }
    // Restores recorded and not yet checked.
    size_t pendingRestores() const { return pending_.size(); }

    // Runs the network on host feature maps (3 x H x W positions and normals) and returns
    // the output tensor (3 x ((H-1)f+1) x ((W-1)f+1)); waits for the GPU. For tests and tools.
    // Throws the checkLastRestore() error if the output holds a NaN or an infinity.
    // `residualGain` as record().
    nn::FeatureMap run(const nn::FeatureMap& positions, const nn::FeatureMap& normals, float residualGain = 1.0f);

    // Per-op GPU times of the last record()/run() when options.profile is set (waits for
    // nothing: call after the work completed). Empty otherwise.
    std::vector<SrOpTiming> profile() const;

    // Device memory currently held: weights + tensors of every input size recorded since the
    // last releaseTensors() (bytes).
    VkDeviceSize gpuBytes() const;

    // Frees the tensors of every input size and the per-restore state (e.g. after the
    // surfaces are built; the recorded work must have completed, and is no longer checked:
    // call checkRestores() first); the next record() reallocates.
    void releaseTensors();

    // Compute pipelines this object created (all of them, at construction).
    size_t pipelineCount() const;

    struct Workspace;  // tensors, descriptor sets of one input size (sr_workspace.cpp)
    struct Restore;    // descriptor sets and non-finite counter of one record() (super_resolution.cpp)
    struct Kernels;    // pipelines (sr_kernels.cpp)

private:
    friend nn::FeatureMap runSuperResolutionLayer(const Context&, const NetworkLayer&, std::span<const float>,
                                                  std::span<const nn::FeatureMap>, uint32_t, uint32_t,
                                                  const SuperResolutionOptions&, std::vector<double>*);
    SuperResolution(const Context& context, const NetworkWeights& network, const SuperResolutionOptions& options,
                    std::vector<TensorShape> shapes, uint32_t extraQueries = 0, bool imagePasses = true);
    // The workspace of this input size, created on first use.
    Workspace& prepare(uint32_t width, uint32_t height);
    // outputGain: the residual gain of the skip that writes the output tensor (1 elsewhere).
    void recordLayers(VkCommandBuffer cmd, const Workspace& ws, float outputGain = 1.0f);
    void checkResidualGain(float gain) const;
    // Compiles every pipeline the op list uses (constructor).
    void createPipelines(bool imagePasses);
    // The pipeline (shader + specialization) of layer li.
    // blend: the variant that blends the output toward the cubic (a residual gain other than 1).
    SrPipelineKey pipelineKey(size_t li, bool blend = false) const;
    // Per-restore state for a record() on `ws`: a spare one or a new one, now pending.
    Restore& acquireRestore(const Workspace& ws);
    void beginTimestamps(VkCommandBuffer cmd);
    void markTimestamp(VkCommandBuffer cmd, std::string name, std::string kind, uint64_t multiplyAdds);
    // Uploads host tensors 0..n-1, records the layers, reads the output tensor back.
    nn::FeatureMap runHost(const Workspace& ws, std::span<const nn::FeatureMap> inputs, uint32_t repeats = 1,
                           float outputGain = 1.0f);

    const Context& context_;
    NetworkWeights network_;
    SuperResolutionOptions options_;
    std::vector<TensorShape> shapes_;                    // per tensor: channels, grid factor
    std::vector<std::array<uint32_t, 3>> explicitDims_;  // single-layer runner: channels, width, height
    uint32_t hostInputs_ = 2;                            // tensors 0..n-1 are inputs
    std::unique_ptr<Kernels> kernels_;
    Buffer weights_;  // repacked conv weights, device-local
    struct ConvPlan {
        uint32_t groupsPerInvocation = 0, pixelsPerInvocation = 0;
        std::vector<uint32_t> blockOffsets;  // byte offset of each output block's weights window
    };
    std::vector<ConvPlan> convPlans_;  // per layer (empty for other kinds)
    std::vector<bool> fusedSkip_;      // per conv layer: the next layer, a BilinearSkip, runs in its epilogue
    std::vector<std::unique_ptr<Workspace>> workspaces_;  // one per input size
    std::vector<std::unique_ptr<Restore>> pending_;       // recorded, not yet checked
    std::vector<std::unique_ptr<Restore>> spare_;         // checked, reused by the next record()
    VkQueryPool queries_ = VK_NULL_HANDLE;
    uint32_t queryCount_ = 0;
    std::vector<SrOpTiming> profiledOps_;  // the timed ops of the last recording
};

// Runs ONE layer of a network on host tensors (inputs in the order of layer.inputs, only
// the used ones) with the engine's kernels; waits for the GPU. For the per-op tests and the
// kernel microbenchmarks: with `gpuMilliseconds`, the layer is recorded 1 + N times in one
// submission (N = its size on entry, at least 1) and the GPU time of each of the N repeats
// after the first (the warm-up) is returned in it.
nn::FeatureMap runSuperResolutionLayer(const Context& context, const NetworkLayer& layer,
                                       std::span<const float> parameters, std::span<const nn::FeatureMap> inputs,
                                       uint32_t outputWidth, uint32_t outputHeight,
                                       const SuperResolutionOptions& options = {},
                                       std::vector<double>* gpuMilliseconds = nullptr);

}  // namespace ngi::vk
