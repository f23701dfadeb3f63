// ngi offline eval, report pictures (see report_picture.h): an orthographic z-buffer
// rasterizer with edge functions, one flat normal per triangle, two-sided Lambert shading
// under a fixed light, rendered at 2x and box-filtered down.
#include "ngi/eval/report_picture.h"

#include "ngi/error.h"
#include "ngi/png_io.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

namespace ngi {

namespace {

struct ViewBasis {
    glm::dvec3 right, up, back;  // back: from the centre towards the camera
};

ViewBasis viewBasis(double yawDegrees, double pitchDegrees)
{
    const double yaw = yawDegrees * std::numbers::pi / 180.0;
    const double pitch = pitchDegrees * std::numbers::pi / 180.0;
    ViewBasis b;
    b.back = {std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch)};
    b.right = glm::normalize(glm::cross(glm::dvec3(0, 1, 0), b.back));
    b.up = glm::cross(b.back, b.right);
    return b;
}

}  // namespace

PictureView pictureViewFor(const TriangleMesh& reference, double yawDegrees, double pitchDegrees)
{
    // Frame the reference's projection: its screen-space box, centred, the longer side filling.
    const ViewBasis basis = viewBasis(yawDegrees, pitchDegrees);
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-lo);
    bool any = false;
    for (const glm::uvec3& t : reference.triangles)
        for (int k = 0; k < 3; ++k) {
            if (t[k] >= reference.positions.size()) continue;
            const glm::dvec3 p = reference.positions[t[k]];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw Error("picture: the reference mesh has a non-finite coordinate");
            const glm::dvec3 q(glm::dot(p, basis.right), glm::dot(p, basis.up), glm::dot(p, basis.back));
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
            any = true;
        }
    if (!any) throw Error("picture: the reference mesh has no triangle");
    const glm::dvec3 mid = 0.5 * (lo + hi);
    PictureView view;
    view.centre = mid.x * basis.right + mid.y * basis.up + mid.z * basis.back;
    view.radius = std::max(0.5 * std::max(hi.x - lo.x, hi.y - lo.y), 1e-12);
    view.yawDegrees = yawDegrees;
    view.pitchDegrees = pitchDegrees;
    return view;
}

namespace {

// renderMeshPicture with triangle t's front face in colourOf(t).
template <class ColourOf>
RgbImage renderMeshPictureWith(const TriangleMesh& mesh, const PictureView& view, uint32_t size,
                               const ColourOf& colourOf)
{
    const uint32_t n = std::max(1u, size) * 2;  // supersampled side
    const ViewBasis basis = viewBasis(view.yawDegrees, view.pitchDegrees);
    const glm::dvec3 right = basis.right, up = basis.up, back = basis.back;
    const double pixelsPerUnit = 0.5 * n / (view.radius * 1.06);
    const glm::dvec3 light = glm::normalize(glm::dvec3(-0.35, 0.55, 1.0));  // view space

    std::vector<float> depth(size_t(n) * n, -std::numeric_limits<float>::infinity());
    std::vector<glm::vec3> pixels(size_t(n) * n, glm::vec3(1.0f));

    std::vector<glm::dvec3> screen(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        const glm::dvec3 d = mesh.positions[i] - view.centre;
        screen[i] = {0.5 * n + glm::dot(d, right) * pixelsPerUnit, 0.5 * n - glm::dot(d, up) * pixelsPerUnit,
                     glm::dot(d, back)};  // larger z = nearer the camera
    }
    for (size_t ti = 0; ti < mesh.triangles.size(); ++ti) {
        const glm::uvec3& t = mesh.triangles[ti];
        if (t.x >= screen.size() || t.y >= screen.size() || t.z >= screen.size()) continue;
        const glm::dvec3 a = screen[t.x], b = screen[t.y], c = screen[t.z];
        if (!std::isfinite(a.x + a.y + a.z + b.x + b.y + b.z + c.x + c.y + c.z)) continue;
        // Face normal in view space (x right, y up, z towards the camera).
        const glm::dvec3 pa = mesh.positions[t.x], pb = mesh.positions[t.y], pc = mesh.positions[t.z];
        glm::dvec3 normal = glm::cross(pb - pa, pc - pa);
        const double length = glm::length(normal);
        if (!(length > 0.0)) continue;
        normal /= length;
        const glm::dvec3 viewNormal(glm::dot(normal, right), glm::dot(normal, up), glm::dot(normal, back));
        const bool front = viewNormal.z >= 0.0;
        const double lambert = std::fabs(glm::dot(viewNormal, light));
        const glm::vec3 base = front ? colourOf(ti) : glm::vec3(0.55f, 0.15f, 0.15f);
        const glm::vec3 shaded = base * float(0.22 + 0.78 * lambert);

        const double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        if (area == 0.0) continue;
        const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
        const int x1 = std::min(int(n) - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
        const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}))));
        const int y1 = std::min(int(n) - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const double sx = x + 0.5, sy = y + 0.5;
                const double w0 = ((b.x - sx) * (c.y - sy) - (b.y - sy) * (c.x - sx)) / area;
                const double w1 = ((c.x - sx) * (a.y - sy) - (c.y - sy) * (a.x - sx)) / area;
                const double w2 = 1.0 - w0 - w1;
                if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
                const float z = float(w0 * a.z + w1 * b.z + w2 * c.z);
                const size_t i = size_t(y) * n + size_t(x);
                if (z > depth[i]) {
                    depth[i] = z;
                    pixels[i] = shaded;
                }
            }
    }

    RgbImage image;
    image.width = image.height = n / 2;
    image.rgb.resize(size_t(image.width) * image.height * 3);
    for (uint32_t y = 0; y < image.height; ++y)
        for (uint32_t x = 0; x < image.width; ++x) {
            glm::vec3 sum(0.0f);
            for (uint32_t dy = 0; dy < 2; ++dy)
                for (uint32_t dx = 0; dx < 2; ++dx) sum += pixels[size_t(2 * y + dy) * n + 2 * x + dx];
            const glm::vec3 v = glm::clamp(sum * 0.25f, glm::vec3(0.0f), glm::vec3(1.0f));
            uint8_t* out = &image.rgb[(size_t(y) * image.width + x) * 3];
            for (int k = 0; k < 3; ++k) out[k] = uint8_t(std::lround(v[k] * 255.0f));
        }
    return image;
}

}  // namespace

