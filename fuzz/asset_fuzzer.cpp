// libFuzzer target: the .ngi asset reader (parseAsset, the buffer form of readAsset).
// Every input is parsed twice: as it is (magic, version, truncation and CRC rejections) and
// with its checksums recomputed (the chunk table, HEAD, the zlib-predicted samples, WGHT).
// What parses must round-trip: serialize -> parse -> serialize gives the same bytes. An
// ngi::Error is the expected answer to a bad input; anything else escaping is a finding.
#include "fuzz_support.h"

#include "ngi/asset.h"
#include "ngi/error.h"
#include "ngi/network_weights.h"

namespace {

void parseAndCheck(std::span<const uint8_t> bytes)
{
    ngi::Asset asset;
    try {
        asset = ngi::parseAsset(bytes, "fuzz.ngi");
    } catch (const ngi::Error&) {
        return;
    }
    for (const ngi::AssetChart& chart : asset.charts) {
        (void)ngi::storedPositions(chart);
        (void)ngi::storedNormals(chart);
    }
    if (!asset.weights.empty()) {
        try {
            (void)ngi::parseNetworkWeights(asset.weights, "fuzz.ngi WGHT");
        } catch (const ngi::Error&) {
        }
    }
    std::vector<uint8_t> once;
    try {
        once = ngi::serializeAsset(asset);
    } catch (const ngi::Error&) {
        ngi::fuzz::invariantFailed("serializeAsset rejects an asset parseAsset accepted");
    }
    const std::vector<uint8_t> twice = ngi::serializeAsset(ngi::parseAsset(once, "fuzz.ngi (rewritten)"));
    if (once != twice) ngi::fuzz::invariantFailed("asset serialize -> parse -> serialize changed the bytes");
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::span<const uint8_t> input(data, size);
    parseAndCheck(input);
    parseAndCheck(ngi::fuzz::withAssetChecksumsFixed(input));
    return 0;
}
