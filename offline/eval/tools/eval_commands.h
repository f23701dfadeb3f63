// ngi-eval's subcommands, one file each (ngi_eval_main.cpp dispatches to them), and the
// restore-network choice that `mesh` and `watertight` share.
#pragma once

#include "ngi/asset.h"
#include "ngi/eval/asset_mesh.h"
#include "ngi/network_weights.h"

#include <optional>
#include <string>
#include <vector>

namespace ngi::eval_cli {

// Each subcommand reads its arguments (those after the command name), does its work, prints
// its result on stdout and returns the exit status (0). Bad arguments throw ngi::UsageError
// (ngi/command_line.h: the dispatcher prints the usage, exit 2); any other failure throws
// ngi::Error naming the file it concerns (exit 1).

// `ngi-eval distance REFERENCE CANDIDATE [options]`: CD, HD and the colour PSNR of CANDIDATE
// against REFERENCE (eval_distance.cpp).
int distanceCommand(const std::vector<std::string>& args);

// `ngi-eval mesh ASSET ... -o OUT`: the mesh the renderer draws for ASSET (eval_mesh.cpp).
int meshCommand(const std::vector<std::string>& args);

// `ngi-eval watertight ASSET [restore]`: open edges and gaps of the drawn mesh at every LoD and
// at adaptive bounds (eval_watertight.cpp).
int watertightCommand(const std::vector<std::string>& args);

// `ngi-eval report --meshes DIR_OR_LIST --out DIR [options]`: bakes and measures, writes
// DIR/report.md (eval_report.cpp). `commandLine` is quoted in the report.
int reportCommand(const std::vector<std::string>& args, const std::string& commandLine);

// The network --sr restores with (ngi/network_catalog.h): --weights, the asset's WGHT chunk
// (restoreFullResolution parses it), or the shipped network the asset names. Prints which, a
// warning when --weights overrides the asset's network, and the charts left to bicubic.
// With no restore option given (`restoreGiven` false): the network the asset carries or names
// when it is found and restores it (defaultRestoreNetwork), else bicubic as ngi-render's
// default, with a warning when the asset names a network that is not found. Throws ngi::Error
// naming the weights file, or `assetPath`, when the network does not read or cannot restore it.
void chooseNetwork(const std::string& assetPath, const ngi::Asset& asset, const std::optional<std::string>& weightsPath,
                   const std::optional<std::string>& networks, ngi::NetworkWeights& network,
                   ngi::AssetMeshOptions& options, bool restoreGiven);

}  // namespace ngi::eval_cli
