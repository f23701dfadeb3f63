// ngi-eval: measures how good a surface is (DESIGN.md "Metrics"), for people and scripts.
//
//   ngi-eval mesh ASSET (--lod F | --grid N) [--no-sr | --bicubic | --sr [--weights NET.ngiw]] -o OUT.{obj,off,ply,glb,gltf}
//   ngi-eval distance REFERENCE CANDIDATE [--json[=PATH]] [--samples N] [--seed S] [--threads T] [--no-colour]
//                     [--heat-map OUT.png [--heat-max H]]
//   ngi-eval report --meshes DIR_OR_LIST --out DIR [--resolution R] [--stored LIST] [--params LIST]
//                   [--jobs N] [--reuse] [--samples N] [--weights NET.ngiw] [--note TEXT]
//                   [--budgets LIST] [--networks DIR]
//
// mesh: writes the triangle mesh the renderer draws for ASSET, in original coordinates (as
// glTF with its normals, chart uvs and base colour textures). distance: prints CD (x1e-4) and
// HD (x1e-2) of CANDIDATE against REFERENCE, both in the reference's frame, and the colour
// PSNR of Y, Cb, Cr when both have appearance (colour_distance.h). report: bakes (or reuses) assets and writes DIR/report.md with the
// paper's tables, peers at equal bytes, SVG plots and contact sheets. Errors: one line "ngi-eval: message" on stderr, exit 1; usage errors exit 2.
// Output files (mesh -o, distance --json=PATH) are checked before the work (directory exists,
// not a directory, not an input, a mesh format writeMesh writes) and replace an existing file
// only once complete (ngi/output_files.h).
// This file is the dispatcher and the usage text; each subcommand is a file of its own
// (eval_commands.h).
#include "eval_commands.h"