RgbImage renderMeshPicture(const TriangleMesh& mesh, const PictureView& view, uint32_t size, glm::vec3 colour)
{
    return renderMeshPictureWith(mesh, view, size, [&](size_t) { return colour; });
}

RgbImage renderMeshPicture(const TriangleMesh& mesh, const PictureView& view, uint32_t size,
                           std::span<const glm::vec3> triangleColours)
{
    if (triangleColours.size() != mesh.triangles.size())
        throw Error("mesh picture: " + std::to_string(triangleColours.size()) + " colours for " +
                    std::to_string(mesh.triangles.size()) + " triangles");
    return renderMeshPictureWith(mesh, view, size, [&](size_t t) { return triangleColours[t]; });
}

glm::vec3 heatColour(double t)
{
    // Piecewise linear through five stops, evenly spaced in t.
    static const glm::vec3 stops[] = {{0.10f, 0.15f, 0.55f},
                                      {0.10f, 0.70f, 0.90f},
                                      {0.20f, 0.80f, 0.25f},
                                      {0.95f, 0.85f, 0.10f},
                                      {0.90f, 0.10f, 0.08f}};
    const double x = (std::isnan(t) ? 1.0 : std::clamp(t, 0.0, 1.0)) * 4.0;
    const int i = std::min(3, int(x));
    const float f = float(x - i);
    return stops[i] * (1.0f - f) + stops[i + 1] * f;
}

RgbImage contactSheet(const std::vector<RgbImage>& tiles, uint32_t columns, uint32_t gap)
{
    if (tiles.empty()) throw Error("contact sheet: no tiles");
    if (columns == 0) throw Error("contact sheet: zero columns");
    const uint32_t w = tiles[0].width, h = tiles[0].height;
    for (const RgbImage& t : tiles)
        if (t.width != w || t.height != h || t.rgb.size() != size_t(w) * h * 3)
            throw Error("contact sheet: tiles differ in size");
    const uint32_t cols = std::min<uint32_t>(columns, uint32_t(tiles.size()));
    const uint32_t rows = uint32_t((tiles.size() + cols - 1) / cols);
    RgbImage sheet;
    sheet.width = cols * w + (cols + 1) * gap;
    sheet.height = rows * h + (rows + 1) * gap;
    sheet.rgb.assign(size_t(sheet.width) * sheet.height * 3, 255);
    for (size_t i = 0; i < tiles.size(); ++i) {
        const uint32_t ox = gap + uint32_t(i % cols) * (w + gap), oy = gap + uint32_t(i / cols) * (h + gap);
        for (uint32_t y = 0; y < h; ++y)
            std::copy_n(&tiles[i].rgb[size_t(y) * w * 3], size_t(w) * 3,
                        &sheet.rgb[(size_t(oy + y) * sheet.width + ox) * 3]);
    }
    return sheet;
}

void writeRgbPng(const std::filesystem::path& path, const RgbImage& image)
{
    if (image.rgb.size() != size_t(image.width) * image.height * 3 || image.width == 0)
        throw Error(path.string() + ": inconsistent RGB image");
    writePng8(path, image.width, image.height, 3, image.rgb.data());
}

}  // namespace ngi
