#pragma once
// E_L's constraints (paper §4.3, "Local Alignment Error"): the relative transforms that T0
// holds between frames j and j + 2^k, k = 0..max_power, and between each frame and the frame
// its odometry aligned it to (its keyframe), kept as the refinement moves poses, so the
// trajectory keeps its local shape. Each is weighted by how much the odometry trusted the
// alignments on the path between the two frames in the tree of odometry references
// (odometry.json), the weakest link deciding:
//   confidence(pair) = method factor (SIFT 1; ICP fallback icp_weight, or
//                      icp_measured_weight where the depth or the image measured every
//                      direction of its motion (odometry.json's degenerate 0); motion prior
//                      prior_weight)
//                    x sigmoid(inlier_slope (inliers - inlier_midpoint))   (SIFT pairs; the
//                      authors' sigmoid of the SIFT inliers)
//                    x ramp(fitness: fitness_low -> 0, fitness_high -> 1, at least min_ramp)
// so an ICP fallback or a pair whose depth overlap is poor weighs less than a clean SIFT pair.
// Optionally (the authors' code) longer spans weigh less: x exp(-d^2 / (2 distance_sigma^2)),
// d the distance T0 puts between the two cameras.
//
// Whitened (beyond the paper; `information`): where every pair on the path is a SIFT or
// tracked pair with its fit's information, or an ICP fallback with the information of its
// fusion (`icp_information`; PairAlignment::information, odometry/depth_alignment.h
// MeasuredInformation: what the depth and the image measured, and the motion prior's
// uncertainty along the rest), the constraint is
// weighed by what those fits measured, direction by direction, instead of by one number and
// the lever arm. A pair's covariance is its information's inverse plus a floor (below); the
// path's is the sum of its pairs', each moved into frame a's coordinates by the adjoint of
// T0's a_from_reference (pairs are independent measurements; the path's shared keyframe
// cancels), and RelativePoseCost's error e = J eps of a left perturbation eps of a_from_b
// (optim/cost_functions.h) has covariance J Sigma J^T; M is the upper Cholesky factor of its
// inverse, times reference_sigma (by default the median translation sigma of the scan's
// whitened constraints), so a typical pair weighs about as a scalar one. The confidence is
// then the fitness ramp alone: the information says what the inlier count said, better. A
// mottled wall's tracked pairs that fix its roll poorly give E_L little say over that roll
// and full say over what they measured well; a run of fallbacks facing a plain wall holds its
// distance and tilts firmly and leaves its roll and slides, which the odometry took from the
// prior, to E_V's steady motion (refine/steady_motion.h), which weighs more there.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "f2c/odometry/odometry.h"
#include "f2c/optim/constraints.h"
#include "f2c/util/fields.h"

