#pragma once
// Trajectory error as the TUM RGB-D benchmark tools define it.
//
// ATE (evaluate_ate.py): associate estimate and ground truth by time stamp (nearest, within
// max_time_difference, greedy unique), fit the rigid transform (Horn/Umeyama, no scale)
// that maps estimated positions onto true ones, and take the per-pose distances.
//
// RPE (evaluate_rpe.py, fixed delta): for each estimated pose i, j = the pose closest to
// stamp_i + delta (seconds) or i + delta (frames); the error of the relative motion is
// E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j), Q ground truth, P estimate; translational error |trans E|
// (metres), rotational error angle(E) (degrees).
//
// Rotation drift (beyond the TUM tools, issue 9): the RPE's rotational error over every pair
// of associated poses at least drift_min_seconds apart. With D_i = Q_i P_i^-1 (rotations
// only), the pair's error is angle(D_i^-1 D_j): how far a wall seen from frame i and the same
// wall seen from frame j are from parallel after registration, whatever lies between them.
// Its worst value is what a straight multi-room scan needs small.
//
// Smoothed rotation drift: the same pairs, each D_i replaced by the chordal mean of the D_j
// within drift_smoothing_seconds / 2 of it (all associated poses, before the subsampling;
// the nearest rotation to their sum). Drift builds up over seconds, while a single frame a
// few tenths of a degree off its neighbours (a frame the data place poorly) sets the worst
// pair on its own; the smoothed worst is what remains of the scan's bending once each
// second of it is averaged, so the two together tell drift from jitter.

#include <vector>

#include <nlohmann/json.hpp>

#include "f2c/io/trajectory.h"
#include "f2c/util/fields.h"

namespace f2c {

struct ErrorStatistics {
  int count = 0;
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;
};
ErrorStatistics ComputeStatistics(std::vector<double> errors);

struct EvaluationOptions {
  double max_time_difference = 0.02;  // seconds, for ATE association (TUM default)
  double rpe_delta_seconds = 1.0;     // RPE per second
  int rpe_delta_frames = 1;           // RPE per frame
  double drift_min_seconds = 5.0;     // rotation drift: pairs at least this far apart in time
  // Rotation drift over all pairs of at most this many poses, evenly spaced (every pose when
  // there are fewer): the pairs grow as the square of the poses.
  int drift_max_poses = 2000;
  // Rotation drift: the share of pairs beyond this angle is reported too (degrees; issue 9's
  // target for the worst pair), and the 99th percentile: the worst pair is set by a few
  // frames, the percentile by the scan.
  double drift_threshold_deg = 0.5;
  // Smoothed rotation drift: each pose's D_i averaged over this window (seconds; 0: off).
  double drift_smoothing_seconds = 1.0;

  template <class V>
  void Fields(V& v) {
    v.Group("Evaluation");
    F2C_FIELD(v, max_time_difference, "--max-time-difference", Positive(), "association window (s)");
    F2C_FIELD(v, rpe_delta_seconds, "", Positive(), "RPE per this many seconds");
    F2C_FIELD(v, rpe_delta_frames, "", AtLeast(1), "RPE per this many frames");
    F2C_FIELD(v, drift_min_seconds, "--drift-min-seconds", AtLeast(0),
              "rotation drift: the relative rotation error over all pose pairs at least this far apart in time (s)");
    F2C_FIELD(v, drift_max_poses, "", AtLeast(2), "rotation drift: poses sampled at most");
    F2C_FIELD(v, drift_threshold_deg, "--drift-threshold", AtLeast(0),
              "rotation drift: also the share of pairs beyond this angle (deg), and the 99th percentile");
    F2C_FIELD(v, drift_smoothing_seconds, "--drift-smoothing", AtLeast(0),
              "smoothed rotation drift: each pose's rotation error averaged over this window first (s; 0: off)");
  }
  void Check() const;
};

struct AteResult {
  ErrorStatistics translation;  // metres
  Rigid3d gt_from_estimate = Rigid3d::Identity();
  int estimated_poses = 0;
  std::vector<double> errors;  // per associated pose
};

struct RpeResult {
  ErrorStatistics translation;  // metres
  ErrorStatistics rotation;     // degrees
};

struct RotationDrift {
  ErrorStatistics rotation;  // degrees, over pose pairs
  int poses = 0;             // poses the pairs were drawn from
  double min_seconds = 0;
  double p99 = 0;            // degrees: the 99th percentile (linear between ranks, as numpy's)
  double threshold_deg = 0;  // ...and the share of pairs beyond this angle
  double share_over = 0;
  double smoothing_seconds = 0;  // the window each D_i was averaged over (0: none)
};

struct EvaluationResult {
  AteResult ate;
  RpeResult rpe_per_frame;
  RpeResult rpe_per_second;
  RotationDrift drift;
  RotationDrift drift_smoothed;  // count 0 when drift_smoothing_seconds is 0
};

// A statistic's numbers as `evaluate --json` prints them (rmse, mean, median, std, min, max,
// count).
nlohmann::json ToJson(const ErrorStatistics& statistics);
// The trajectory metrics as `evaluate --json` prints them (ate_m, rpe_per_frame,
// rpe_per_second, the rotation drift's keys), for the CLI and the Python module alike.
nlohmann::json ToJson(const EvaluationResult& result);

// InputError (naming "estimate") when fewer than 3 poses associate.
AteResult ComputeAte(const Trajectory& estimate, const Trajectory& ground_truth, const EvaluationOptions& options = {});

// `delta` in seconds if `in_seconds`, else in frames of the estimate.
RpeResult ComputeRpe(const Trajectory& estimate, const Trajectory& ground_truth, double delta, bool in_seconds);

// Pairs counted: 0 when no two associated poses are min_seconds apart.
RotationDrift ComputeRotationDrift(const Trajectory& estimate, const Trajectory& ground_truth,
                                   const EvaluationOptions& options = {});

// The smoothed rotation drift (above): drift_smoothing_seconds must be positive.
RotationDrift ComputeSmoothedRotationDrift(const Trajectory& estimate, const Trajectory& ground_truth,
                                           const EvaluationOptions& options = {});

EvaluationResult Evaluate(const Trajectory& estimate, const Trajectory& ground_truth,
                          const EvaluationOptions& options = {});

}  // namespace f2c
