// ngi-fuzz-seeds DIR: writes the fuzz targets' seed corpora, DIR/<target>/<name>, each a tiny
// valid input (a few hundred bytes) that takes its reader through its main paths: a
// tetrahedron in every mesh format (ASCII and binary variants, glTF with a node transform),
// assets of a 5x5 stored sphere level (with and without a WGHT chunk) and two networks
// (the smallest x2 one; one with every layer kind but CubicSkip). tools/make-fuzz-corpus.sh
// runs it to regenerate fuzz/corpus/.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/asset_legacy.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/network_weights.h"

#include <array>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

void writeFile(const fs::path& path, const std::vector<uint8_t>& bytes)
{
    fs::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!out) throw ngi::Error(path.string() + ": cannot write the seed");
}

void writeText(const fs::path& path, const std::string& text)
{
    writeFile(path, std::vector<uint8_t>(text.begin(), text.end()));
}

template <typename T> void put(std::vector<uint8_t>& out, T v)
{
    const size_t at = out.size();
    out.resize(at + sizeof v);
    std::memcpy(out.data() + at, &v, sizeof v);
}

// The tetrahedron every mesh seed holds, faces counter-clockwise from outside.
const float kVertices[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const uint16_t kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

std::string base64(const std::vector<uint8_t>& bytes)
{
    static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    for (size_t i = 0; i < bytes.size(); i += 3) {
        const uint32_t n = uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
            (i + 2 < bytes.size() ? bytes[i + 2] : 0);
        out += table[n >> 18 & 63];
        out += table[n >> 12 & 63];
        out += i + 1 < bytes.size() ? table[n >> 6 & 63] : '=';
        out += i + 2 < bytes.size() ? table[n & 63] : '=';
    }
    return out;
}

// glTF buffer: 4 float VEC3 positions (48 bytes), then 12 u16 indices (24 bytes).
std::vector<uint8_t> gltfBuffer()
{
    std::vector<uint8_t> b;
    for (const auto& v : kVertices)
        for (float c : v) put(b, c);
    for (const auto& f : kFaces)
        for (uint16_t i : f) put(b, i);
    return b;
}

std::string gltfJson(const std::string& bufferUri)
{
    const std::string uri = bufferUri.empty() ? "" : ",\"uri\":\"" + bufferUri + "\"";
    return "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
           "\"nodes\":[{\"children\":[1],\"translation\":[1,2,3]},{\"mesh\":0,\"rotation\":[0,0,0.7071068,0.7071068],"
           "\"scale\":[2,2,2]}],"
           "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":4}]}],"
           "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\",\"min\":[0,0,0],"
           "\"max\":[1,1,1]},"
           "{\"bufferView\":1,\"componentType\":5123,\"count\":12,\"type\":\"SCALAR\"}],"
           "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48,\"byteStride\":12},{\"buffer\":0,"
           "\"byteOffset\":48,\"byteLength\":24}],"
           "\"buffers\":[{\"byteLength\":72" +
        uri + "}]}";
}

