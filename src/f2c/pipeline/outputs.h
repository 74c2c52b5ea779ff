#pragma once
// A registration's files, written from its typed result (register.h): the trajectories
// (TUM, .log, .conf, T0), odometry.json, mesh.ply, run.json and report.html. Each file is
// written whole (a temporary, then renamed).

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "f2c/pipeline/register.h"

namespace f2c {

struct OutputOptions {
  bool report = true;       // report.html
  bool iterations = false;  // iterations/iteration_NN.txt (with RegisterOptions::keep_iterations)
  std::string input;        // what run.json names as the input (default: the sequence's root)
  IoOptions io;             // how the input was read, for run.json's options
  nlohmann::json options;   // run.json's "options" (null: io's and the stages' options)
};

// Versions of fine2coarse and its main libraries, for run.json.
nlohmann::json Versions();

// run.json: the input, intrinsics, versions, options, each stage's timings, statistics and
// the refinement's per-iteration record, the outputs.
nlohmann::json RunJson(const RegisterResult& result, const RegisterOptions& options, const OutputOptions& outputs);

// Writes the files into `dir` (made if missing) and returns their names (run.json's
// "outputs"), cache files included when RegisterOptions::cache_dir is `dir`/cache.
std::vector<std::string> WriteOutputs(const std::filesystem::path& dir, const RegisterResult& result,
                                      const RegisterOptions& options, const OutputOptions& outputs = {});

}  // namespace f2c
