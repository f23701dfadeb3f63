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

int main(int argc, char** argv)
{
    const char* usage = "usage: ngi-make-analytic sphere|torus OUT.ngi [--resolution 1024] [--store-res 128]\n";
    if (argc < 3) {
        std::fprintf(stderr, "%s", usage);
        return 2;
    }
    try {
        const std::string surface = argv[1], out = argv[2];
        uint32_t resolution = 1024, store = 128;
        for (int i = 3; i < argc; ++i) {
            const std::string a = argv[i];
            if (i + 1 >= argc) throw ngi::Error(a + " needs a value");
            const uint32_t v = ngi::parseUintOption(a, argv[++i]);
            if (a == "--resolution")
                resolution = v;
            else if (a == "--store-res")
                store = v;
            else
                throw ngi::Error("unknown option " + a);
        }
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
