// ngi offline eval, peers: Draco encoding and decoding of a triangle mesh (positions only,
// 14-bit quantization by default), docs/DESIGN.md "Metrics" (peers at equal bytes).
#include "ngi/eval/draco_codec.h"

#include "ngi/error.h"
#include "surface_checks.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>

#include <array>
#include <memory>

namespace ngi {

std::vector<uint8_t> encodeDraco(const TriangleMesh& mesh, const DracoOptions& options)
{
    detail::checkSurface(mesh, "draco: mesh");
    if (options.positionQuantizationBits < 1 || options.positionQuantizationBits > 30)
        throw Error("draco: position quantization bits must be in [1, 30], got " +
                    std::to_string(options.positionQuantizationBits));
    if (options.compressionLevel < 0 || options.compressionLevel > 10)
        throw Error("draco: compression level must be in [0, 10], got " + std::to_string(options.compressionLevel));

    // Compact to the used vertices of proper triangles.
    std::vector<uint32_t> remap(mesh.positions.size(), UINT32_MAX);
    std::vector<glm::dvec3> points;
    std::vector<std::array<uint32_t, 3>> faces;
    for (const glm::uvec3& t : mesh.triangles) {
        if (t.x == t.y || t.y == t.z || t.z == t.x) continue;
        std::array<uint32_t, 3> f;
        for (int k = 0; k < 3; ++k) {
            if (remap[t[k]] == UINT32_MAX) {
                remap[t[k]] = uint32_t(points.size());
                points.push_back(mesh.positions[t[k]]);
            }
            f[k] = remap[t[k]];
        }
        faces.push_back(f);
    }
    if (faces.empty()) throw Error("draco: mesh has no proper triangle");

    draco::Mesh dm;
    dm.set_num_points(uint32_t(points.size()));
    draco::GeometryAttribute position;
    position.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, sizeof(float) * 3, 0);
    const int attribute = dm.AddAttribute(position, true, uint32_t(points.size()));
    draco::PointAttribute* pa = dm.attribute(attribute);
    for (uint32_t i = 0; i < points.size(); ++i) {
        const float v[3] = {float(points[i].x), float(points[i].y), float(points[i].z)};
        pa->SetAttributeValue(draco::AttributeValueIndex(i), v);
    }
    for (const auto& f : faces) dm.AddFace({draco::PointIndex(f[0]), draco::PointIndex(f[1]), draco::PointIndex(f[2])});

    draco::Encoder encoder;
    encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, options.positionQuantizationBits);
    const int speed = 10 - options.compressionLevel;
    encoder.SetSpeedOptions(speed, speed);
    draco::EncoderBuffer buffer;
    const draco::Status status = encoder.EncodeMeshToBuffer(dm, &buffer);
    if (!status.ok()) throw Error(std::string("draco: encoding failed: ") + status.error_msg());
    return std::vector<uint8_t>(buffer.data(), buffer.data() + buffer.size());
}

TriangleMesh decodeDraco(std::span<const uint8_t> bytes, const std::string& name)
{
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    auto type = draco::Decoder::GetEncodedGeometryType(&buffer);
    if (!type.ok() || type.value() != draco::TRIANGULAR_MESH)
        throw Error(name + ": not a Draco triangle mesh" +
                    (type.ok() ? std::string() : std::string(" (") + type.status().error_msg() + ")"));
    draco::Decoder decoder;
    auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
    if (!decoded.ok()) throw Error(name + ": Draco decoding failed: " + decoded.status().error_msg());
    const draco::Mesh& dm = *decoded.value();
    const draco::PointAttribute* pa = dm.GetNamedAttribute(draco::GeometryAttribute::POSITION);
    if (pa == nullptr || pa->num_components() != 3) throw Error(name + ": Draco mesh has no 3D positions");

    TriangleMesh mesh;
    mesh.positions.reserve(dm.num_points());
    for (uint32_t i = 0; i < dm.num_points(); ++i) {
        float v[3] = {0.0f, 0.0f, 0.0f};
        if (!pa->ConvertValue<float, 3>(pa->mapped_index(draco::PointIndex(i)), v))
            throw Error(name + ": Draco positions cannot be read as floats");
        mesh.positions.push_back({v[0], v[1], v[2]});
    }
    mesh.triangles.reserve(dm.num_faces());
    for (uint32_t f = 0; f < dm.num_faces(); ++f) {
        const draco::Mesh::Face& face = dm.face(draco::FaceIndex(f));
        mesh.triangles.push_back({face[0].value(), face[1].value(), face[2].value()});
    }
    return mesh;
}

}  // namespace ngi
