#pragma once
// Depth alignment for pairs SIFT cannot align (textureless views): point-to-plane ICP (OpenCV
// rgbd's ICPOdometry, KinectFusion-style, on an image pyramid) started from the previous
// motion; the motions a view's depth (and image) constrain; and a depth-overlap score that
// measures any pair's alignment.

#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/geometry/rigid.h"
#include "f2c/odometry/photometric.h"
#include "f2c/util/fields.h"

namespace f2c {

struct IcpOptions {
  double min_depth = 0.3;  // metres; pixels outside are ignored
  double max_depth = 5.0;
  double max_depth_difference = 0.07;        // correspondences further apart (metres) are dropped
  double max_points_part = 0.07;             // fraction of pixels sampled per level (OpenCV default)
  std::vector<int> iterations{7, 7, 7, 10};  // per pyramid level, fine to coarse
  // ICP runs on the depth images shrunk by this factor (every n-th pixel). 2 is 4x less work
  // but less accurate: mean T0 ATE 0.32 m against 0.20 m over the six simulated walks.
  int downscale = 1;
  double max_translation = 0.3;    // metres between frames; larger answers are rejected
  double max_rotation_deg = 30.0;  // likewise
  // Degenerate geometry (a plain wall leaves ICP free to slide along it and turn about its
  // normal; a corner, to slide along the edge): ICP's answer is fused with the previous
  // motion as two estimates, ICP's information along each direction of motion being the
  // reference's point-to-plane constraint there (an eigenvalue, per sample and in units of
  // the mean depth; ConstrainToGeometry) and the previous motion's this much in every
  // direction. A plain wall's tilts score 0.06-0.12 and its distance 1, its slides 0. 0: off.
  double prior_information = 0.01;
  int degeneracy_stride = 8;  // pixels between the reference depth samples it looks at
  // A wall the depth leaves free may still show texture SIFT does not key on (mottled
  // plaster, low-contrast paint). Where the depth leaves directions to the prior, the fused
  // answer is refined along them (and along any the image measures better than the depth,
  // PhotometricDirections) by dense photometric alignment (photometric.h), and each
  // reference sample whose grey-level gradient (Gaussian sigma 1 px, central differences) is
  // at least min_gradient adds the constraint the image puts on the sideways motion of its
  // point (AnalyseViewConstraints), which decides how much of it is kept. On the simulated
  // walks a flat-colour wall's noise gradients reach 1 grey level per pixel at 1% of its
  // pixels; mottled plaster exceeds 2 at a quarter of them. On since the loops' presolve
  // keeps the better of two starts (refine/sift_loops.h): before, the 5,000-frame walk lost
  // with it.
  bool photometric = true;
  double min_gradient = 2.0;  // grey levels per pixel
  // How far the motion prior's prediction is off per pair (metres; rotations at the mean depth):
  // the scale of an ICP fallback's information (MeasuredInformation). Measured: 5 mm against 10 and
  // 20 on the simulated walks.
  double prior_sigma = 0.005;
  // ...widened by this many prior_sigma for each pair in a row before it that left
  // directions to the motion prior (PriorAge): the prior came from them.
  double prior_sigma_growth = 0.5;
  PhotometricOptions dense;

