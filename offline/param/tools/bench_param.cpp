// ngi-bench-param: maps one disk mesh onto the square with every --param method and prints a
// table (time, iterations, residuals, distortion, flips), then times the rasterization.
// Input: an OFF file (an open mesh with one boundary loop is used as is; a closed mesh is
// opened by deleting the k-ring of its vertex 0, --hole K, which makes a genus-0 surface a
// disk: a stress test of the conformal start), or a procedural disk (--procedural).
// A benchmark, not a test: it prints; the library never does.
#include "ngi/error.h"
#include "ngi/command_line.h"
#include "ngi/param/parameterize.h"
#include "ngi/param/rasterize.h"

#include <glm/geometric.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

ngi::TriangleMesh readOff(const std::string& path)
{
    std::ifstream in(path);
    if (!in) throw ngi::Error(path + ": cannot open");
    std::string header;
    in >> header;
    if (header != "OFF") throw ngi::Error(path + ": not an OFF file");
    size_t nv = 0, nf = 0, ne = 0;
    in >> nv >> nf >> ne;
    ngi::TriangleMesh mesh;
    mesh.positions.resize(nv);
    for (auto& p : mesh.positions) in >> p.x >> p.y >> p.z;
    for (size_t f = 0; f < nf; ++f) {
        size_t k = 0;
        in >> k;
        std::vector<uint32_t> poly(k);
        for (auto& i : poly) in >> i;
        std::string rest;
        std::getline(in, rest);
        for (size_t j = 1; j + 1 < k; ++j) mesh.triangles.push_back({poly[0], poly[j], poly[j + 1]});
    }
    if (!in) throw ngi::Error(path + ": truncated");
    return mesh;
}

// Deletes the triangles within `rings` of vertex `seed`, drops unused vertices and returns the
// disk with its boundary loop (one loop required).
ngi::DiskMesh openToDisk(const ngi::TriangleMesh& mesh, int rings, uint32_t seed)
{
    std::set<uint32_t> region{seed};
    std::vector<uint8_t> removeTriangle(mesh.triangles.size(), 0);
    for (int r = 0; r < rings; ++r) {
        std::set<uint32_t> grown = region;
        for (size_t t = 0; t < mesh.triangles.size(); ++t) {
            const auto& tri = mesh.triangles[t];
            if (region.count(tri[0]) || region.count(tri[1]) || region.count(tri[2])) {
                removeTriangle[t] = 1;
                for (int k = 0; k < 3; ++k) grown.insert(tri[k]);
            }
        }
        region = grown;
    }
    std::vector<int64_t> remap(mesh.positions.size(), -1);
    ngi::DiskMesh disk;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        if (removeTriangle[t]) continue;
        glm::uvec3 tri;
        for (int k = 0; k < 3; ++k) {
            uint32_t v = mesh.triangles[t][k];
            if (remap[v] < 0) {
                remap[v] = int64_t(disk.mesh.positions.size());
                disk.mesh.positions.push_back(mesh.positions[v]);
                disk.originalVertex.push_back(v);
            }
            tri[k] = uint32_t(remap[v]);
        }
        disk.mesh.triangles.push_back(tri);
    }
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const auto& tri : disk.mesh.triangles)
        for (int k = 0; k < 3; ++k) directed[{tri[k], tri[(k + 1) % 3]}]++;
    std::map<uint32_t, uint32_t> next;
    for (const auto& [edge, count] : directed)
        if (!directed.count({edge.second, edge.first})) next[edge.first] = edge.second;
    if (next.empty()) throw ngi::Error("mesh has no boundary after opening (use --hole 1 or more)");
    uint32_t start = next.begin()->first, v = start;
    do {
        disk.boundaryLoop.push_back(v);
        v = next.at(v);
    } while (v != start && disk.boundaryLoop.size() <= next.size());
    if (disk.boundaryLoop.size() != next.size())
        throw ngi::Error("mesh has " + std::to_string(next.size()) + " boundary edges but the first loop has " +
                         std::to_string(disk.boundaryLoop.size()) + " (several boundary loops)");
    return disk;
}

// One 1-to-4 midpoint subdivision (flat: positions on the input triangles), to reach the
// vertex counts of a remeshed input (100k-250k) from the smaller data-set meshes.
ngi::TriangleMesh subdivide(const ngi::TriangleMesh& mesh)
{
    ngi::TriangleMesh out;
    out.positions = mesh.positions;
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t b) {
        const auto key = std::minmax(a, b);
        auto it = midpoint.find(key);
        if (it != midpoint.end()) return it->second;
        out.positions.push_back(0.5 * (mesh.positions[a] + mesh.positions[b]));
        return midpoint[key] = uint32_t(out.positions.size() - 1);
    };
    for (const auto& t : mesh.triangles) {
        const uint32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
        out.triangles.push_back({t[0], ab, ca});
        out.triangles.push_back({ab, t[1], bc});
        out.triangles.push_back({ca, bc, t[2]});
        out.triangles.push_back({ab, bc, ca});
    }
    return out;
}

