#pragma once
// What the subcommands share: run.json pieces and the CLI option groups that several
// subcommands take.

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "f2c/features/depth_features.h"
#include "f2c/fusion/fuse.h"
#include "f2c/io/sequence.h"

namespace f2c::app {


// Versions of fine2coarse and its main libraries, for run.json.
nlohmann::json Versions();

nlohmann::json ToJson(const FusionTimings& timings, const PlyPoints& mesh);

}  // namespace f2c::app
