// ngi core: a compact coder for one stored level of a geometry image, across its nested
// mip pyramid.
//
// Positions (the scheme of interpolating-wavelet geometry coders: Sweldens 1996, "The
// lifting scheme"; Khodakovsky, Schroeder, Sweldens 2000, "Progressive geometry
// compression"): the stored level (2^k + 1)^2 holds every coarser nested level (mip_pyramid.h:
// level L+1 = the even samples of level L). The 2 x 2 corners are coded first, then each
// finer level's new samples as residuals from a prediction out of the already DECODED
// samples: edge midpoints by the 4-tap cubic (-1, 9, 9, -1) / 16 along their row or column
// (linear where a tap falls off the grid), cell centres by the mean of that prediction along
// both axes from the level's decoded midpoints. Residuals are quantized uniformly with a
// step of q units of the 16-bit sample (q per level, any integer in [1, 4096]; q = 1 is
// lossless, q = 64 is 2^-10 of the normalized bounding box) and the encoder predicts from decoded values (closed loop),
// so every decoded sample is within step / 2 of its input. The quantized residuals are coded
// with an adaptive binary range coder (range_coder.h): zero flag, sign, Exp-Golomb exponent
// in unary and the two top mantissa bits with adaptive models, contexts by pass (row
// midpoint, column midpoint, centre), component and the magnitude of the already decoded
// residuals around the sample (the samples at distance 1 of the level's grid, of every
// level, and the sample's earlier components).
//
// Normals: predicted from the decoded positions (the cross product of central differences,
// one-sided at the border, oriented like the majority of the input's normals), then either
// kept as the prediction (bits = 0) or corrected by a residual: the normal's octahedral
// coordinates in the prediction's tangent frame, quantized to `bits` bits over [-1, 1].
//
// Payload layouts (each starts with a u8 codec version):
//   positions, one stream (codec 1, encodePyramidPositions; asset format 4): u8 1, u8
//              levelCount (= log2(size - 1) + 1, the 2 x 2 level included), u8 tangent scale
//              (0: xyz residuals), levelCount u16 steps (coarse to fine), then the
//              range-coded stream of every level.
//   positions, level by level (codec 2, encodePyramidLevels; asset format 5): the same
//              header with u8 2, and one stream per level: the coder is flushed at the end of
//              each level (about 4 bytes each) so that levels 0..l decode without the finer
//              ones (streaming: a prefix is the coarser nested level, bitwise). The adaptive
//              models carry on from level to level, so the residuals cost what they cost in
//              one stream. A stream's end is found by decoding it (range_coder.h): the streams
//              can be stored back to back with no lengths.
//   normals:   u8 1, u8 flags (bit 0: prediction sign flipped), u8 bits, then the stream.
// Decoding is safe on any bytes: every loop is bounded by the sample count, values are
// clamped to the 16-bit range, and a stream that ends early, has bytes left over or
// declares a step or level count it cannot have is an ngi::Error naming `name`.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace ngi {

// Largest step: 2^12 of 65536, i.e. 1/16 of the bounding box.
inline constexpr uint32_t kMaxPyramidStep = 4096;
inline constexpr uint32_t kMaxTangentScale = 16;

struct PyramidCodecOptions {
    uint32_t step = 1;                 // every level's step, in units of 1/65536 of the box
    std::vector<uint16_t> levelSteps;  // optional: one per level, coarse (2 x 2) to fine; overrides step
    // 0: residuals in x, y, z. T in [1, 16]: residuals in a local frame (the normal from the
    // decoded neighbours, two tangents), the tangent components with a T times larger step.
    uint32_t tangentScale = 0;
    // Optional out: stream bytes per level (one stream: to within the final flush; level by
    // level: each level's stream, its flush included).
    std::vector<size_t>* levelBytes = nullptr;
    // Optional seam mates: for each sample (y * size + x) the id (a sample index) of its mate
    // class, or its own index. A sample whose class already has a decoded member is not coded
    // and copies that member, so mates decode bitwise identical (seam.h).
    std::span<const uint32_t> mates;
};

// Graded steps: each coarser level coded `grade` times finer than the one above it. Level l of
// `levelCount` gets max(1, round(finestStep / grade^(levelCount - 1 - l))), clamped to
// kMaxPyramidStep. Why: a coarse level's quantization noise enters the prediction of every
// finer sample (closed loop), and a level holds a quarter of the samples of the next, so a finer
// coarse step costs few bits and shrinks the finer residuals (docs/rate-control.md measures it).
// Grade 1 is every level at finestStep.
// ngi::Error on a grade that is not finite or below 1, or a finest step outside [1, kMaxPyramidStep].
std::vector<uint16_t> gradedLevelSteps(uint32_t finestStep, uint32_t levelCount, double grade);

// The grades writers use (1: uniform, sqrt 2); stepGradeOf finds which one made `steps`.
inline constexpr double kPyramidStepGrades[] = {1.0, 1.4142135623730951};

// The grade of kPyramidStepGrades whose gradedLevelSteps(finest, count) is exactly `steps`,
// else 0 (steps no ngi writer makes: a rewrite then codes every level at the finest step).
double stepGradeOf(std::span<const uint16_t> steps);

// Number of levels of a size x size nested grid, the 2 x 2 corners included (2 -> 1, 3 -> 2,
// 129 -> 8). ngi::Error unless size = 2^k + 1 with 2 <= size <= 4097.
uint32_t pyramidLevelCount(uint32_t size);

