// ngi-make-analytic: writes an asset of an analytic surface (sphere or rippled torus),
// sampled exactly at full resolution and stored at a chosen level. Used for the default
// asset until a baked real mesh replaces it, and for tests and benchmarks.
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/error.h"
#include "ngi/mip_pyramid.h"
#include "ngi/output_files.h"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
    const char* usage = "usage: ngi-make-analytic sphere|torus OUT.ngi [--resolution 1024] [--store-res 128]\n";
    try {
        std::vector<std::string> positional;
        uint32_t resolution = 1024, store = 128;
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            if (args.is("--resolution"))
                resolution = ngi::parseUintOption(args.flag(), args.value());
            else if (args.is("--store-res"))
                store = ngi::parseUintOption(args.flag(), args.value());
            else if (args.is("-h", "--help")) {
                std::printf("%s", usage);
                return 0;
            } else if (args.positional() && positional.size() < 2)
                positional.push_back(args.flag());
            else
                throw args.unknown();
        }
        if (positional.size() < 2) {
            std::fprintf(stderr, "%s", usage);
            return 2;
        }
        const std::string surface = positional[0], out = positional[1];
        if (!ngi::isNestedGridSize(resolution + 1) || !ngi::isNestedGridSize(store + 1) || store > resolution)
            throw ngi::Error("--resolution and --store-res must be powers of two with store-res <= resolution");
        ngi::OutputFiles outputs({out});  // a bad OUT fails before the surface is sampled
        uint32_t level = 0;
        while ((resolution >> level) > store) ++level;
        const ngi::AnalyticSurface s = surface == "sphere" ? ngi::sphereGeometryImage(resolution + 1)
            : surface == "torus"                           ? ngi::rippledTorusGeometryImage(resolution + 1)
                                 : throw ngi::Error("unknown surface '" + surface + "' (sphere, torus)");
        outputs.write(out, ngi::serializeAsset(ngi::makeAnalyticAsset(surface, s, level)));
        outputs.commit();
        std::printf("wrote %s: analytic %s, resolution %u, stored %ux%u\n", out.c_str(), surface.c_str(), resolution,
                    store + 1, store + 1);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-make-analytic: error: %s\n", e.what());
        return 1;
    }
}
