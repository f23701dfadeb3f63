// ngi offline: the bake report as JSON (nlohmann-json): the --json summary of ngi-bake and
// the asset's metadata chunk (report + seam description).
#pragma once

#include "ngi/bake/bake.h"

#include <nlohmann/json.hpp>

namespace ngi {

// The --json summary: vertex and face counts before and after remeshing, genus, boundaries,
// cut length, Ricci and OT iterations and residuals, area and angle distortion, flipped
// triangles, time per stage (seconds). The tool adds file names, bytes and peak memory.
nlohmann::json bakeReportJson(const BakeReport& report);

// The seam of the asset: cut description plus, per disk boundary vertex, its uv, and the pairs
// of boundary edges that are mates (edge i runs from boundary vertex i to i + 1); the corners.
nlohmann::json seamJson(const DiskMesh& disk, const SquareMap& map, const CutReport& cut);

} // namespace ngi