void writeMeshSeeds(const fs::path& dir)
{
    std::string obj = "# tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n",
                objUv = obj + "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n";
    for (const auto& f : kFaces)
        obj += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " + std::to_string(f[2] + 1) + "\n";
    objUv += "f 1/1/1 3/3/1 2/2/1\nf 1/1 2/2 4/3\nf -4//1 -1//1 -2//1\nf 2 3 4\n";
    writeText(dir / "mesh_obj_fuzzer/tetrahedron.obj", obj);
    writeText(dir / "mesh_obj_fuzzer/tetrahedron-uv-normals.obj", objUv);

    std::string off = "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    for (const auto& f : kFaces)
        off += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    writeText(dir / "mesh_off_fuzzer/tetrahedron.off", off);
    writeText(
        dir / "mesh_off_fuzzer/tetrahedron-coff-comments.off",
        "# Output of a CGAL tool\nCOFF 4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n# vertex 2\n0 1 0 0 0 255 255\n"
        "0 0 1 9 9 9 255\n4 0 1 3 2\n3 1 2 3\n");

    const std::string plyHeader =
        "ply\nformat ascii 1.0\ncomment tetrahedron\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
    std::string ply = plyHeader + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    for (const auto& f : kFaces)
        ply += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
    writeText(dir / "mesh_ply_fuzzer/tetrahedron-ascii.ply", ply);
    std::string plyBinary = plyHeader;
    plyBinary.replace(plyBinary.find("ascii"), 5, "binary_little_endian");
    std::vector<uint8_t> plyBytes(plyBinary.begin(), plyBinary.end());
    for (const auto& v : kVertices)
        for (float c : v) put(plyBytes, c);
    for (const auto& f : kFaces) {
        put(plyBytes, uint8_t(3));
        for (uint16_t i : f) put(plyBytes, int32_t(i));
    }
    writeFile(dir / "mesh_ply_fuzzer/tetrahedron-binary.ply", plyBytes);

    std::string stl = "solid tetrahedron\n";
    std::vector<uint8_t> stlBytes(80, ' ');
    std::memcpy(stlBytes.data(), "binary tetrahedron", 18);
    put(stlBytes, uint32_t(4));
    for (const auto& f : kFaces) {
        stl += " facet normal 0 0 0\n  outer loop\n";
        for (int k = 0; k < 3; ++k) put(stlBytes, 0.0f);
        for (uint16_t i : f) {
            stl += "   vertex " + std::to_string(kVertices[i][0]) + " " + std::to_string(kVertices[i][1]) + " " +
                std::to_string(kVertices[i][2]) + "\n";
            for (float c : kVertices[i]) put(stlBytes, c);
        }
        stl += "  endloop\n endfacet\n";
        put(stlBytes, uint16_t(0));
    }
    stl += "endsolid tetrahedron\n";
    writeText(dir / "mesh_stl_fuzzer/tetrahedron-ascii.stl", stl);
    writeFile(dir / "mesh_stl_fuzzer/tetrahedron-binary.stl", stlBytes);

    const std::vector<uint8_t> buffer = gltfBuffer();
    writeText(dir / "mesh_gltf_fuzzer/tetrahedron.gltf",
              gltfJson("data:application/octet-stream;base64," + base64(buffer)));
    std::string json = gltfJson("");
    while (json.size() % 4) json += ' ';
    std::vector<uint8_t> glb;
    put(glb, uint32_t(0x46546C67));  // "glTF"
    put(glb, uint32_t(2));
    put(glb, uint32_t(12 + 8 + json.size() + 8 + buffer.size()));
    put(glb, uint32_t(json.size()));
    put(glb, uint32_t(0x4E4F534A));  // "JSON"
    glb.insert(glb.end(), json.begin(), json.end());
    put(glb, uint32_t(buffer.size()));
    put(glb, uint32_t(0x004E4942));  // "BIN\0"
    glb.insert(glb.end(), buffer.begin(), buffer.end());
    writeFile(dir / "mesh_glb_fuzzer/tetrahedron.glb", glb);
}

ngi::NetworkLayer layer(ngi::LayerKind kind, std::array<uint32_t, 3> inputs, uint32_t output, uint32_t in, uint32_t out)
{
    ngi::NetworkLayer l;
    l.kind = kind;
    l.inputs = inputs;
    l.output = output;
    l.inChannels = in;
    l.outChannels = out;
    return l;
}

// The smallest x2 network: 1x1 conv to 12 channels, pixel shuffle, bilinear skip.
ngi::NetworkWeights smallestNetwork()
{
    using ngi::LayerKind;
    constexpr uint32_t no = ngi::kNoTensor;
    ngi::NetworkWeights net;
    net.name = "seed-x2";
    net.scaleFactor = 2;
    auto conv = layer(LayerKind::Conv, {0, no, no}, 2, 3, 12);
    conv.kernelSize = 1;
    conv.biasOffset = 36;
    auto shuffle = layer(LayerKind::PixelShuffle, {2, no, no}, 3, 12, 3);
    shuffle.factor = 2;
    auto skip = layer(LayerKind::BilinearSkip, {0, 3, no}, 4, 3, 3);
    skip.factor = 2;
    net.layers = {conv, shuffle, skip};
    net.tensorCount = 5;
    net.outputTensor = 4;
    net.parameters.assign(48, 0.01f);
    return net;
}

