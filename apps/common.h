#pragma once
// What the subcommands share: run.json pieces and the CLI option groups that several
// subcommands take.

#include <CLI/CLI.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "f2c/features/depth_features.h"
#include "f2c/fusion/fuse.h"
#include "f2c/io/sequence.h"
#include "f2c/io/trajectory.h"

namespace f2c::app {


// Versions of fine2coarse and its main libraries, for run.json.
nlohmann::json Versions();

nlohmann::json ToJson(const FusionTimings& timings, const PlyPoints& mesh);

// Ground truth from a trajectory file or a dataset folder (or .conf; then `*dataset` holds
// it: its frame time stamps place estimates that carry frame ids, and its frames feed the
// report). InputError naming `path` when a dataset has none.
Trajectory LoadGroundTruth(const std::filesystem::path& path, IoOptions io, std::optional<RgbdSequence>* dataset);

}  // namespace f2c::app