  template <class V>
  void Fields(V& v) {
    v.Group("Keyframe odometry");
    F2C_FIELD(v, min_depth, "", AtLeast(0), "ICP: nearest depth used (m)");
    F2C_FIELD(v, max_depth, "", Positive(), "ICP: farthest depth used (m)");
    F2C_FIELD(v, max_depth_difference, "", Positive(), "ICP: correspondences farther apart are dropped (m)");
    F2C_FIELD(v, max_points_part, "", AboveUpTo(0, 1), "ICP: share of pixels sampled per level");
    F2C_FIELD(v, iterations, "", {}, "ICP iterations per pyramid level, fine to coarse");
    F2C_FIELD(v, downscale, "--icp-downscale", Between(1, 8), "depth ICP on the depth images shrunk by this factor");
    F2C_FIELD(v, max_translation, "", Positive(), "ICP answers moving farther are rejected (m)");
    F2C_FIELD(v, max_rotation_deg, "", Positive(), "...or turning farther (deg)");
    F2C_FIELD(v, prior_information, "--icp-prior", AtLeast(0),
              "ICP keeps lambda / (lambda + this) of its motion along each direction the depth constrains by "
              "lambda, the motion prior the rest (0: ICP alone)");
    F2C_FIELD(v, degeneracy_stride, "", AtLeast(1), "pixels between the depth samples of the degeneracy check");
    F2C_FIELD(v, photometric, "--icp-photometric,!--no-icp-photometric", {},
              "where the depth leaves motions free, measure them by photometric alignment");
    F2C_FIELD(
        v, prior_sigma, "--icp-prior-sigma", Positive(),
        "the motion prior's error per pair (m; rotations at the mean depth), the scale of an ICP pair's information");
    F2C_FIELD(
        v, prior_sigma_growth, "--icp-prior-sigma-growth", AtLeast(0),
        "the motion prior's error grows by this many --icp-prior-sigma per pair in a row before it left to the prior");
    F2C_FIELD(v, min_gradient, "--icp-min-gradient", Positive(),
              "grey-level gradient (per pixel) at which a sample's intensity constrains the motion");
    F2C_NESTED(v, dense);
  }
  void Check() const;
};

// Estimates target_from_source. Returns false (and leaves *target_from_source alone) when
// ICP fails or its answer moves more than the limits.
bool AlignDepthIcp(const cv::Mat& source_depth, const cv::Mat& target_depth, const CameraIntrinsics& intrinsics,
                   const Rigid3d& initial_target_from_source, const IcpOptions& options, Rigid3d* target_from_source);

// The motions a depth image constrains under point-to-plane alignment. With the
// reference's points p_i and normals n_i (sampled every `stride` pixels) and L their mean
// depth, moving the reference_from_frame transform on the left by (w, v) changes residual i by
// J_i (w L, v), J_i = [(p_i x n_i) / L, n_i]. H = sum J_i^T J_i / N; its eigenvectors with
// eigenvalue >= threshold are the constrained directions (in (w L, v) units).
struct DepthConstraints {
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();       // H
  Eigen::Matrix<double, 6, 1> eigenvalues = Eigen::Matrix<double, 6, 1>::Zero();       // ascending
  Eigen::Matrix<double, 6, 6> eigenvectors = Eigen::Matrix<double, 6, 6>::Identity();  // columns
  double mean_depth = 1.0;                                                             // L
  int samples = 0;
  int Degenerate(double threshold) const;  // eigenvalues below threshold (diagnostics)
  // The information H' = P H P along the span of `directions` (orthonormal columns, P their
  // projector) and none across it.
  DepthConstraints Along(const Eigen::Matrix<double, 6, Eigen::Dynamic>& directions) const;
};
DepthConstraints AnalyseDepthConstraints(const cv::Mat& depth, const CameraIntrinsics& intrinsics, int stride);

// What the grey image adds, at the same samples and in the same units (H sums over the
// depth's N): each sample whose gradient direction g (unit, in the image) has magnitude >=
// min_gradient (grey levels per pixel, after a Gaussian blur of 1 px) gives the row [(p_i x
// a_i) / L, a_i], a_i = (g_x, g_y, -(g_x x_i + g_y y_i) / z_i): a_i . dp is the sideways
// displacement along g (metres at the point's depth) that moving the point by dp makes its
// projection show, the one motion intensity measures there. Unit-weighted like the depth rows,
// a wall textured all over constrains its slides and its turn about the normal about as
// strongly as its depth constrains its distance.
struct ViewConstraints {
  DepthConstraints depth, image;
};
ViewConstraints AnalyseViewConstraints(const cv::Mat& depth, const cv::Mat& gray, const CameraIntrinsics& intrinsics,
                                       int stride, double min_gradient);

// `icp` (reference_from_frame) fused with `prior`: the left difference icp * prior^-1, in
// (w L, v) units, keeps lambda_i / (lambda_i + prior_information) of its component along each
// eigenvector i of `constraints`, and is applied to prior. Where the geometry is silent
// (lambda 0) the prior stands; where it constrains (lambda >> prior_information), ICP. (The
// same fusion keeps the photometric step where the image constrains it: odometry.cc.)
Rigid3d ConstrainToGeometry(const Rigid3d& icp, const Rigid3d& prior, const DepthConstraints& constraints,
                            double prior_information);

// The directions of motion the photometric step refines (photometric.h): each eigenvector e_i
// of the depth's information whose eigenvalue lambda_i is below prior_information (the depth
// leaves it to the prior), or on which the image adds more than the depth and the prior give,
// every other direction free: 1 / (e_i^T (H_depth + p I + H_image)^-1 e_i) > 2 (lambda_i + p).
// That takes a wall's slide that one door jamb's edge barely constrains (ICP's error there
// stays near the prior's), and leaves a textured wall's tilts, which its image sees only
// together with its slides. Orthonormal columns, weakest first.
Eigen::Matrix<double, 6, Eigen::Dynamic> PhotometricDirections(const ViewConstraints& view, double prior_information);

// The photometric answer `refined`, which differs from `fused` only along the columns B of
// `directions`, fused with `fused` as two estimates there: with s the left difference
// refined * fused^-1 in B's coordinates ((w L, v) units), `fused` measured by A_f = B^T
// (H_depth + prior_information I) B and `refined` by A_i = B^T H_image B, the result is
// exp(B (A_f + A_i)^-1 A_i s) fused. Where the depth is silent (H_depth 0 along B) this is
// ConstrainToGeometry with the image's information. *degenerate (optional): the eigenvalues
// of B^T (H_depth + H_image) B below prior_information, the directions neither measures.
Rigid3d FusePhotometric(const Rigid3d& refined, const Rigid3d& fused, const ViewConstraints& view,
                        const Eigen::Matrix<double, 6, Eigen::Dynamic>& directions, double prior_information,
                        int* degenerate = nullptr);

// How precisely an ICP fallback's fused answer is known (PairAlignment::information): the
// information it was fused under, the depth's H plus the image's along `directions` (the
// columns the photometric step refined; none where it did not run) plus the motion prior's
// prior_information I, all in (w L, v) units and per sample (ConstrainToGeometry,
// FusePhotometric). Its scale is set by the prior: prior_information stands for a motion
// prior uncertain by prior_sigma (metres, rotations at the mean depth L), so the result is
// D (H + prior_information I) D / (prior_information prior_sigma^2), D = diag(L, L, L, 1, 1,
// 1), in (w radians, v metres). A direction the depth measures with eigenvalue lambda is
// known lambda / prior_information times better than the prior, as the fusion weighed it.
// The prior of this pair may be worse than prior_sigma, by prior_widening (>= 1), where it
// was taken from answers that themselves repeated an older prior (a run of ICP fallbacks on a
// plain wall: the velocity along the wall stays what it was when the run began, and its
// error grows with the run); the prior's own term is then I / (prior_widening prior_sigma)^2,
// H's stays H / (prior_information prior_sigma^2).
Eigen::Matrix<double, 6, 6> MeasuredInformation(const ViewConstraints& view,
                                                const Eigen::Matrix<double, 6, Eigen::Dynamic>& directions,
                                                double prior_information, double prior_sigma,
                                                double prior_widening = 1);

struct DepthOverlap {
  double fitness = 0;  // fraction of valid source samples within `threshold` of the target's surface
  double rmse = 0;     // metres, over those
  int samples = 0;     // valid source samples that project inside the target image
};

// Projects every `stride`-th valid source pixel into the target with target_from_source and
// compares depths along the target ray.
DepthOverlap MeasureDepthOverlap(const cv::Mat& source_depth, const cv::Mat& target_depth,
                                 const CameraIntrinsics& intrinsics, const Rigid3d& target_from_source,
                                 double threshold = 0.05, int stride = 4);

}  // namespace f2c
