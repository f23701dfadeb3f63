// libFuzzer target: the .ngi asset readers (parseAsset, the buffer form of readAsset, and the
// streaming readAssetPrefix of ngi/asset_prefix.h). Every input is parsed twice: as it is
// (magic, version, truncation and CRC rejections) and with its checksums recomputed (the
// chunk table, HEAD, the zlib-predicted samples, format 5's level table and levels, WGHT).
// What parses must round-trip: serialize -> parse -> serialize gives the same bytes (where
// the coding is idempotent: xyz residuals, no normal residual, no base colour). What the prefix reader
// accepts must be a valid asset (it serializes); a whole file both accept must decode to
// the same samples. An ngi::Error is the expected answer to a bad input; anything else
// escaping is a finding.
#include "fuzz_support.h"

#include "ngi/asset.h"
#include "ngi/asset_prefix.h"
#include "ngi/error.h"
#include "ngi/network_weights.h"

namespace {

bool sameSamples(const ngi::Asset& a, const ngi::Asset& b)
{
    if (a.charts.size() != b.charts.size()) return false;
    for (size_t c = 0; c < a.charts.size(); ++c)
        if (a.charts[c].storedLevel != b.charts[c].storedLevel || a.charts[c].positions != b.charts[c].positions ||
            a.charts[c].normals != b.charts[c].normals)
            return false;
    return true;
}

// The prefix reader on the input and on its first half: what it accepts is an asset the
// writer takes, at no more levels than the file has.
void prefixAndCheck(std::span<const uint8_t> bytes, const ngi::Asset* whole)
{
    for (const size_t n : {bytes.size(), bytes.size() / 2}) {
        ngi::AssetPrefix prefix;
        try {
            prefix = ngi::readAssetPrefix(bytes.first(n), "fuzz.ngi");
        } catch (const ngi::Error&) {
            if (whole && n == bytes.size())
                ngi::fuzz::invariantFailed("readAssetPrefix rejects a file parseAsset accepted");
            continue;
        }
        if (prefix.levelsDecoded == 0 || prefix.levelsDecoded > prefix.levelCount || prefix.boundaryBytes > n)
            ngi::fuzz::invariantFailed("readAssetPrefix reports impossible levels or bytes");
        try {
            (void)ngi::serializeAsset(prefix.asset);
        } catch (const ngi::Error&) {
            ngi::fuzz::invariantFailed("serializeAsset rejects an asset readAssetPrefix accepted");
        }
        if (whole && n == bytes.size() && (!prefix.complete || !sameSamples(prefix.asset, *whole)))
            ngi::fuzz::invariantFailed("readAssetPrefix of a whole file differs from parseAsset");
    }
}

void parseAndCheck(std::span<const uint8_t> bytes)
{
    ngi::Asset asset;
    try {
        asset = ngi::parseAsset(bytes, "fuzz.ngi");
    } catch (const ngi::Error&) {
        prefixAndCheck(bytes, nullptr);
        return;
    }
    prefixAndCheck(bytes, &asset);
    for (const ngi::AssetChart& chart : asset.charts) {
        (void)ngi::storedPositions(chart);
        (void)ngi::storedNormals(chart);
    }
    if (!asset.weights.empty()) {
        try {
            (void)ngi::parseNetworkWeights(asset.weights, "fuzz.ngi WGHT");
        } catch (const ngi::Error&) {}
    }
    std::vector<uint8_t> once;
    try {
        once = ngi::serializeAsset(asset);
    } catch (const ngi::Error&) {
        ngi::fuzz::invariantFailed("serializeAsset rejects an asset parseAsset accepted");
    }
    const std::vector<uint8_t> twice = ngi::serializeAsset(ngi::parseAsset(once, "fuzz.ngi (rewritten)"));
    // Coding decoded samples again is exact for xyz residuals and prediction-only normals
    // (ngi/asset.h applyAssetCoding); the residual frame and normal residuals may move them. Base
    // colours are coded again at coding.colorQuality, which the file does not record: a parsed
    // asset codes them at the default quality, lossy, so their bytes change.
    bool coloured = false;
    for (const ngi::AssetChart& chart : asset.charts) coloured |= !chart.baseColor.empty();
    const bool idempotent = !coloured &&
        (!asset.coding.pyramid || (asset.coding.positionTangentScale == 0 && asset.coding.normalBits == 0));
    if (idempotent && once != twice)
        ngi::fuzz::invariantFailed("asset serialize -> parse -> serialize changed the bytes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::span<const uint8_t> input(data, size);
    parseAndCheck(input);
    parseAndCheck(ngi::fuzz::withAssetChecksumsFixed(input));
    return 0;
}