#include "ngi/command_line.h"
#include "ngi/error.h"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage =
    "usage: ngi-eval mesh ASSET (--lod F | --grid N | --max-error E | --eye X,Y,Z --look-at X,Y,Z --max-error-px P "
    "[--fov DEG] [--size WxH]) [--no-sr | --bicubic | --sr [--weights NET.ngiw] [--networks DIR]]\n"
    "                -o OUT.{obj,off,ply,glb,gltf}\n"
    "       ngi-eval watertight ASSET [--no-sr | --bicubic | --sr [--weights NET.ngiw] [--networks DIR]]\n"
    "       ngi-eval distance REFERENCE CANDIDATE [options]\n"
    "       ngi-eval report --meshes DIR_OR_LIST --out DIR [options]\n"
    "\n"
    "mesh: the triangle mesh the renderer draws for ASSET (.ngi) at continuous LoD F\n"
    "  (0 = full resolution .. levels - 1) or on a fixed N x N grid, in the input mesh's\n"
    "  original coordinates. --no-sr restores the full image by bilinear upsampling of\n"
    "  the stored level (as ngi-render --no-sr); --bicubic by bicubic\n"
    "  upsampling (a comparison baseline); --sr by the super-resolution network (its C++\n"
    "  reference forward, which the engine's GLSL matches): --weights NET.ngiw, else the\n"
    "  asset's own WGHT chunk, else the shipped network the asset names (in --networks DIR,\n"
    "  else $NGI_NETWORK_DIR, else the assets/ beside the executable). Charts the network's\n"
    "  factor does not restore are restored bicubically (said on stdout). Default (none of\n"
    "  the three): --sr when the asset carries weights or the network it names is found and\n"
    "  restores it, else (a warning when it names one) --bicubic: what ngi-render draws.\n"
    "  Adaptive LoD (each 4x4-quad tile of each chart at its own level, crack-free):\n"
    "  --max-error E draws every tile at the coarsest level within E (a fraction of the\n"
    "  asset's longest side, (0, 1]) of the full restored surface; a camera (--eye and\n"
    "  --look-at in the input's coordinates, --fov DEG default 45, --size WxH default\n"
    "  1280x720) draws each tile within --max-error-px P pixels, near tiles finer, far and\n"
    "  flat ones coarser, geomorphed. The whole surface is written (tiles outside the view\n"
    "  too); stdout says how many the renderer would cull. OUT.glb (binary) or OUT.gltf\n"
    "  (embedded) is glTF 2.0 with normals, each vertex's chart uv as TEXCOORD_0 and one\n"
    "  material per coloured chart whose base colour texture is the chart's image (PNG).\n"
    "\n"
    "watertight: for every LoD 0, 0.5, 1, ... to the coarsest drawn level, and for the adaptive\n"
    "  surface within 0.2%, 0.5%, 1%, 2%, 5% and 20% of the size, the mesh of 'mesh'\n"
    "  with vertices welded within 1e-6 of the bounding box's longest side: its open edges\n"
    "  (0 for a closed input with matched seams; else the input's own boundary loops) and the\n"
    "  widest gap between open edges (% of the longest side).\n"
    "\n"
    "distance:\n"
    "  Chamfer (CD, x1e-4) and Hausdorff (HD, x1e-2) distance of CANDIDATE against\n"
    "  REFERENCE, as DESIGN.md \"Metrics\" defines them: both meshes centred on the\n"
    "  reference's bounding-box centre and scaled so its longest side is 1; point-to-surface\n"
    "  distances (CGAL AABB tree) from area-uniform samples on each surface.\n"
    "  Colour, when both meshes have appearance (textures, vertex colours or materials):\n"
    "  PSNR of Y, Cb, Cr (BT.709, 8-bit sRGB, full range; inf for identical colours) of the\n"
    "  base colour at the reference's samples against the candidate's at its closest\n"
    "  surface point. A mesh whose appearance does not read is measured without colour\n"
    "  (said on stderr).\n"
    "  Meshes: OBJ, OFF, PLY, STL, glTF (.gltf/.glb).\n"
    "\n"
    "distance options:\n"
    "  --json         print JSON on stdout instead of text\n"
    "  --json=PATH    also write the JSON to PATH\n"
    "  --samples N    samples per surface (default 200000, the DESIGN.md value)\n"
    "  --seed S       sampling seed (default: the fixed DESIGN.md seed)\n"
    "  --threads T    threads for the closest-point queries (default 2)\n"
    "  --no-colour    read geometry only: no colour PSNR\n"
    "  --heat-map OUT.png  also draw where the distance comes from: the reference from two\n"
    "                 sides, each triangle coloured by its largest distance (corners and\n"
    "                 centroid) to the candidate, on a log scale: blue at 1/100 of the HD,\n"
    "                 red at the HD\n"
    "  --heat-max H   with --heat-map: red at H (x1e-2 of the size) instead of the HD\n"
    "\n"
    "report: bakes every mesh (DIR: all mesh files in it; or a comma-separated list of files)\n"
    "  with each parameterization and writes DIR/report.md: Table 1 (CD/HD of each map's\n"
    "  full image), Table 4 (OT stored at each resolution, restored without SR), peers at\n"
    "  equal bytes (meshoptimizer + Draco 14-bit, Loop, Butterfly) and at equal triangle\n"
    "  count, SVG plots (DIR/plots), contact sheets and distance heat maps (DIR/pictures). A\n"
    "  failed bake is a reported row, not an error. Progress with ETA on stderr.\n"
    "report options:\n"
    "  --resolution R       full geometry image (default 1024)\n"
    "  --stored LIST        stored resolutions (default 32,64,128,256,512)\n"
    "  --params LIST        parameterizations (default tutte,harmonic,ricci,authalic,ot)\n"
    "  --jobs N             meshes processed at once (default 1)\n"
    "  --reuse              reuse DIR/assets from an earlier run (and its recorded failures)\n"
    "  --samples N          samples per surface (default 200000)\n"
    "  --picture-size N     contact-sheet tile side in pixels (default 200)\n"
    "  --weights NET.ngiw   the trained SR network, if any (its bytes are reported)\n"
    "  --note TEXT          a note quoted in the report (e.g. why this resolution)\n"
    "  --budgets LIST       byte budgets of the rate-distortion curves: ngi-bake --target-bytes N\n"
    "                       against meshopt+Draco's best qp 10/12/14 (default\n"
    "                       4096,8192,16384,32768,65536; 'none': no curves)\n"
    "  --networks DIR       the shipped networks the budget assets may name (default: ngi-bake's)\n";

using ngi::UsageError;  // core/include/ngi/command_line.h, shared by every tool

}  // namespace

int main(int argc, char** argv)
{
    std::vector<std::string> args(argv + 1, argv + argc);
    if (args.empty() || args[0] == "--help" || args[0] == "-h" || args[0] == "help") {
        std::fputs(kUsage, args.empty() ? stderr : stdout);
        return args.empty() ? 2 : 0;
    }
    const std::string command = args[0];
    args.erase(args.begin());
    try {
        if (command == "distance") return ngi::eval_cli::distanceCommand(args);
        if (command == "mesh") return ngi::eval_cli::meshCommand(args);
        if (command == "watertight") return ngi::eval_cli::watertightCommand(args);
        if (command == "report") {
            std::string line = "ngi-eval";
            for (int i = 1; i < argc; ++i) line += std::string(" ") + argv[i];
            return ngi::eval_cli::reportCommand(args, line);
        }
        throw UsageError("unknown command '" + command + "'");
    } catch (const UsageError& e) {
        std::fprintf(stderr, "ngi-eval: %s\n\n%s", e.what(), kUsage);
        return 2;
    } catch (const ngi::Error& e) {
        std::fprintf(stderr, "ngi-eval: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-eval: unexpected error: %s\n", e.what());
        return 1;
    }
}
