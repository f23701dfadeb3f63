// ngi offline eval, peers: a triangle mesh's size on disk as users would ship it, with
// Google's Draco (edgebreaker connectivity + quantized, predicted positions). docs/DESIGN.md
// "Metrics": peers are compared at equal bytes, Draco with 14-bit positions.
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace ngi {

struct DracoOptions {
    int positionQuantizationBits = 14;  // docs/DESIGN.md: 14-bit positions (over the bbox's longest side)
    int compressionLevel = 10;          // 0 (fastest) .. 10 (smallest); draco_encoder's -cl.
                                        // 10: the peer at its best at equal bytes
};

// Encodes positions and triangles (no normals, no other attributes) as a Draco bitstream;
// its size is the peer's byte count. Vertices no triangle uses and triangles with a repeated
// vertex are left out (they hold no surface). Throws ngi::Error on an index out of range,
// a non-finite coordinate, no triangles, bits outside [1, 30], level outside [0, 10], or if
// Draco fails (its message is included).
std::vector<uint8_t> encodeDraco(const TriangleMesh& mesh, const DracoOptions& options = {});

// Decodes a Draco mesh bitstream back to a triangle mesh (positions as Draco restores them,
// i.e. quantized). `name` is used in error messages. Throws ngi::Error if the bytes are not
// a Draco triangle mesh with 3D positions.
TriangleMesh decodeDraco(std::span<const uint8_t> bytes, const std::string& name = "draco");

}  // namespace ngi
