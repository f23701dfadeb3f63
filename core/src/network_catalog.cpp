// The shipped super-resolution networks and the one an asset expects (ngi/network_catalog.h).
#include "ngi/network_catalog.h"

#include "ngi/error.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <system_error>

namespace ngi {

std::vector<std::filesystem::path> networkSearchPath(const std::filesystem::path& explicitDir)
{
    if (!explicitDir.empty()) return {explicitDir};
    std::vector<std::filesystem::path> dirs;
    if (const char* env = std::getenv("NGI_NETWORK_DIR"); env && *env) dirs.emplace_back(env);
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec && exe.has_parent_path()) {
        const std::filesystem::path bin = exe.parent_path();
        dirs.push_back((bin / ".." / ".." / "assets").lexically_normal());
        dirs.push_back((bin / ".." / "share" / "ngi").lexically_normal());
    }
    return dirs;
}

std::vector<ShippedNetwork> findShippedNetworks(std::span<const std::filesystem::path> dirs,
                                                std::vector<std::string>& skipped)
{
    std::vector<ShippedNetwork> found;
    for (const std::filesystem::path& dir : dirs) {
        std::error_code ec;
        if (!std::filesystem::is_directory(dir, ec)) continue;
        std::vector<std::filesystem::path> files;
        for (const auto& entry : std::filesystem::directory_iterator(dir, ec))
            if (entry.path().extension() == ".ngiw" && entry.is_regular_file(ec)) files.push_back(entry.path());
        std::sort(files.begin(), files.end());
        for (const std::filesystem::path& file : files) {
            ShippedNetwork s{file, {}, 0};
            try {
                s.network = readNetworkWeights(file);
            } catch (const Error& e) {
                skipped.push_back(e.what());  // one broken file must not hide the others
                continue;
            }
            s.hash = networkHash(s.network);
            found.push_back(std::move(s));
        }
    }
    return found;
}

const ShippedNetwork* shippedNetworkForFactor(std::span<const ShippedNetwork> shipped, uint32_t factor)
{
    for (const ShippedNetwork& s : shipped)
        if (s.network.scaleFactor == factor) return &s;
    return nullptr;
}

std::string networkHashText(uint64_t hash)
{
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
    return text;
}

std::optional<NetworkWeights> findAssetNetwork(const Asset& asset, std::span<const std::filesystem::path> dirs,
                                               std::string& problem, std::vector<std::string>& skipped)
{
    problem.clear();
    if (asset.networkId.empty()) {
        problem = "it names no network (no shipped network matched its stored level when it was baked): give --weights "
                  "NET.ngiw";
        return std::nullopt;
    }
    const ShippedNetwork* otherHash = nullptr;
    const size_t skippedBefore = skipped.size();
    std::vector<ShippedNetwork> shipped = findShippedNetworks(dirs, skipped);
    for (ShippedNetwork& s : shipped) {
        if (s.network.name != asset.networkId) continue;
        if (s.hash == asset.networkHash) return std::move(s.network);
        if (!otherHash) otherHash = &s;
    }
    if (otherHash) {
        problem = "it names network '" + asset.networkId + "' (hash " + networkHashText(asset.networkHash) + ") but " +
            otherHash->path.string() + " has hash " + networkHashText(otherHash->hash) +
            " (another network of that name: re-bake the asset, or give --weights to use it anyway)";
        return std::nullopt;
    }
    std::string searched;
    for (const std::filesystem::path& d : dirs) searched += (searched.empty() ? "" : ", ") + d.string();
    problem = "it names network '" + asset.networkId + "' (hash " + networkHashText(asset.networkHash) +
        "), not found in " + (searched.empty() ? std::string("no directory") : searched) +
        " (give --weights NET.ngiw, --networks DIR or NGI_NETWORK_DIR)";
    for (size_t i = skippedBefore; i < skipped.size(); ++i)
        problem +=
            i == skippedBefore ? "; skipped a network file that does not read: " + skipped[i] : "; and " + skipped[i];
    return std::nullopt;
}

std::string networkMismatch(const Asset& asset, const NetworkWeights& network)
{
    if (asset.networkId.empty()) return "";
    const uint64_t hash = networkHash(network);
    if (hash == asset.networkHash) return "";
    return "the asset names network '" + asset.networkId + "' (hash " + networkHashText(asset.networkHash) + ") but " +
        networkLabel(network) + " is '" + network.name + "' (hash " + networkHashText(hash) + ")";
}

NetworkWeights networkForRestore(const Asset& asset, const std::filesystem::path& weightsPath,
                                 std::span<const std::filesystem::path> dirs, std::string& warning,
                                 std::vector<std::string>& skipped)
{
    warning.clear();
    if (!weightsPath.empty()) {
        NetworkWeights given = readNetworkWeights(weightsPath);
        warning = networkMismatch(asset, given);
        return given;
    }
    if (!asset.weights.empty()) return parseNetworkWeights(asset.weights, "the asset's WGHT chunk");
    std::string problem;
    if (std::optional<NetworkWeights> named = findAssetNetwork(asset, dirs, problem, skipped)) return std::move(*named);
    throw Error("super-resolution restore needs a network: this asset carries no weights, and " + problem);
}

std::optional<NetworkWeights> defaultRestoreNetwork(const Asset& asset, std::span<const std::filesystem::path> dirs,
                                                    std::string& why, std::vector<std::string>& skipped)
{
    why.clear();
    std::optional<NetworkWeights> network;
    if (!asset.weights.empty())
        network = parseNetworkWeights(asset.weights, "the asset's WGHT chunk");
    else if (asset.networkId.empty()) {
        why = "the asset names no network";
        return std::nullopt;
    } else if (!(network = findAssetNetwork(asset, dirs, why, skipped))) {
        return std::nullopt;
    }
    for (const AssetChart& chart : asset.charts)
        if (networkRestoresChart(*network, chart)) return network;
    why = "its x" + std::to_string(network->scaleFactor) + " network restores none of its charts";
    return std::nullopt;
}

bool networkRestoresChart(const NetworkWeights& network, const AssetChart& chart)
{
    return chart.storedLevel > 0 && chart.storedLevel < 32 && network.scaleFactor == (1u << chart.storedLevel);
}

const ShippedNetwork* nameMatchingNetwork(Asset& asset, std::span<const ShippedNetwork> shipped)
{
    asset.networkId.clear();
    asset.networkHash = 0;
    if (asset.charts.empty()) return nullptr;
    for (const ShippedNetwork& s : shipped)
        if (!s.network.name.empty() && networkRestoresChart(s.network, asset.charts.front())) {
            asset.networkId = s.network.name;
            asset.networkHash = s.hash;
            return &s;
        }
    return nullptr;
}

}  // namespace ngi
