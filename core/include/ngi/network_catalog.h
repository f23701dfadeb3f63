// ngi core: the shipped super-resolution networks (assets/*.ngiw) and the one an asset expects
// ("--sr with no --weights uses the shipped network matching the asset").
//
// An asset names its network in HEAD: Asset::networkId = the network's `name` (e.g. "ngi-sr-x8")
// and Asset::networkHash = networkHash(network), FNV-1a 64 of its serialized file. ngi-bake
// writes both when a shipped network restores the largest chart's stored level to its full
// resolution (factor = 2^storedLevel); an asset baked with no such network names none.
//
// Where the networks are found (networkSearchPath): `--networks DIR` alone when given; else
// $NGI_NETWORK_DIR (one directory) when set, then beside the executable: ../../assets (a build
// tree bin/ inside the repository: build/bin -> assets) and ../share/ngi (an installed prefix/bin).
// Every *.ngiw file directly in a directory is a candidate; the first one (directories in order,
// files by name) whose name and hash are the asset's is used.
//
// Mismatches are never silent: an asset naming a network whose shipped file of that name has
// another hash (a retrained network) is an error naming both hashes and the file; --weights
// overriding an asset's named network with a different one is a warning (networkMismatch).
// A *.ngiw file that does not parse is skipped, so that one broken file does not hide the valid
// networks beside it: each such file is one sentence in the `skipped` list the functions below
// fill ("FILE: PROBLEM"), which the tools print as warnings, and a network not found says
// which files were skipped.
#pragma once

#include "ngi/asset.h"
#include "ngi/network_weights.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace ngi {

// The directories searched for shipped networks, in order (see the top of this file):
// [explicitDir] when it is not empty; else $NGI_NETWORK_DIR (if set and not empty), then
// EXE/../../assets and EXE/../share/ngi with EXE the directory of /proc/self/exe (left out when
// it cannot be read). Directories that do not exist are kept (the messages list what was searched).
std::vector<std::filesystem::path> networkSearchPath(const std::filesystem::path& explicitDir = {});

// One network file found in the search path.
struct ShippedNetwork {
    std::filesystem::path path;
    NetworkWeights network;  // source = the path
    uint64_t hash = 0;       // networkHash(network)
};

// Every *.ngiw file directly in `dirs` that parses (missing directories skipped), directories
// in order, files by name. A file that does not parse is left out and its reader's error
// ("FILE: PROBLEM") appended to `skipped`.
std::vector<ShippedNetwork> findShippedNetworks(std::span<const std::filesystem::path> dirs,
                                                std::vector<std::string>& skipped);

// The first of `shipped` whose scale factor is `factor`, else null (what ngi-bake names).
const ShippedNetwork* shippedNetworkForFactor(std::span<const ShippedNetwork> shipped, uint32_t factor);

// The network `asset` names, looked up in `dirs` (findShippedNetworks: files that do not parse
// are appended to `skipped`). Returns it, or nullopt with `problem` set to one sentence (no file
// name prefix): the asset names none; no file of that name in the search path (listing the
// directories and the files skipped); or files of that name but with another hash (naming the
// first such file and both hashes).
std::optional<NetworkWeights> findAssetNetwork(const Asset& asset, std::span<const std::filesystem::path> dirs,
                                               std::string& problem, std::vector<std::string>& skipped);

// "" when `asset` names no network or `network` is the one it names (same hash); else one
// sentence naming both ("the asset names network 'A' (hash H1) but NET is 'B' (hash H2)"),
// which the tools print as a warning when --weights overrides the asset's network.
std::string networkMismatch(const Asset& asset, const NetworkWeights& network);

// The hash as 16 lowercase hex digits (how messages and the bake JSON write it).
std::string networkHashText(uint64_t hash);

// Whether `network` restores `chart` (its factor takes the stored level to the full size).
bool networkRestoresChart(const NetworkWeights& network, const AssetChart& chart);

// The network a tool's --sr restores `asset` with: the file `weightsPath` when it is not empty
// (`warning` = networkMismatch when the asset names another), else the asset's own WGHT chunk
// (source "the asset's WGHT chunk"), else the shipped network the asset names, found in `dirs`
// (findAssetNetwork; unparsable files there are appended to `skipped`). ngi::Error
// "super-resolution restore needs a network: this asset carries no weights, and PROBLEM" when
// there is none; the readers' errors otherwise (the --weights file's, the WGHT chunk's).
NetworkWeights networkForRestore(const Asset& asset, const std::filesystem::path& weightsPath,
                                 std::span<const std::filesystem::path> dirs, std::string& warning,
                                 std::vector<std::string>& skipped);

// The tools' default restore (no --sr, no --no-sr: "every tool restores with the matching
// network by default"): the asset's own WGHT chunk, else the shipped network it names found in
// `dirs` (findAssetNetwork), when that network restores at least one chart; else nullopt and
// `why` one sentence saying why not ("the asset names no network", the lookup's problem, or the
// factor that restores no chart), which the tools print before restoring without a network.
// Network files that do not parse are appended to `skipped`; ngi::Error only for a WGHT chunk
// that does not parse.
std::optional<NetworkWeights> defaultRestoreNetwork(const Asset& asset, std::span<const std::filesystem::path> dirs,
                                                    std::string& why, std::vector<std::string>& skipped);

// What ngi-bake does: names in `asset` (networkId, networkHash) the first of `shipped` that
// restores its largest chart (charts[0]) and returns it; with none, clears both and returns null.
// The other charts are restored by it only where their factor is the same (networkRestoresChart);
// the tools restore the rest without it and say so.
const ShippedNetwork* nameMatchingNetwork(Asset& asset, std::span<const ShippedNetwork> shipped);

}  // namespace ngi
