#pragma once
// report.html for a registration (src/f2c/report/report.h): the run's facts, T0 and the
// final trajectory against the ground truth when the dataset has one, the frames that fell
// back to ICP or the motion prior, the dataset's ground-truth correspondences when it has
// them, the refinement's iterations and self-check, and pictures of the mesh.

#include <string>

#include "f2c/pipeline/register.h"

namespace f2c {

// `input` as run.json names it; `options_json`: every option of the run, shown folded under
// the facts (run.json's).
std::string RegisterReport(const RegisterResult& result, const std::string& input, const std::string& options_json);

}  // namespace f2c
