// ngi core: the asset formats before the current one (ngi/asset.h's version history, 1 to 8).
// ngi writes only the current format (serializeAsset), and every reader still reads the older
// ones (parseAsset, readAssetPrefix). This writer keeps those readers tested and fuzzed: it
// writes an asset as the builds before format 9 wrote it. Its chunk codings live with the
// readers' in one unit (core/src/asset_legacy.cpp).
#pragma once

#include "ngi/asset.h"

#include <cstdint>
#include <vector>

namespace ngi {

// `asset` in the oldest of formats 3-8 that holds it, as builds before format 9 wrote it: 3;
// with coding.pyramid 5, or 4 when not coding.progressive; 6 in place of any of them when a
// chart's residual gain is not 1; 7 with cross-chart seams; 8 when a chart has a base colour.
// The same checks and errors as serializeAsset.
std::vector<uint8_t> serializeLegacyAsset(const Asset& asset);

}  // namespace ngi
