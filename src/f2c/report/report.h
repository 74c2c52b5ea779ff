#pragma once
// report.html: one self-contained page per run (works offline, no network), with the run's facts
// and inline SVG plots (svg_plot.h): the trajectories from above and from the side, aligned
// as for ATE; translation and rotation error over time; error against frame distance (the
// paper's Fig. 9), from ground-truth correspondences where the dataset has them, else from
// relative pose errors; the histogram of correspondence errors; and, per refinement iteration,
// each energy term's cost, the correspondences by type, the window length and the time; a
// top-down slice of the registered points under each set of poses (the paper's Fig. 1).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "f2c/eval/correspondence_error.h"
#include "f2c/io/correspondences.h"
#include "f2c/io/trajectory.h"
#include "f2c/report/slice.h"

namespace f2c {

struct ReportTrajectory {
  std::string name;  // "T0", "final", ...
  Trajectory trajectory;
  std::string color;  // SVG colour
};

// One refinement iteration, as run.json records it.
struct ReportIteration {
  double window_length = 0;  // frames (or metres of path)
  int windows = 0;
  double seconds = 0;
  std::vector<std::pair<std::string, double>> cost_after;  // per energy term
  std::vector<std::pair<std::string, int>> correspondences_by_type;
  // The self-check (refine/self_check.h): held-out features' RMS disagreement before and after
  // the iteration (metres; NaN: no check), and whether the iteration was undone.
  double check_before = std::numeric_limits<double>::quiet_NaN();
  double check_after = std::numeric_limits<double>::quiet_NaN();
  bool undone = false;
};

struct ReportInput {
  std::string title;
  std::vector<std::pair<std::string, std::string>> facts;  // shown as a two-column table
  std::string options_json;  // every option of the run, shown folded under the facts (empty: none)
  std::optional<Trajectory> ground_truth;
  std::vector<ReportTrajectory> estimates;  // the last is the result; fallbacks are marked on it
  std::vector<double> fallback_times;       // frames aligned by ICP or the motion prior (time stamps)
  // Ground-truth correspondences and the time stamp of each frame they name.
  std::vector<Correspondence> correspondences;
  std::vector<double> frame_timestamps;
  double max_time_difference = 0.02;        // association of estimates with frames / ground truth
  std::vector<ReportIteration> iterations;  // the refinement's, if it ran
  // The 3D view (three.js, inlined: the page stays one file that works offline): points with
  // colours (e.g. the mesh's vertices, subsampled), the camera path, and which way is up.
  // Left out, with a line saying why, when `three_js` (the library's source) is empty.
  std::string three_js;
  std::vector<Eigen::Vector3f> points;
  std::vector<std::array<uint8_t, 3>> point_colors;
  std::vector<Eigen::Vector3f> camera_path;
  Eigen::Vector3f up = Eigen::Vector3f::UnitZ();
  // The top-down slice of the registered points (the paper's Fig. 1; slice.h): what some
  // frames saw, at these time stamps, placed by the ground truth and by each estimate.
  std::vector<double> slice_timestamps;
  std::vector<SliceFrame> slice_frames;
  SliceOptions slice_options;
  std::string no_slice_reason;  // said in the slice's place when there are no slice frames
  std::string extra_html;       // appended as is (pictures, further tables)
};

// The whole page (UTF-8). Sections without their data (no ground truth, no correspondences)
// are left out, with a line saying why.
std::string BuildReport(const ReportInput& input);

// Bytes as base64 (RFC 4648), for data inlined in the page.
std::string Base64(const std::string& bytes);

// A histogram of `values` over [0, max) in `bins` equal bins (values beyond go to the last).
std::vector<int> Histogram(const std::vector<double>& values, double max, int bins);

}  // namespace f2c