// Every layer kind but CubicSkip: 3x3 conv (replicate, leaky, residual-free), 1x1 conv of
// the normals, attention, 1x1 conv with a residual, pixel shuffle, Hermite skip.
ngi::NetworkWeights everyLayerNetwork()
{
    using ngi::LayerKind;
    constexpr uint32_t no = ngi::kNoTensor;
    ngi::NetworkWeights net;
    net.name = "seed-every-layer-x2";
    net.metadata = "{\"seed\":true}";
    net.scaleFactor = 2;
    auto a = layer(LayerKind::Conv, {0, no, no}, 2, 3, 4);
    a.kernelSize = 3;
    a.padding = ngi::Padding::Replicate;
    a.activation = ngi::Activation::LeakyReLU;
    a.activationSlope = 0.1f;
    a.weightOffset = 0;
    a.biasOffset = 108;
    auto b = layer(LayerKind::Conv, {1, no, no}, 3, 3, 4);
    b.kernelSize = 1;
    b.activation = ngi::Activation::ReLU;
    b.weightOffset = 112;
    b.biasOffset = 124;
    auto attention = layer(LayerKind::NeighborhoodCrossAttention, {2, 3, 2}, 4, 4, 4);
    attention.heads = 2;
    attention.kernelSize = 3;
    attention.attentionScale = 0.5f;
    auto c = layer(LayerKind::Conv, {4, 2, no}, 5, 4, 4);
    c.kernelSize = 1;
    c.weightOffset = 128;
    c.biasOffset = 144;
    auto d = layer(LayerKind::Conv, {5, no, no}, 6, 4, 12);
    d.kernelSize = 1;
    d.weightOffset = 148;
    d.biasOffset = 196;
    auto shuffle = layer(LayerKind::PixelShuffle, {6, no, no}, 7, 12, 3);
    shuffle.factor = 2;
    auto skip = layer(LayerKind::HermiteSkip, {0, 7, 1}, 8, 3, 3);
    skip.factor = 2;
    net.layers = {a, b, attention, c, d, shuffle, skip};
    net.tensorCount = 9;
    net.outputTensor = 8;
    net.parameters.resize(208);
    for (size_t i = 0; i < net.parameters.size(); ++i) net.parameters[i] = 0.01f * float(int(i % 7) - 3);
    return net;
}

// `asset` with residual gains 0.25, 0, 0.25, ... (format 6).
ngi::Asset gainSeed(ngi::Asset asset)
{
    for (size_t c = 0; c < asset.charts.size(); ++c) asset.charts[c].residualGain = c % 2 ? 0.0f : 0.25f;
    return asset;
}

