// ngi-consumer: the smallest program against the installed package -- loads an asset (or
// makes an analytic one), builds it on the GPU and writes one frame to a PNG.
// usage: ngi-consumer [ASSET.ngi] OUT.png
#include "ngi/analytic_surfaces.h"
#include "ngi/asset.h"
#include "ngi/engine/asset_surface.h"
#include "ngi/engine/camera.h"
#include "ngi/engine/context.h"
#include "ngi/engine/offscreen.h"
#include "ngi/engine/renderer.h"
#include "ngi/png_io.h"

#include <cstdio>
#include <exception>

int main(int argc, char** argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: ngi-consumer [ASSET.ngi] OUT.png\n");
        return 1;
    }
    try {
        const ngi::Asset asset =
            argc > 2 ? ngi::readAsset(argv[1]) : ngi::makeAnalyticAsset("sphere", ngi::sphereGeometryImage(65), 2);
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
        ngi::writePng8(argv[argc - 1], 256, 256, 4, pixels.data());
        std::printf("wrote %s\n", argv[argc - 1]);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ngi-consumer: %s\n", e.what());
        return 1;
    }
}
