// ngi offline eval, report pictures: every mesh of a contact sheet (the input, each LoD the
// renderer draws, the peers) is drawn by the same small CPU z-buffer rasterizer, with the
// same camera and light, so the tiles differ only by their triangles. The LoD meshes are
// exactly the triangles the vertex shader draws (assetMesh, core's lod_grid.h), so the
// picture of a LoD is the engine's surface, flat shaded; drawing input and peers through the
// same path keeps the comparison fair (no Vulkan device needed for a report).
#pragma once

#include "ngi/mesh/triangle_mesh.h"

#include <glm/vec3.hpp>

#include <cstdint>
#include <filesystem>
#include <span>
#include <vector>

namespace ngi {

struct RgbImage {
    uint32_t width = 0, height = 0;
    std::vector<uint8_t> rgb;  // width * height * 3, row-major, top row first
};

// Orthographic camera looking at `centre` from direction (yaw, pitch), y up; a square of
// half-side `radius` around `centre` (in the view plane) fills the picture.
struct PictureView {
    glm::dvec3 centre{0.0};
    double radius = 1.0;
    double yawDegrees = 35.0;
    double pitchDegrees = 20.0;
};

// A view framing `reference`: its projection's screen-space box, centred, the longer side
// filling the picture. ngi::Error if the
// mesh has no vertex used by a triangle or a non-finite coordinate.
PictureView pictureViewFor(const TriangleMesh& reference, double yawDegrees = 35.0, double pitchDegrees = 20.0);

// Flat-shaded picture of `mesh` (size x size pixels, 2x2 supersampled): front faces in
// `colour`, back faces (open boundaries, flipped triangles seen from behind) in dark red.
// Triangles with an index out of range or a non-finite corner are skipped.
RgbImage renderMeshPicture(const TriangleMesh& mesh, const PictureView& view, uint32_t size,
                           glm::vec3 colour = {0.75f, 0.78f, 0.85f});

// The same with a colour per triangle: triangle t's front face in `triangleColours[t]` (back
// faces stay dark red), for a quantity over the surface (ngi-eval distance --heat-map).
// ngi::Error if there is not one colour per triangle.
RgbImage renderMeshPicture(const TriangleMesh& mesh, const PictureView& view, uint32_t size,
                           std::span<const glm::vec3> triangleColours);

// A heat colour for t in [0, 1] (clamped; NaN is 1): dark blue at 0, through cyan, green and
// yellow, to red at 1, so that equal steps of t read as equal steps of colour.
glm::vec3 heatColour(double t);

// Tiles (all the same size) in rows of `columns`, separated by `gap` white pixels.
// ngi::Error if tiles is empty, sizes differ, or columns == 0.
RgbImage contactSheet(const std::vector<RgbImage>& tiles, uint32_t columns, uint32_t gap = 4);

// Writes an 8-bit RGB PNG atomically. ngi::Error naming the path on failure.
void writeRgbPng(const std::filesystem::path& path, const RgbImage& image);

}  // namespace ngi
