#pragma once
// Closest-feature correspondences E_C (paper §4.2, "Creating Feature Correspondences"): for
// each candidate pair, features of one frame are moved into the other by the current poses
// and matched to the closest compatible feature there, like ICP, without descriptors.
// Compatible: same family (refine/feature_index.h), within max_distance, and directions
// within max_angle (plane normals oriented, edge directions as lines).
//
// Thresholds (paper): 0.5 m / 45 deg the first time two frames share a window, decreasing
// linearly to 0.15 m / 20 deg as they stay together (here over decay_iterations iterations).
// The authors' code instead sets them per pair from the camera path between the frames,
// min + sqrt(d / (L / 2)) (max - min) with L the window length (ThresholdSchedule::kPath).
//
// After the paper's schedule, optional polish iterations use tighter thresholds still
// (polish_max_distance, polish_max_angle_deg).
//
// The total is subsampled to |C| = per_frame n (the paper: 100 n), spread evenly over the
// pairs (half of each pair's share from each side), with seeded, deterministic sampling; in
// the polish iterations to polish_per_frame n.

#include <array>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "f2c/optim/constraints.h"
#include "f2c/optim/pose.h"
#include "f2c/refine/feature_index.h"
#include "f2c/refine/pairs.h"
#include "f2c/refine/windows.h"
#include "f2c/util/fields.h"

namespace f2c {

enum class ThresholdSchedule { kAge, kPath };
F2C_ENUM_NAMES(ThresholdSchedule, {{ThresholdSchedule::kAge, "age"}, {ThresholdSchedule::kPath, "path"}})

struct CorrespondenceOptions {
  double initial_max_distance = 0.5;  // metres
  double initial_max_angle_deg = 45;
  double final_max_distance = 0.15;
  double final_max_angle_deg = 20;
  int decay_iterations = 3;  // kAge: iterations from the initial to the final thresholds
  // Beyond the paper: thresholds of the polish iterations (refine/windows.h).
  double polish_max_distance = 0.03;
  double polish_max_angle_deg = 10;
  ThresholdSchedule schedule = ThresholdSchedule::kAge;
  int per_frame = 100;  // |C| = per_frame n per iteration
  // Beyond the paper: |C| of the polish iterations (0: per_frame). Each iteration draws its
  // own sample, so the poses carry that sample's noise: with 100 n, the polish iterations
  // move every pose by about 0.1 deg RMS from one to the next without converging
  //; more correspondences there average it away.
  int polish_per_frame = 600;
  int min_per_pair = 6;   // a pair's share is never below this (then |C| exceeds per_frame n)
  double attempts = 3.0;  // features tried per correspondence wanted
  int neighbours = 4;     // closest features checked for compatibility, nearest first
  // Relative weights by the target feature's type (the authors': plane 1, silhouette 0.6,
  // ridge and valley 0.2); shadows and borders when used.
  std::array<double, kFeatureTypeCount> type_weights = {1.0, 0.6, 0.2, 0.2, 0.2, 0.2};
  uint64_t seed = 0;
  // Plane features held out for the self-check (refine/self_check.h's HeldOut, one in this
  // many; 0: none): never a correspondence's point or target. Set by the refinement.
  int held_out_every = 0;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: frame pairs and correspondences (paper 4.2)");
    F2C_FIELD(v, initial_max_distance, "--max-distance-initial", Positive(),
              "correspondence distance when a pair first shares a window (m)");
    F2C_FIELD(v, final_max_distance, "--max-distance-final", Positive(), "...decreasing linearly to this (m)");
    F2C_FIELD(v, initial_max_angle_deg, "--max-angle-initial", AboveUpTo(0, 180),
              "normal/direction angle when a pair first shares a window (deg)");
    F2C_FIELD(v, final_max_angle_deg, "--max-angle-final", AboveUpTo(0, 180), "...decreasing linearly to this (deg)");
    F2C_FIELD(v, decay_iterations, "--threshold-decay", AtLeast(0),
              "iterations from the initial to the final thresholds");
    F2C_FIELD(v, polish_max_distance, "--polish-max-distance", Positive(),
              "correspondence distance in polish iterations (m)");
    F2C_FIELD(v, polish_max_angle_deg, "--polish-max-angle", AboveUpTo(0, 180),
              "normal/direction angle in polish iterations (deg)");
    F2C_FIELD(v, schedule, "--thresholds", {},
              "age: by iterations together (the paper); path: per pair by camera path (the authors' code)");
    F2C_FIELD(v, per_frame, "--correspondences-per-frame", AtLeast(1), "|C| = this times the frames, per iteration");
    F2C_FIELD(v, polish_per_frame, "--polish-correspondences-per-frame", AtLeast(0),
              "|C| of the polish iterations, times the frames (0: --correspondences-per-frame)");
    F2C_FIELD(v, min_per_pair, "--min-correspondences-per-pair", AtLeast(1), "each pair's share at least this");
    F2C_FIELD(v, attempts, "", AtLeast(1), "features tried per correspondence wanted");
    F2C_FIELD(v, neighbours, "", Between(1, 64), "closest features checked for compatibility");
    v.Field(type_weights[0], "weight_plane", "--weight-plane", AtLeast(0),
            "E_C weight of plane correspondences (relative)");
    v.Field(type_weights[1], "weight_silhouette", "--weight-silhouette", AtLeast(0), "...of silhouette edges");
    v.Field(type_weights[2], "weight_shadow", "", AtLeast(0), "...of shadow edges (--use-shadows)");
    v.Field(type_weights[3], "weight_border", "", AtLeast(0), "...of image-border points (--use-borders)");
    v.Field(type_weights[4], "weight_ridge", "--weight-ridge", AtLeast(0), "...of ridges");
    v.Field(type_weights[5], "weight_valley", "--weight-valley", AtLeast(0), "...of valleys");
    F2C_FIELD(v, seed, "--refine-seed", {}, "seed of the correspondence sampling");
  }
  void Check() const;
};

struct Thresholds {
  double max_distance = 0;  // metres
  double max_angle = 0;     // radians
};

// kAge: thresholds after `age` iterations together (0: the first).
Thresholds ThresholdsForAge(const CorrespondenceOptions& options, int age);
// kPath: thresholds for frames `distance` metres of path apart in windows `window_length` long.
Thresholds ThresholdsForPath(const CorrespondenceOptions& options, double distance, double window_length);

struct CorrespondenceStats {
  int pairs = 0;                                 // candidate pairs searched
  int pairs_matched = 0;                         // pairs that gave at least one correspondence
  int per_pair = 0;                              // each pair's share
  int64_t tried = 0;                             // features moved and searched
  std::array<int, kFeatureTypeCount> by_type{};  // by the target feature's type
  int total() const;
};

// `path` holds each frame's camera path (metres), for kPath and path-window lengths.
std::vector<FeatureCorrespondence> FindCorrespondences(const std::vector<FramePair>& pairs, const FeatureIndex& index,
                                                       const PoseVector& poses, const WindowSchedule& schedule,
                                                       int iteration, const std::vector<double>& path,
                                                       const CorrespondenceOptions& options,
                                                       CorrespondenceStats* stats = nullptr);

nlohmann::json ToJson(const CorrespondenceStats& stats);

}  // namespace f2c
