#pragma once
// report.html for a register run (src/f2c/report/report.h): the run's facts from run.json,
// T0 and the final trajectory against the ground truth when the dataset has one, the
// frames that fell back to ICP or the motion prior, the dataset's ground-truth
// correspondences when it has them, and pictures of the mesh.

#include <nlohmann/json.hpp>
#include <string>

#include "f2c/io/ply.h"
#include "f2c/io/sequence.h"
#include "f2c/odometry/odometry.h"
#include "f2c/report/report.h"

namespace f2c::app {

// `mesh` may be null (no mesh fused). `run` is run.json's content.
std::string RegisterReport(const RgbdSequence& seq, const Odometry& odometry, const Trajectory& result, bool refined,
                           const nlohmann::json& run, const PlyPoints* mesh);

// What `frames` evenly spread frames of `seq` saw, for the report's top-down slice (the
// paper's Fig. 1): depth on an 8-pixel grid with normals, a few ms per frame. Needs the
// sequence's intrinsics; frames whose depth cannot be read are left out.
void AddSliceFrames(const RgbdSequence& seq, int frames, ReportInput* in);

// Debian's three.js and its orbit controls, to inline; empty when libjs-three is absent.
std::string ThreeJs();

// A picture as an <img> with its PNG/JPEG bytes inline (base64), so the page stays one file.
std::string InlineImage(const std::string& encoded_bytes, const std::string& mime, const std::string& alt, int width);

}  // namespace f2c::app