void writeNetworkAndAssetSeeds(const fs::path& dir)
{
    const std::vector<uint8_t> smallest = ngi::serializeNetworkWeights(smallestNetwork());
    writeFile(dir / "weights_fuzzer/smallest-x2.ngiw", smallest);
    writeFile(dir / "weights_fuzzer/every-layer-x2.ngiw", ngi::serializeNetworkWeights(everyLayerNetwork()));

    // The seeds of formats 3-8 as builds before format 9 wrote them (ngi/asset_legacy.h: the
    // readers still read them), then format 9 (packed SEAM and XSEM) at the end.
    const ngi::AnalyticSurface sphere = ngi::sphereGeometryImage(9);
    ngi::Asset asset = ngi::makeAnalyticAsset("sphere", sphere, 1);  // 8 cells, 5x5 stored
    writeFile(dir / "asset_fuzzer/sphere-8-level1.ngi", ngi::serializeLegacyAsset(asset));
    asset.metadataJson = "{\"seed\":true}";
    asset.weights = smallest;
    asset.networkId = "seed-x2";
    asset.networkHash = ngi::fnv1a64(smallest);
    writeFile(dir / "asset_fuzzer/sphere-8-level1-weights.ngi", ngi::serializeLegacyAsset(asset));
    // Format 5 (streamed positions): one chart, then two charts with a normal residual (NORM).
    ngi::Asset streamed = ngi::makeAnalyticAsset("sphere", sphere, 1);
    streamed.coding.pyramid = true;
    streamed.coding.positionStep = 64;
    writeFile(dir / "asset_fuzzer/sphere-8-level1-streamed.ngi", ngi::serializeLegacyAsset(streamed));
    ngi::AssetChart second = streamed.charts[0];
    second.fullResolution /= 2;
    second.storedLevel = 0;
    second.seams = {};
    const uint32_t n = second.storedSize();
    second.positions.resize(size_t(n) * n * 3);
    second.normals.resize(size_t(n) * n * 3);
    streamed.charts.push_back(second);
    streamed.coding.normalBits = 4;
    writeFile(dir / "asset_fuzzer/two-charts-streamed-normals.ngi", ngi::serializeLegacyAsset(streamed));
    // Format 6 (per-chart residual gains in CHRT) over a format-3 and a format-5 coding.
    writeFile(dir / "asset_fuzzer/sphere-8-level1-gain.ngi",
              ngi::serializeLegacyAsset(gainSeed(ngi::makeAnalyticAsset("sphere", sphere, 1))));
    writeFile(dir / "asset_fuzzer/two-charts-streamed-gains.ngi", ngi::serializeLegacyAsset(gainSeed(streamed)));
    // Format 7 (XSEM: a curve two charts share) over the format-5 coding: both charts matched at
    // one level, the second chart's bottom side against the first's top side.
    ngi::Asset split = streamed;
    split.charts[1].fullResolution = split.charts[0].fullResolution;
    split.charts[1].storedLevel = split.charts[0].storedLevel;
    split.charts[1].positions = split.charts[0].positions;
    split.charts[1].normals = split.charts[0].normals;
    for (ngi::AssetChart& chart : split.charts) {
        chart.seams.matched = true;
        chart.seams.coarsestWatertightLevel = 1;
        chart.seams.segments.clear();
    }
    const uint32_t r = split.charts[0].fullResolution;
    split.crossSeams = {{0, 2 * r, 1, 0, r}};
    writeFile(dir / "asset_fuzzer/two-charts-cross-seam.ngi", ngi::serializeLegacyAsset(split));
    // Format 9: the same split, and one chart with its zlib-predicted samples.
    writeFile(dir / "asset_fuzzer/two-charts-cross-seam-format9.ngi", ngi::serializeAsset(split));
    writeFile(dir / "asset_fuzzer/sphere-8-level1-format9.ngi",
              ngi::serializeAsset(ngi::makeAnalyticAsset("sphere", sphere, 1)));
    // Format 9 with base colours (the one packed BCOL): the split, chart 0 coloured at its
    // stored level (3 x 3 texels), chart 1 without.
    ngi::Asset coloured = split;
    coloured.coding.colorQuality = 101;
    ngi::AssetChart& painted = coloured.charts[0];
    painted.baseColorLevel = painted.storedLevel;
    const uint32_t texels = painted.baseColorSize();
    painted.baseColor.resize(size_t(texels) * texels * 4);
    for (size_t i = 0; i < painted.baseColor.size(); ++i) painted.baseColor[i] = uint8_t(i % 4 == 3 ? 255 : i * 29);
    writeFile(dir / "asset_fuzzer/two-charts-colour-format9.ngi", ngi::serializeAsset(coloured));
}

}  // namespace

int main(int argc, char** argv)
{
    const char* usage = "usage: ngi-fuzz-seeds DIR\n";
    std::string dir;
    try {
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            if (args.is("-h", "--help")) {
                std::fputs(usage, stdout);
                return 0;
            } else if (args.positional() && dir.empty())
                dir = args.flag();
            else
                throw args.unknown();
        }
        if (dir.empty()) throw ngi::UsageError("no DIR given");
    } catch (const ngi::UsageError& e) {
        std::fprintf(stderr, "ngi-fuzz-seeds: %s\n%s", e.what(), usage);
        return 2;
    }
    try {
        writeMeshSeeds(dir);
        writeNetworkAndAssetSeeds(dir);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-fuzz-seeds: %s\n", e.what());
        return 1;
    }
    return 0;
}