double seconds(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void usage()
{
    std::puts(
        "usage: ngi-bench-param MESH.off [--hole K] [--subdivide N] [--methods tutte,harmonic,ricci,authalic,ot]\n"
        "                       [--resolution R] [--ot-tolerance T] [--verbose]");
}

}  // namespace

int main(int argc, char** argv)
{
    std::string path, methods = "tutte,harmonic,ricci,authalic,ot";
    int hole = 2, subdivisions = 0;
    uint32_t resolution = 1024;
    double otTolerance = 1e-3;
    bool verbose = false;
    try {
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            const std::string& arg = args.flag();
            if (args.is("--hole"))
                hole = int(ngi::parseIntegerOptionInRange(arg, args.value(), 0, 64));
            else if (args.is("--methods"))
                methods = args.value();
            else if (args.is("--subdivide"))
                subdivisions = int(ngi::parseIntegerOptionInRange(arg, args.value(), 0, 8));
            else if (args.is("--resolution"))
                resolution = uint32_t(ngi::parseIntegerOptionInRange(arg, args.value(), 2, 1u << 16));
            else if (args.is("--ot-tolerance"))
                otTolerance = ngi::parseFloatOptionInRange(arg, args.value(), 1e-12, 1.0, "a tolerance");
            else if (args.is("--verbose"))
                verbose = true;
            else if (args.is("--help", "-h")) {
                usage();
                return 0;
            } else if (args.positional() && path.empty())
                path = arg;
            else
                throw args.unknown();
        }
    } catch (const ngi::UsageError& e) {
        std::fprintf(stderr, "ngi-bench-param: %s\n", e.what());
        return 2;
    }
    if (path.empty()) {
        usage();
        return 2;
    }
    try {
        ngi::TriangleMesh mesh = readOff(path);
        for (int k = 0; k < subdivisions; ++k) mesh = subdivide(mesh);
        const ngi::DiskMesh disk = openToDisk(mesh, hole, 0);
        std::printf("%s: %zu vertices, %zu triangles, boundary %zu vertices (hole %d)\n", path.c_str(),
                    disk.mesh.positions.size(), disk.mesh.triangles.size(), disk.boundaryLoop.size(), hole);
        std::printf("%-9s %8s %6s %9s %6s %9s %9s %9s %9s %9s %6s %s\n", "method", "seconds", "ricci", "residual", "ot",
                    "residual", "areaMax", "areaMean", "angleMax", "angleMean", "flips", "notes");
        std::vector<glm::dvec2> lastUv;
        std::stringstream list(methods);
        for (std::string name; std::getline(list, name, ',');) {
            ngi::ParameterizeOptions options;
            options.method = ngi::parseParameterizationMethod(name);
            options.otTolerance = otTolerance;
            if (verbose)
                options.progress = [](const std::string& line) { std::fprintf(stderr, "  %s\n", line.c_str()); };
            const auto start = std::chrono::steady_clock::now();
            try {
                ngi::SquareMap map = ngi::parameterizeToSquare(disk, options);
                const double t = seconds(start);
                const auto& r = map.report;
                std::string notes;
                if (r.negativeWeights) notes += "negative weights " + std::to_string(r.negativeWeights) + "; ";
                if (r.clampedWeights) notes += "clamped " + std::to_string(r.clampedWeights) + "; ";
                if (options.method == ngi::ParameterizationMethod::OptimalTransport) {
                    char buffer[160];
                    std::snprintf(buffer, sizeof buffer,
                                  "conformal %.1fs, transport %.1fs, halvings %d, centroid flips %zu%s",
                                  r.secondsConformal, r.secondsTransport, r.otHalvings, r.otCentroidFlips,
                                  r.otRelaxed ? " (relaxed)" : "");
                    notes += buffer;
                }
                std::printf("%-9s %8.2f %6d %9.2e %6d %9.2e %9.3f %9.4f %9.3f %9.4f %6zu %s\n", name.c_str(), t,
                            r.ricciIterations, r.ricciResidual, r.otIterations, r.otResidual, r.areaDistortionMax,
                            r.areaDistortionMean, r.angleDistortionMax, r.angleDistortionMean, r.flippedTriangles,
                            notes.c_str());
                lastUv = std::move(map.uv);
            } catch (const ngi::Error& e) {
                std::printf("%-9s %8.2f failed: %s\n", name.c_str(), seconds(start), e.what());
            }
            std::fflush(stdout);
        }
        if (!lastUv.empty() && resolution > 0) {
            const auto start = std::chrono::steady_clock::now();
            const ngi::RasterizedGeometryImage image = ngi::rasterizeGeometryImage(disk, lastUv, resolution);
            std::printf("rasterize %u^2 (last method): %.2f s, %zu samples extrapolated\n", resolution, seconds(start),
                        image.extrapolatedSamples);
        }
    } catch (const ngi::Error& e) {
        std::fprintf(stderr, "ngi-bench-param: %s\n", e.what());
        return 1;
    }
    return 0;
}
