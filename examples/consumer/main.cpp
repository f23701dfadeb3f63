// ngi-consumer: the smallest program against the installed package -- loads an asset (or
// makes an analytic one), builds it on the GPU and writes one frame to a PNG.
// usage: ngi-consumer [ASSET.ngi] OUT.png
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/command_line.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/context.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/renderer.h"
#include "ngi/png_io.h"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

int main(int argc, char** argv)
{
    const char* usage = "usage: ngi-consumer [ASSET.ngi] OUT.png\n";
    std::vector<std::string> paths;  // [ASSET.ngi] OUT.png
    try {
        ngi::ArgReader args(argc, argv);
        while (args.next()) {
            if (args.is("-h", "--help")) {
                std::fputs(usage, stdout);
                return 0;
            } else if (args.positional() && paths.size() < 2)
                paths.push_back(args.flag());
            else
                throw args.unknown();
        }
        if (paths.empty()) throw ngi::UsageError("no OUT.png given");
    } catch (const ngi::UsageError& e) {
        std::fprintf(stderr, "ngi-consumer: %s\n%s", e.what(), usage);
        return 1;
    }
    try {
        const ngi::Asset asset = paths.size() == 2 ? ngi::readAsset(paths[0])
                                                   : ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(65), 2);
        auto context = ngi::vk::Context::create({});
        ngi::vk::Renderer renderer(*context);
        ngi::vk::AssetSurface surface(renderer, asset);
        surface.build();
        ngi::vk::OffscreenTarget target(renderer, 256, 256);
        const auto camera = ngi::vk::frameBounds(surface.boundsMin(), surface.boundsMax(), 30.0f, 20.0f, 1.0f);
        ngi::vk::DrawParams p;
        p.viewProjection = camera.viewProjection(1.0f);
        p.eye = camera.eye();
        const auto pixels = target.render([&](VkCommandBuffer cmd) { surface.recordDraw(cmd, p, target.extent()); },
                                          {0.1f, 0.1f, 0.1f, 1.0f});
        ngi::writePng8(paths.back(), 256, 256, 4, pixels.data());
        std::printf("wrote %s\n", paths.back().c_str());
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-consumer: %s\n", e.what());
        return 1;
    }
}
