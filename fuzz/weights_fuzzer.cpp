// libFuzzer target: the .ngiw weights reader and the network validator
// (parseNetworkWeights, which runs validateNetwork). Every input is parsed as it is and with
// its body size and CRC recomputed; what parses must validate again, have a countable cost
// and round-trip byte for byte (serialize -> parse -> serialize). An ngi::Error is the
// expected answer to a bad input; anything else escaping is a finding.
#include "fuzz_support.h"

#include "ngi/error.h"
#include "ngi/network_weights.h"

namespace {

void parseAndCheck(std::span<const uint8_t> bytes)
{
    ngi::NetworkWeights net;
    try {
        net = ngi::parseNetworkWeights(bytes, "fuzz.ngiw");
    } catch (const ngi::Error&) {
        return;
    }
    const std::vector<ngi::TensorShape> shapes = ngi::validateNetwork(net, "fuzz.ngiw");
    if (shapes.size() != net.tensorCount) ngi::fuzz::invariantFailed("validateNetwork returned a shape per tensor");
    (void)ngi::networkMultiplyAdds(net, 5);
    (void)ngi::networkMultiplyAdds(net, 129);
    (void)ngi::networkHash(net);
    std::vector<uint8_t> once;
    try {
        once = ngi::serializeNetworkWeights(net);
    } catch (const ngi::Error&) {
        ngi::fuzz::invariantFailed("serializeNetworkWeights rejects a network parseNetworkWeights accepted");
    }
    const std::vector<uint8_t> twice =
        ngi::serializeNetworkWeights(ngi::parseNetworkWeights(once, "fuzz.ngiw (rewritten)"));
    if (once != twice) ngi::fuzz::invariantFailed("weights serialize -> parse -> serialize changed the bytes");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    const std::span<const uint8_t> input(data, size);
    parseAndCheck(input);
    parseAndCheck(ngi::fuzz::withWeightsChecksumsFixed(input));
    return 0;
}
