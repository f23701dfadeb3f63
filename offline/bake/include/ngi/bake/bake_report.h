// ngi offline: the bake report as JSON (nlohmann-json): the --json summary of ngi-bake and
// the asset's metadata chunk (the seams are the binary SEAM chunks, ngi/seam.h).
#pragma once

#include "ngi/bake/bake.h"

#include <nlohmann/json.hpp>

namespace ngi {

// The --json summary: vertex and face counts before and after remeshing, genus, boundaries,
// cut length, Ricci and OT iterations and residuals, area and angle distortion, flipped
// triangles, time per stage (seconds). The tool adds file names, bytes and peak memory.
nlohmann::json bakeReportJson(const BakeReport& report);

}  // namespace ngi
