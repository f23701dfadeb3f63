// ngi core: a compact coder for one stored level of a geometry image, across its nested
// mip pyramid (issue 14).
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
// Payload layouts (all versions start with a u8 codec version, 1):
//   positions: u8 1, u8 levelCount (= log2(size - 1) + 1, the 2 x 2 level included), u8
//              tangent scale (0: xyz residuals), levelCount u16 steps (coarse to fine), then
//              the range-coded stream.
//   normals:   u8 1, u8 flags (bit 0: prediction sign flipped), u8 bits, then the stream.
// Decoding is safe on any bytes: every loop is bounded by the sample count, values are
// clamped to the 16-bit range, and a stream that ends early, has bytes left over or
// declares a step or level count it cannot have is an ngi::Error naming `name`.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ngi {

// Largest step: 2^12 of 65536, i.e. 1/16 of the bounding box.
inline constexpr uint32_t kMaxPyramidStep = 4096;
inline constexpr uint32_t kMaxTangentScale = 16;

struct PyramidCodecOptions {
    uint32_t step = 1;                  // every level's step, in units of 1/65536 of the box
    std::vector<uint16_t> levelSteps;   // optional: one per level, coarse (2 x 2) to fine; overrides step
    // 0: residuals in x, y, z. T in [1, 16]: residuals in a local frame (the normal from the
    // decoded neighbours, two tangents), the tangent components with a T times larger step.
    uint32_t tangentScale = 0;
    std::vector<size_t>* levelBytes = nullptr;  // optional out: stream bytes per level (to within the flush)
    // Optional seam mates: for each sample (y * size + x) the id (a sample index) of its mate
    // class, or its own index. A sample whose class already has a decoded member is not coded
    // and copies that member, so mates decode bitwise identical (seam.h).
    std::span<const uint32_t> mates;
};

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

// What a positions payload's header says (zeros when it is too short to say).
struct PyramidPayloadInfo {
    uint32_t finestStep = 0, tangentScale = 0;
};
PyramidPayloadInfo pyramidPayloadInfo(std::span<const uint8_t> payload);

// The normals the positions imply: size * size * 3 u16 in the asset's normal encoding
// ((n + 1) / 2 * 65535), from decoded positions. `flip` reverses the orientation.
std::vector<uint16_t> normalsFromPositions(std::span<const uint16_t> positions, uint32_t size, bool flip);

// Codes `normals` (the asset's u16 normal encoding) given the DECODED positions; bits in
// [0, 16]: 0 stores no residual (the decoder uses the prediction).
std::vector<uint8_t> encodePredictedNormals(std::span<const uint16_t> decodedPositions, std::span<const uint16_t> normals,
                                            uint32_t size, uint32_t bits, std::span<const uint32_t> mates = {});

// Decodes a payload of encodePredictedNormals with the same decoded positions.
std::vector<uint16_t> decodePredictedNormals(std::span<const uint8_t> payload, std::span<const uint16_t> decodedPositions,
                                             uint32_t size, const std::string& name, std::span<const uint32_t> mates = {});

} // namespace ngi
