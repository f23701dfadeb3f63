// ngi-view command line.
#include "options.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace ngi::view {

const char* kUsage = "usage: ngi-view [ASSET] [--device NAME|INDEX] [--size WxH] [--max-error-px P | --lod F | "
                     "--auto-lod N] [--mode MODE]\n"
                     "                [--weights NET.ngiw] [--sr | --no-sr] [--networks DIR] [--samples 1|4] "
                     "[--no-vsync] [--hide-panel] [--show-help] [--validation]\n"
                     "                [--frames N [--screenshot OUT.png] [--lod-sequence F,F,...]\n"
                     "                 [--open-at FRAME:PATH] [--resize-at FRAME:WxH]]\n"
                     "Opens ASSET (.ngi) in a window: orbit (left mouse), pan (middle/right), zoom (wheel). It draws\n"
                     "adaptively by default: each tile of the grid at the coarsest level within --max-error-px P\n"
                     "pixels (default 1; T toggles, mode 'lod' colours tiles by level); --lod F or --auto-lod N\n"
                     "draw one uniform LoD instead: drag the LoD slider,\n"
                     "zoom (wheel), F1 lists every shortcut. MODE: shaded, normals, wireframe, lod, image.\n"
                     "--weights loads a super-resolution network (an asset's own WGHT chunk takes precedence;\n"
                     "without either, the shipped network the asset names, found in --networks DIR, else\n"
                     "$NGI_NETWORK_DIR, else the assets/ beside the executable). SR starts on when such a network\n"
                     "restores the asset; --sr requires it (an error says why not), --no-sr starts without it.\n"
                     "Without the network the finer levels are restored bicubically (as ngi-render draws them).\n"
                     "--frames N renders N frames and exits; --screenshot writes the last one (panel included);\n"
                     "--lod-sequence spreads LoDs over the frames; --open-at/--resize-at script a file drop or a\n"
                     "window resize. --validation: exit 3 if the Vulkan validation layer reported anything.\n"
                     "Needs a display (X11/Wayland, or Xvfb); for headless capture use ngi-render.\n";

namespace {

constexpr auto parseFloat = ngi::parseFloatOption;

void parseSize(const std::string& flag, const std::string& v, uint32_t& w, uint32_t& h)
{
    const auto x = v.find('x');
    if (x == std::string::npos) throw UsageError(flag + " expects WxH, got '" + v + "'");
    w = ngi::parseUintOption(flag, v.substr(0, x));
    h = ngi::parseUintOption(flag, v.substr(x + 1));
    if (w < 64 || h < 64 || w > 16384 || h > 16384) throw UsageError(flag + " must be between 64x64 and 16384x16384");
}

// "FRAME:REST" -> frame, rest.
std::pair<uint32_t, std::string> parseAt(const std::string& flag, const std::string& v)
{
    const auto colon = v.find(':');
    if (colon == std::string::npos || colon + 1 == v.size())
        throw UsageError(flag + " expects FRAME:VALUE, got '" + v + "'");
    return {ngi::parseUintOption(flag, v.substr(0, colon)), v.substr(colon + 1)};
}

}  // namespace

Options parseOptions(int argc, char** argv)
{
    Options o;
    ngi::ArgReader args(argc, argv);
    while (args.next()) {
        const std::string& a = args.flag();
        if (args.is("--device"))
            o.device = args.value();
        else if (args.is("--size"))
            parseSize(a, args.value(), o.width, o.height);
        else if (args.is("--lod"))
            o.lod = parseFloat(a, args.value());
        else if (args.is("--auto-lod"))
            o.autoLodPixels = parseFloat(a, args.value());
        else if (args.is("--max-error-px"))
            o.maxErrorPx = ngi::parseFloatOptionInRange(a, args.value(), 0.01, 1e4, "pixels");
        else if (args.is("--mode"))
            o.mode = args.value();
        else if (args.is("--samples"))
            o.samples = ngi::parseUintOption(a, args.value());
        else if (args.is("--weights"))
            o.weights = args.value();
        else if (args.is("--sr"))
            o.superResolution = true;
        else if (args.is("--no-sr"))
            o.superResolution = false;
        else if (args.is("--networks"))
            o.networks = args.value();
        else if (args.is("--no-vsync"))
            o.vsync = false;
        else if (args.is("--hide-panel"))
            o.hidePanel = true;
        else if (args.is("--show-help"))
            o.showHelp = true;
        else if (args.is("--validation"))
            o.validation = true;
        else if (args.is("--frames"))
            o.frames = ngi::parseUintOption(a, args.value());
        else if (args.is("--screenshot"))
            o.screenshot = parseOutputPathOption(a, args.value());
        else if (args.is("--lod-sequence")) {
            const std::string v = args.value();
            size_t start = 0;
            while (start <= v.size()) {
                const size_t comma = std::min(v.find(',', start), v.size());
                o.lodSequence.push_back(parseFloat(a, v.substr(start, comma - start)));
                start = comma + 1;
            }
        } else if (args.is("--open-at")) {
            auto [frame, path] = parseAt(a, args.value());
            o.opens.push_back({frame, path});
        } else if (args.is("--resize-at")) {
            auto [frame, size] = parseAt(a, args.value());
            ScriptedResize r{frame};
            parseSize(a, size, r.width, r.height);
            o.resizes.push_back(r);
        } else if (args.is("-h", "--help"))
            o.help = true;
        else if (args.positional() && o.asset.empty())
            o.asset = a;
        else
            throw args.unknown();
    }
    if (o.help) return o;
    if (o.samples != 0 && o.samples != 1 && o.samples != 4) throw UsageError("--samples must be 1 or 4");
    if (int(bool(o.lod)) + int(bool(o.autoLodPixels)) + int(bool(o.maxErrorPx)) > 1)
        throw UsageError("--max-error-px, --lod and --auto-lod are exclusive");
    if (o.maxErrorPx && !o.lodSequence.empty()) throw UsageError("--lod-sequence excludes --max-error-px");
    if (o.autoLodPixels && *o.autoLodPixels <= 0.0f) throw UsageError("--auto-lod expects a positive pixel count");
    if (!o.screenshot.empty() && o.frames == 0)
        throw UsageError("--screenshot needs --frames N (the frame to capture)");
    if (o.frames == 0 && (!o.lodSequence.empty() || !o.opens.empty() || !o.resizes.empty()))
        throw UsageError("--lod-sequence, --open-at and --resize-at need --frames N");
    if (!o.lodSequence.empty() && (o.lod || o.autoLodPixels))
        throw UsageError("--lod-sequence excludes --lod and --auto-lod");
    return o;
}

}  // namespace ngi::view