// Codes `samples` (size * size * 3 u16, RGB interleaved, row-major). ngi::Error on a size
// that is not a nested grid size, a sample count that does not match or a step outside
// [1, kMaxPyramidStep].
std::vector<uint8_t> encodePyramidPositions(std::span<const uint16_t> samples, uint32_t size,
                                            const PyramidCodecOptions& options);

// Decodes a payload of encodePyramidPositions for a size x size level (the caller knows
// the size and has checked it against its own limits). Every decoded sample is within
// step / 2 of the encoded one. ngi::Error "NAME: problem" on any malformed payload.
// `mates` must be the encoder's (empty or size * size entries below size * size).
std::vector<uint16_t> decodePyramidPositions(std::span<const uint8_t> payload, uint32_t size, const std::string& name,
                                             std::span<const uint32_t> mates = {});

// What a positions payload's header says, codec 1 or 2 (zeros and no steps when it is too
// short to say or has another codec version).
struct PyramidPayloadInfo {
    uint32_t finestStep = 0, tangentScale = 0;
    std::vector<uint16_t> steps;  // every level's step, coarse (2 x 2) to fine
};
PyramidPayloadInfo pyramidPayloadInfo(std::span<const uint8_t> payload);

// A stored level coded level by level (codec 2): the header and one stream per level.
struct PyramidLevels {
    std::vector<uint8_t> header;               // pyramidLevelsHeaderBytes(size) bytes
    std::vector<std::vector<uint8_t>> levels;  // pyramidLevelCount(size) streams, level 0 (2 x 2) first
};

// Bytes of a codec-2 header for a size x size level (3 + 2 x levels). ngi::Error on a size
// that is not a nested grid size.
size_t pyramidLevelsHeaderBytes(uint32_t size);

// Codes `samples` level by level; same inputs, errors and decoded samples as
// encodePyramidPositions (the residuals and models are the same, only the flushes differ).
PyramidLevels encodePyramidLevels(std::span<const uint16_t> samples, uint32_t size, const PyramidCodecOptions& options);

// Decodes the levels of encodePyramidLevels one at a time, as they arrive. Memory: the
// whole size x size level (and its context state) from the start, ~12 bytes per sample.
class PyramidLevelDecoder {
public:
    // `header`: PyramidLevels::header, exactly; `mates`: the encoder's (empty or size * size
    // entries below size * size). ngi::Error "NAME: problem" on a bad size, header or mates.
    PyramidLevelDecoder(std::span<const uint8_t> header, uint32_t size, std::string name,
                        std::span<const uint32_t> mates = {});
    ~PyramidLevelDecoder();
    PyramidLevelDecoder(PyramidLevelDecoder&&) noexcept;
    PyramidLevelDecoder& operator=(PyramidLevelDecoder&&) = delete;

    // Decodes level levelsDecoded() from the start of `bytes` (its stream, possibly followed
    // by other bytes) and returns the bytes its stream took. ngi::Error naming the level if
    // the stream would run past `bytes` or every level is decoded; after an error the decoder
    // refuses every further level. Bounded work on any bytes.
    size_t decodeLevel(std::span<const uint8_t> bytes);
    uint32_t levelCount() const;
    uint32_t levelsDecoded() const;
    // The finest decoded level: decodedSize()^2 * 3 u16 (0 before any level is decoded),
    // bitwise the even samples of the full decode (the nested level). ngi::Error before the
    // first level.
    uint32_t decodedSize() const;
    std::vector<uint16_t> decodedLevel() const;
    const std::vector<uint16_t>& steps() const { return steps_; }
    uint32_t tangentScale() const { return tangentScale_; }

private:
    struct State;
    std::string name_;
    uint32_t size_ = 0;
    std::vector<uint16_t> steps_;
    uint32_t tangentScale_ = 0;
    std::unique_ptr<State> state_;
};

// Decodes the first levels.levels.size() levels (all of them: the stored level) of a
// PyramidLevels; each stream must be read to its last byte. ngi::Error "NAME: problem".
std::vector<uint16_t> decodePyramidLevels(const PyramidLevels& levels, uint32_t size, const std::string& name,
                                          std::span<const uint32_t> mates = {});

// The normals the positions imply: size * size * 3 u16 in the asset's normal encoding
// ((n + 1) / 2 * 65535), from decoded positions. `flip` reverses the orientation. With
// `mates` (as for the coders), a seam mate copies its class's first sample in raster order:
// what decodePredictedNormals gives for a prediction-only payload.
std::vector<uint16_t> normalsFromPositions(std::span<const uint16_t> positions, uint32_t size, bool flip,
                                           std::span<const uint32_t> mates = {});

// Codes `normals` (the asset's u16 normal encoding) given the DECODED positions; bits in
// [0, 16]: 0 stores no residual (the decoder uses the prediction).
std::vector<uint8_t> encodePredictedNormals(std::span<const uint16_t> decodedPositions,
                                            std::span<const uint16_t> normals, uint32_t size, uint32_t bits,
                                            std::span<const uint32_t> mates = {});

// Decodes a payload of encodePredictedNormals with the same decoded positions.
std::vector<uint16_t> decodePredictedNormals(std::span<const uint8_t> payload,
                                             std::span<const uint16_t> decodedPositions, uint32_t size,
                                             const std::string& name, std::span<const uint32_t> mates = {});

}  // namespace ngi
