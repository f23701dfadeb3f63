// ngi-peer-equal-bytes: the peer at equal bytes (ngi/eval/equal_bytes.h: meshoptimizer
// simplification to the largest triangle count whose Draco bitstream fits) for several
// budgets and Draco position precisions, written as meshes to measure with ngi-eval distance.
//   ngi-peer-equal-bytes MESH -o DIR BUDGET... [--qp 10,12,14]
// Writes DIR/NAME_BUDGET_qpQ.ply (the DECODED mesh) and prints one line per mesh:
// budget, qp, Draco bytes, triangles, whether the budget was met.
#include "ngi/error.h"
#include "ngi/command_line.h"
#include "ngi/eval/equal_bytes.h"
#include "ngi/mesh/mesh_io.h"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
    try {
        std::filesystem::path mesh, out;
        std::vector<size_t> budgets;
        std::vector<int> qps = {10, 12, 14};
        const char* usage = "usage: ngi-peer-equal-bytes MESH -o DIR BUDGET... [--qp 10,12,14]\n";
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            const std::string& a = args.flag();
            if (args.is("-o"))
                out = args.value();
            else if (args.is("--qp")) {
                qps.clear();
                std::stringstream list(args.value());
                std::string item;
                while (std::getline(list, item, ','))
                    qps.push_back(int(ngi::parseIntegerOptionInRange(a, item, 1, 30)));
            } else if (args.is("-h", "--help")) {
                std::fputs(usage, stdout);
                return 0;
            } else if (args.positional() && mesh.empty())
                mesh = a;
            else if (args.positional())
                budgets.push_back(size_t(ngi::parseIntegerOptionInRange("BUDGET", a, 1, uint64_t(1) << 40)));
            else
                throw args.unknown();
        }
        if (mesh.empty() || out.empty() || budgets.empty()) {
            std::fputs(usage, stderr);
            return 2;
        }
        const ngi::TriangleMesh input = ngi::readMesh(mesh);
        for (size_t budget : budgets)
            for (int qp : qps) {
                ngi::EqualBytesOptions options;
                options.draco.positionQuantizationBits = qp;
                const ngi::EqualBytesResult r = ngi::simplifyToByteBudget(input, budget, options);
                const std::filesystem::path file =
                    out / (mesh.stem().string() + "_" + std::to_string(budget) + "_qp" + std::to_string(qp) + ".ply");
                ngi::writeMesh(file, r.decoded);
                std::printf("%zu %d %zu %zu %d %s\n", budget, qp, r.dracoBytes, r.decoded.triangles.size(),
                            r.budgetMet ? 1 : 0, file.string().c_str());
                std::fflush(stdout);
            }
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-peer-equal-bytes: error: %s\n", e.what());
        return 1;
    }
}
