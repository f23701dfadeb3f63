// ngi: constants and push-constant layouts shared by C++ and GLSL (STYLE.md rule 2).
// Included by every shader and by the engine; the layouts are written once, here.
#ifndef NGI_SHARED_H
#define NGI_SHARED_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
namespace ngi::gpu {
using uint = uint32_t;
using vec4 = glm::vec4;
using mat4 = glm::mat4;
#endif

// Compute workgroups over geometry-image texels: NGI_TILE x NGI_TILE invocations.
#define NGI_TILE 8

// Geometry-image texels on the GPU are RGBA32UI: xyz = floatBitsToUint(position, normalized
// to the asset's bbox), w = packUnorm2x16(octahedral(normal)). Integer texels keep the float
// bits exact (a float format could flush the packed normal's bit pattern as a denormal).

// The shared topology-only index buffer: quad q's vertices are 4q + corner (0..3), indexed
// as (0, 1, 2), (0, 2, 3). 16-bit indices cover NGI_QUADS_PER_CHUNK quads; bigger grids are
// drawn in chunks with vertexOffset = 4 * NGI_QUADS_PER_CHUNK * chunk.
#define NGI_QUADS_PER_CHUNK 16384

// How a grid draw's vertices are numbered (DrawPushConstants::gridTopology, surface.vert).
#define NGI_GRID_NON_INDEXED 0   // 6 vertices per quad, no index buffer
#define NGI_GRID_QUAD_INDEXED 1  // 4 vertices per quad, the shared quad index buffer above
// One vertex per grid sample (gl_VertexIndex = j * N + i), indexed by the level's expanded
// index buffer (grid_expansion.comp): 6 indices per quad with the quad's chosen diagonal.
#define NGI_GRID_SHARED_VERTICES 2

// surface.vert's specialization constant NGI_SPEC_VERTEX_WAY: the one way of placing the
// grid's vertices a pipeline runs. ngi makes a pipeline per way (SurfacePipeline) rather
// than branch on a push constant: lavapipe runs both sides of every branch under lane
// masks, so one shader holding all the ways paid for all of them at every vertex.
#define NGI_SPEC_VERTEX_WAY 0
#define NGI_WAY_PER_QUAD 0           // gridSize == levelSize: corners are the level's samples
#define NGI_WAY_PER_QUAD_BILINEAR 1  // gridSize between level sizes: corners sampled bilinearly
#define NGI_WAY_SHARED 2             // NGI_GRID_SHARED_VERTICES
#define NGI_WAY_COUNT 3
// surface.vert's specialization constant NGI_SPEC_INSTANCED: 1 for batched draws (per-instance
// records, any world matrix), 0 for single draws (world = normalized space), for the same
// reason: a single draw then does not pay for the instance's world transform per vertex.
#define NGI_SPEC_INSTANCED 1

// The fragment stage's specialization constant NGI_SPEC_CUT_OUT (ngi's own shading,
// surface_shading.glsl): 1 where the base colour's alpha cuts the surface out (a chart whose
// alpha is not all 1, ChartColorImages::cutsOut). Without the test the shader has no discard,
// so a GPU may test and write depth before it runs (early fragment tests); ngi makes both
// pipelines and draws each surface with the one it needs.
#define NGI_SPEC_CUT_OUT 0

// Shading modes of surface.frag.
#define NGI_MODE_SHADED 0
#define NGI_MODE_NORMALS 1
#define NGI_MODE_WIREFRAME 2
#define NGI_MODE_LOD 3
#define NGI_MODE_BASE_COLOUR 4  // the chart's base colour, unlit (adaptive draws)

// mip_downsample.comp, mip_upsample.comp, morph_targets.comp.
struct MipPushConstants {
    uint fineSize;    // samples per side of the finer level
    uint coarseSize;  // samples per side of the coarser level ((fine - 1) / 2 + 1)
    uint pad0;
    uint pad1;
};

// seam_weld.comp: the (destination, source) perimeter pairs of one level.
struct SeamWeldPushConstants {
    uint resolution;  // cells per side of the level
    uint pairCount;
    uint pairOffset;  // first pair of this level in the buffer
    uint pad0;
};

// seam_weld_group.comp: one pass (gather or scatter) over one chart's pairs of one level.
struct GroupWeldPushConstants {
    uint resolution;  // cells per side of the chart's level
    uint pairCount;
    uint pairOffset;  // first pair of this (level, chart, pass) in the buffer
    uint scatter;     // 0: image -> value slots, 1: value slots -> image
};

// surface.vert / surface.frag: one draw of the geometry-image grid.
struct DrawPushConstants {
    mat4 viewProjection;  // normalized asset space -> clip space
    vec4 eye;             // xyz: camera position in normalized asset space
    uint gridSize;        // vertices per side of the drawn grid N (2 .. full size)
    uint levelSize;       // samples per side of the mip level the grid samples
    float morph;          // 0..1: blend towards the next coarser level (geomorph)
    uint mode;            // NGI_MODE_*
    float lod;            // continuous LoD drawn (LoD colouring)
    float wireWidth;      // wireframe line width in pixels
    uint gridTopology;    // NGI_GRID_*: how gl_VertexIndex numbers the grid's vertices
    uint instanced;  // 1: a batched draw; per-instance data from DrawInstance[gl_InstanceIndex] (= NGI_SPEC_INSTANCED)
};

// grid_expansion.comp: one level's index buffer for shared-vertex draws
// (NGI_GRID_SHARED_VERTICES), written at run time; surface.vert geomorphs the samples itself.
#define NGI_EXPANSION_BINDING_DIAGONALS 0  // storage image RGBA32F: the level's quad diagonals (C, B, A)
#define NGI_EXPANSION_BINDING_INDICES 1    // storage buffer: 6 (N - 1)^2 16-bit indices, written
// The index buffer holds 16-bit indices in chunks of chunkRows quad rows, each drawn with
// vertexOffset = its first row * N: an index is a vertex's offset from its chunk's first
// sample ((chunkRows + 1) N <= 65535). Quad q's 6 indices are uints 3q .. 3q + 2 (two each,
// the first in the low half).
struct GridExpansionPushConstants {
    uint gridSize;   // samples per side of the level N
    float morph;     // geomorph factor the diagonals are chosen for
    uint chunkRows;  // quad rows per chunk of the index buffer
    uint pad0;
};

// The public vertex stage's descriptor sets (shaders/surface.vert; Renderer::drawLayout).
#define NGI_DRAW_SET_LEVEL 0  // level, geomorph targets, quad diagonals (combined image samplers)
// Set 0's binding for the fragment stage, in the uniform and the adaptive draw: the chart's base
// colour (sRGB sampler2D over its square, mipmapped; a 1 x 1 stand-in where the chart has none:
// chart_colour.glsl).
#define NGI_DRAW_BINDING_BASE_COLOUR 3
#define NGI_DRAW_SET_INSTANCES 1  // binding 0: readonly std430 buffer of DrawInstance
#define NGI_DRAW_HOST_SET 2       // the first set a host's own pipeline layout may add

// One instance of a batched draw (DrawBatch, surface.vert with DrawPushConstants::instanced):
// one record per chart per instance per DrawBatch::record, std430, 160 bytes.
struct DrawInstance {
    mat4 clipFromNormalized;   // normalized asset space -> clip space (the pass's viewProjection * world * asset)
    mat4 worldFromNormalized;  // normalized asset space -> world space (world * asset de-normalization)
    vec4 eye;                  // xyz: camera position in normalized asset space
    float morph;               // geomorph factor of this instance at the bucket's level
    float lod;                 // continuous LoD of this instance (LoD colouring)
    uint pad0;
    uint pad1;
};

// Adaptive LoD (ngi/adaptive_lod.h; engine/adaptive_draw.h, shaders/adaptive_surface.vert):
// one instance per selected tile, NGI_TILE_QUADS x NGI_TILE_QUADS quads of the tile's level,
// 6 non-indexed vertices per quad, alternating diagonals.
#define NGI_TILE_QUADS 4
#define NGI_TILE_BORDER_VERTICES (4 * NGI_TILE_QUADS)
// Border vertex b of a tile, counter-clockwise from its corner (0, 0) as perimeterSample
// numbers a square's border: b in [0, P] -> (b, 0), [P, 2P] -> (P, b - P), [2P, 3P] ->
// (3P - b, P), [3P, 4P) -> (0, 4P - b). Its state is 16 bits of border[b / 2] (low half
// first): bit 15 set = drawn one level coarser than the tile, bits 0..14 = morph x 32767.
#define NGI_TILE_COARSER_BIT 0x8000u
#define NGI_TILE_MORPH_SCALE 32767.0
// The adaptive draw's set 0: the tile level's texels and the next two coarser levels'
// (bindings 0, 1, 2; binding NGI_DRAW_BINDING_BASE_COLOUR = 3 is the chart's base colour,
// fragment stage), compact
// (RGBA16UI, ngi/compact_texel.h: xyz 16-bit unorm positions over this lattice of normalized
// space, w a 2 x 8-bit octahedral normal).
#define NGI_COMPACT_ORIGIN (-0.125)
#define NGI_COMPACT_EXTENT 1.25
#define NGI_ADAPTIVE_SET_LEVELS 0
// Set 1: binding 0 = readonly std430 buffer of AdaptiveTile (indexed by gl_InstanceIndex),
// binding 1 = readonly std430 buffer of AdaptiveInstance (indexed by the tile's instance).
#define NGI_ADAPTIVE_SET_TILES 1
// Sets 2..: a host pipeline's own (AdaptivePipeline's hostSetLayouts).
#define NGI_ADAPTIVE_HOST_SET 2
struct AdaptiveTile {
    uint x;  // tile origin in the level's samples (a multiple of NGI_TILE_QUADS)
    uint y;
    uint levelInstance;                         // bits 0..7: mip level drawn; 8..31: its AdaptiveInstance
    float morph;                                // interior geomorph factor towards level + 1
    uint border[NGI_TILE_BORDER_VERTICES / 2];  // 16-bit border vertex states, see above
};
// One instance of an adaptive draw (one AdaptiveSurface::recordDraw), std430, 144 bytes.
struct AdaptiveInstance {
    mat4 clipFromNormalized;   // normalized asset space -> clip space of the pass
    mat4 worldFromNormalized;  // normalized asset space -> world space
    vec4 eye;                  // xyz: the camera in normalized space
};

// The adaptive LoD's selection on the GPU (engine/gpu_tile_selection.h, shaders/select_*.comp,
// tile_selection.glsl): core's selectTiles (ngi/adaptive_lod.h) as per-tile passes. Tiles of
// every chart and level are numbered level by level, coarsest first; each level's run starts at
// a multiple of 32, so one invocation owns one 32-bit word of a tile bitset.
#define NGI_SELECT_LOCAL 64
#define NGI_SELECT_MAX_LEVELS 16
// Set 0 of every select pass.
#define NGI_SELECT_BINDING_TILES 0        // SelectionTile[tile]
#define NGI_SELECT_BINDING_CROSS 1        // uint[tile]: first (bits 0..23) | count << 24 into crossTiles
#define NGI_SELECT_BINDING_CROSS_TILES 2  // uint[]: tiles one level finer across a seam
#define NGI_SELECT_BINDING_CHARTS 3       // SelectionChart[chart]
#define NGI_SELECT_BINDING_PERIMETER 4    // uint[chart's perimeterFirst + t]: first | count << 24 into mates
#define NGI_SELECT_BINDING_MATES 5        // uint[]: chart << 16 | perimeter index t
#define NGI_SELECT_BINDING_VIEWS 6        // SelectionView[job]
#define NGI_SELECT_BINDING_BITS 7  // uint[]: per job, one bit per tile of levels >= 1 (refined by error, then refined)
#define NGI_SELECT_BINDING_COUNTERS 8   // uint[]: bucket counts, bucket cursors, per-job stats, wanted charts
#define NGI_SELECT_BINDING_COMMANDS 9   // VkDrawIndirectCommand[bucket]
#define NGI_SELECT_BINDING_RECORDS 10   // AdaptiveTile[]: the drawn tiles, bucket by bucket
#define NGI_SELECT_NO_TILE 0xFFFFFFFFu  // SelectionTile::chartLevel of the padding between levels
// Per-job statistics (counters[statsFirst + 4 * job + k]).
#define NGI_SELECT_STAT_DRAWN 0
#define NGI_SELECT_STAT_CULLED_FRUSTUM 1
#define NGI_SELECT_STAT_CULLED_BACKFACE 2
#define NGI_SELECT_STAT_TRIANGLES 3
// A tile's bound (ngi/tile_bound_code.h, the definition: the CPU selection decides on the same
// numbers) and its chart and level; its place (x, y) in its level follows from its index
// (tileAt in tile_selection.glsl).
struct SelectionTile {
    uint centreXY;       // the compact texel (ngi/compact_texel.h) of the sphere's centre
    uint centreZAxis;    // and the normal cone's axis: x | y << 16, z | axis << 16
    uint radiusConeCos;  // half floats: radius | coneCos << 16
    uint errors;         // half floats: error | errorUp << 16
    uint chartLevel;     // chart | level << 16 (NGI_SELECT_NO_TILE: padding)
};
struct SelectionChart {
    uint levelFirst[NGI_SELECT_MAX_LEVELS];  // tile (0, 0) of level l (l <= rootLevel)
    uint rootLevel;
    uint resolution;
    uint perimeterLevel;
    uint coarsestLevel;
    uint closed;          // every border sample has a mate: backface culling allowed
    uint finestDrawable;  // 0, or 1 while the chart's level 0 is not resident
    uint perimeterFirst;  // its full-resolution perimeter samples in NGI_SELECT_BINDING_PERIMETER
    uint bucketFirst;     // bucket of (group 0, level 0); + group * bucketsPerGroup + level
};
struct SelectionView {
    mat4 clipFromNormalized;
    vec4 planes[6];  // the frustum's inward unit planes (planeCount of them)
    vec4 eye;        // xyz: the camera in normalized space
    float gradW;     // |d w / d position|
    float rowY;      // |d y_clip / d position|
    float viewportHeight;
    float budget;  // pixels (camera) or normalized units
    uint flags;    // bit 0 camera, 1 cull, 2 backface (a perspective camera)
    uint planeCount;
    uint instance;  // the AdaptiveInstance of its records
    uint group;     // the buckets it draws into
};
struct SelectionPushConstants {
    uint level;      // the level of this pass (refine, close)
    uint firstTile;  // the level's first tile (a multiple of 32)
    uint tileCount;  // tiles of the pass
    uint jobCount;
    uint wordsPerJob;  // words of one bitset
    uint buckets;      // groups * bucketsPerGroup
    uint statsFirst;   // counters[statsFirst ..]: 4 per job, then one word per chart (wanted level 0)
    uint bucketsPerGroup;
    uint levelFlagsFirst;  // counters[levelFlagsFirst + job]: bit l when a tile of level l is refined,
                           // bit 16 + l when one is refined by error
    uint roots;            // 1 when a chart's root tile is at this level (refine, count, write)
    uint pad0;
    uint pad1;
};

// Super-resolution network (engine/src/super_resolution.cpp, shaders/sr_*.comp).
// Activation tensors are "C4 planes": channel c of pixel (x, y) is lane c % 4 of the rgba32f
// texel ((c / 4) * height + y) * width + x of a texel buffer (read as samplerBuffer, written
// as imageBuffer). Channels past the tensor's count in the last group are kept at 0.
#define NGI_SR_LOCAL_X 8
#define NGI_SR_LOCAL_Y 8
// Descriptor bindings of every SR op (one set layout; unused bindings hold a dummy).
#define NGI_SR_BINDING_IN0 0      // uniform texel buffer: input (conv, shuffle), q, coarse
#define NGI_SR_BINDING_IN1 1      // uniform texel buffer: residual, k, fine
#define NGI_SR_BINDING_IN2 2      // uniform texel buffer: v, coarse tensor of a conv's fused bilinear skip
#define NGI_SR_BINDING_OUT 3      // storage texel buffer: output tensor
#define NGI_SR_BINDING_WEIGHTS 4  // dynamic uniform buffer: conv weights window
#define NGI_SR_BINDING_LEVEL 5    // storage image RGBA32UI: stored level (input pass) or level 0 (output pass)
#define NGI_SR_BINDING_STORED 6   // storage image RGBA32UI: stored level (output pass: normal orientation)
#define NGI_SR_BINDING_CHECK 7    // storage buffer, one uint: output pass counts the non-finite restored samples
// Conv weights: one 64 KiB uniform-buffer window per dispatch (4096 vec4), see sr_conv.comp.
#define NGI_SR_UBO_VEC4S 4096
// SrPushConstants.flags
#define NGI_SR_REPLICATE 1u  // conv: clamp-to-edge padding (else zero padding)
// sr_bilinear_skip.comp's KIND specialization constant
#define NGI_SR_SKIP_BILINEAR 0  // BilinearSkip
#define NGI_SR_SKIP_CUBIC 1     // CubicSkip: Catmull-Rom
#define NGI_SR_SKIP_HERMITE 2   // HermiteSkip: normal-projected Hermite, normals at binding 2
// sr_conv.comp's EPILOGUE specialization constant (compile-time: see the shader's notes)
#define NGI_SR_EPILOGUE_RESIDUAL 1  // add the residual tensor (binding 1) after the activation
#define NGI_SR_EPILOGUE_SKIP 2      // then add upsample_x factor(coarse tensor, binding 2): a fused skip
#define NGI_SR_EPILOGUE_CUBIC 4     // that skip is Catmull-Rom (CubicSkip), else bilinear
#define NGI_SR_EPILOGUE_BLEND 8     // then blend toward the Catmull-Rom: c + residualGain (v - c)
// SrPushConstants.activation: values of ngi::Activation
#define NGI_SR_ACT_NONE 0u
#define NGI_SR_ACT_RELU 1u
#define NGI_SR_ACT_LEAKY 2u

// One dispatch of an SR op. width/height: the op's output grid; inWidth/inHeight: its
// (first) input's grid; groups = ceil(channels / 4).
struct SrPushConstants {
    uint width;
    uint height;
    uint inWidth;
    uint inHeight;
    uint inGroups;
    uint outGroups;  // groups of the output tensor
    uint groupBase;  // conv: first output group of this dispatch (its weights block)
    uint pad0;
    uint flags;          // NGI_SR_REPLICATE
    uint activation;     // NGI_SR_ACT_*
    float slope;         // LeakyReLU slope
    uint factor;         // pixel shuffle, bilinear skip, output pass: upsampling factor
    uint channels;       // pixel shuffle: output channels; attention: channels
    float scale;         // attention: logit scale
    float residualGain;  // the network's output skip with BLEND (sr_bilinear_skip.comp) or a fused
                         // skip with NGI_SR_EPILOGUE_BLEND: out = c + residualGain (out - c), c the
                         // Catmull-Rom of the coarse input (AssetChart::residualGain)
    uint pad2;
};

#ifdef __cplusplus
static_assert(sizeof(MipPushConstants) == 16);
static_assert(sizeof(SeamWeldPushConstants) == 16);
static_assert(sizeof(GroupWeldPushConstants) == 16);
static_assert(sizeof(GridExpansionPushConstants) == 16);
static_assert(sizeof(SrPushConstants) == 64);
static_assert(sizeof(SelectionTile) == 20, "std430 layout of SelectionTile");
static_assert(sizeof(SelectionChart) == 96, "std430 layout of SelectionChart");
static_assert(sizeof(SelectionView) == 208, "std430 layout of SelectionView");
static_assert(sizeof(SelectionPushConstants) == 48);
static_assert(sizeof(DrawPushConstants) == 112, "must fit the 128-byte push-constant minimum");
static_assert(sizeof(DrawInstance) == 160, "std430 layout of surface.vert's instance buffer");
}  // namespace ngi::gpu
#endif

#endif