namespace f2c {

enum class LocalSpans { kFrames, kKeyframes };
F2C_ENUM_NAMES(LocalSpans, {{LocalSpans::kFrames, "frames"}, {LocalSpans::kKeyframes, "keyframes"}})

struct LocalAlignmentOptions {
  // k_max: frames j + 1, ..., j + 2^k_max. The paper spans up to 16 frames (k_max 4); here
  // consecutive frames only (0). A long span carries the drift of every pair it crosses as
  // if it were one measurement, and fights the correspondences that remove that drift;
  // measured, with spans up to 16 E_L had to weigh
  // little, and the refined poses were no steadier from frame to frame than T0.
  int max_power = 0;
  double icp_weight = 0.3;
  // An ICP pair that left nothing to the prediction (a corner's three planes, or the
  // photometric step along what the depth left free, docs/odometry.md) is a measurement like
  // a SIFT pair's. Measured: 0.3 for these too left the runs
  // of frames facing a mottled wall bent by up to 1 deg.
  double icp_measured_weight = 1.0;
  double prior_weight = 0.01;
  double inlier_midpoint = 5;
  double inlier_slope = 0.5;
  double fitness_low = 0.4;
  double fitness_high = 0.8;
  double min_ramp = 0.05;
  double distance_sigma = 0;   // metres; 0: off
  bool information = true;     // whiten constraints whose pairs all carry their information
  double reference_sigma = 0;  // metres; 0: the median translation sigma of those constraints
  // What the fit's noise model leaves out (a real sensor's depth distortion, colour-depth
  // misregistration, rolling shutter) does not shrink with more inliers: each pair's covariance
  // gains these standard deviations in every direction. Measured: without them the real sequences
  // lost (fr1/xyz 0.0108 -> 0.0129 m, redkitchen 0.0262 -> 0.0294 m: their fits claim 0.03-0.04
  // deg); with them they are level and the simulated walks keep most of the gain.
  double floor_rotation_deg = 0.05;
  double floor_translation = 0.001;  // metres
  // ICP fallbacks whitened too, by the information their fusion of depth, image and motion
  // prior had (PairAlignment::information). Measured:
  // with one weight each, E_L held the roll and slide that a run of fallbacks facing a plain
  // wall had taken from the prior as firmly as what their depth measured.
  bool icp_information = true;
  // Which pairs: kFrames, j and j + 2^k over all frames (the paper), plus each frame and its
  // reference; kKeyframes, each frame and its reference (the odometry's own measurements),
  // plus keyframes i and i + 2^k over the keyframes (k >= 1). Without keyframe odometry the
  // two are the same.
  LocalSpans spans = LocalSpans::kFrames;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: energy and solver (paper 4.3)");
    F2C_FIELD(v, max_power, "--local-max-power", Between(0, 20), "E_L between frames j and j + 2^k, k <= this");
    F2C_FIELD(v, icp_weight, "--local-icp-weight", Between(0, 1),
              "E_L confidence of ICP-fallback pairs (SIFT pairs up to 1)");
    F2C_FIELD(v, icp_measured_weight, "--local-icp-measured-weight", Between(0, 1),
              "...of ICP-fallback pairs with no direction left to the prediction");
    F2C_FIELD(v, prior_weight, "--local-prior-weight", Between(0, 1), "E_L confidence of motion-prior pairs");
    F2C_FIELD(v, inlier_midpoint, "", AnyFinite(), "SIFT confidence: logistic midpoint in inliers");
    F2C_FIELD(v, inlier_slope, "", AtLeast(0), "...and its slope");
    F2C_FIELD(v, fitness_low, "", Between(0, 1), "SIFT confidence: fitness ramp start");
    F2C_FIELD(v, fitness_high, "", Between(0, 1), "...and end");
    F2C_FIELD(v, min_ramp, "", Between(0, 1), "...the ramp's floor");
    F2C_FIELD(v, spans, "--local-spans", {},
              "E_L pairs: frames (j, j + 2^k, and each frame with its keyframe) or keyframes (each frame with its "
              "keyframe, and keyframes i, i + 2^k)");
    F2C_FIELD(v, distance_sigma, "--local-distance-sigma", AtLeast(0),
              "E_L weight exp(-d^2/2s^2) by camera distance (m; 0: off)");
    F2C_FIELD(v, information, "--local-information=on|off", {},
              "E_L constraints over SIFT and tracked pairs whitened by their fits' information (off: one weight each)");
    F2C_FIELD(v, reference_sigma, "--local-reference-sigma", AtLeast(0),
              "a whitened constraint this uncertain (m) weighs as a scalar one (0: the scan's median)");
    F2C_FIELD(v, floor_rotation_deg, "--local-floor-rotation", AtLeast(0),
              "each whitened pair's rotation is uncertain by at least this (deg)");
    F2C_FIELD(v, floor_translation, "--local-floor-translation", AtLeast(0),
              "...and its translation by at least this (m)");
    F2C_FIELD(v, icp_information, "--local-icp-information=on|off", {},
              "whiten E_L through ICP fallbacks too, by what their depth and image measured");
  }
  void Check() const;
};

double PairConfidence(const PairAlignment& pair, const LocalAlignmentOptions& options);
// Whether E_L whitens this pair (`information` on, a SIFT or tracked pair, or an ICP
// fallback with `icp_information` on, whose information is positive definite); its
// confidence is then the fitness ramp alone.
bool Whitens(const PairAlignment& pair, const LocalAlignmentOptions& options);
// The fitness ramp of PairConfidence alone.
double FitnessRamp(const PairAlignment& pair, const LocalAlignmentOptions& options);

// The covariance of RelativePoseCost's error (translation in a, rotation in b) when the
// estimate is exp(w, v) a_from_b and (w, v) has covariance left_covariance_in_a.
Eigen::Matrix<double, 6, 6> LocalErrorCovariance(const Rigid3d& a_from_b,
                                                 const Eigen::Matrix<double, 6, 6>& left_covariance_in_a);

// pairs[k-1] aligns frame k to its reference (odometry.h); one constraint per (j, j + 2^k)
// inside the scan, and one per (reference, k) that is not among those.
std::vector<RelativePoseConstraint> LocalConstraints(const std::vector<PairAlignment>& pairs,
                                                     const LocalAlignmentOptions& options);

}  // namespace f2c
