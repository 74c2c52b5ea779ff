#include "f2c/matching/sift.h"

#include <fmt/format.h>

#include <algorithm>
#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "f2c/util/error.h"

namespace f2c {

void SiftOptions::Check() const {
  CheckFields(*this);
  if (!(max_depth > min_depth)) {
    ThrowInputError("--max-depth", fmt::format("must be greater than --min-depth ({}), got {}", min_depth, max_depth));
  }
}

SiftFeatures ExtractSiftWithDepth(const cv::Mat& gray, const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                                  const SiftOptions& options) {
  F2C_CHECK(gray.type() == CV_8UC1 && depth.type() == CV_32FC1 && gray.size() == depth.size(),
            "gray 8UC1 and depth 32FC1 of one size");
  auto sift = cv::SIFT::create(options.max_features, options.octave_layers, options.contrast_threshold,
                               options.edge_threshold, options.sigma);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  if (options.downscale > 1) {
    cv::Mat small;
    cv::resize(gray, small, cv::Size(), 1.0 / options.downscale, 1.0 / options.downscale, cv::INTER_AREA);
    sift->detectAndCompute(small, cv::noArray(), keypoints, descriptors);
    // Pixel centres: x_full = (x_small + 0.5) * s - 0.5.
    for (cv::KeyPoint& kp : keypoints) {
      kp.pt = (kp.pt + cv::Point2f(0.5f, 0.5f)) * static_cast<float>(options.downscale) - cv::Point2f(0.5f, 0.5f);
    }
  } else {
    sift->detectAndCompute(gray, cv::noArray(), keypoints, descriptors);
  }

  SiftFeatures features;
  features.detected = static_cast<int>(keypoints.size());
  std::vector<int> kept;
  for (int i = 0; i < static_cast<int>(keypoints.size()); ++i) {
    float z = 0;
    if (!KeypointDepth(depth, keypoints[i].pt, options, &z)) continue;
    features.points_in_camera.push_back(intrinsics.Unproject(keypoints[i].pt.x, keypoints[i].pt.y, z));
    features.pixels.push_back(keypoints[i].pt);
    kept.push_back(i);
  }
  features.descriptors.create(static_cast<int>(kept.size()), descriptors.cols, CV_32F);
  for (size_t r = 0; r < kept.size(); ++r)
    descriptors.row(kept[r]).copyTo(features.descriptors.row(static_cast<int>(r)));
  return features;
}

bool KeypointDepth(const cv::Mat& depth, const cv::Point2f& pixel, const SiftOptions& options, float* z) {
  const int u = static_cast<int>(std::lround(pixel.x));
  const int v = static_cast<int>(std::lround(pixel.y));
  if (u < 1 || v < 1 || u >= depth.cols - 1 || v >= depth.rows - 1) return false;
  const float centre = depth.at<float>(v, u);
  if (!(centre >= options.min_depth && centre <= options.max_depth)) return false;
  float lo = centre, hi = centre;
  for (int dv = -1; dv <= 1; ++dv) {
    for (int du = -1; du <= 1; ++du) {
      const float d = depth.at<float>(v + dv, u + du);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
  }
  if (lo <= 0 || hi - lo > options.max_depth_spread * centre) return false;
  *z = centre;
  return true;
}

namespace {

// Both nearest train descriptors of each query descriptor (squared distances, best first).
// |q - t|^2 = |q|^2 + |t|^2 - 2 q.t, the dot products a block of queries at a time from one
// matrix product: Eigen's blocked, vectorised GEMM makes matching about twice as fast as
// OpenCV's BFMatcher, which computes each distance on its own. Ties keep the
// lower train index, as BFMatcher does.
struct TwoNearest {
  int index = -1;
  float first = std::numeric_limits<float>::infinity();
  float second = std::numeric_limits<float>::infinity();
};
std::vector<TwoNearest> NearestTwo(const cv::Mat& query, const cv::Mat& train) {
  using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  F2C_CHECK(query.type() == CV_32F && train.type() == CV_32F && query.cols == train.cols,
            "SIFT descriptors: float rows of one length");
  const cv::Mat qc = query.isContinuous() ? query : query.clone();
  const cv::Mat tc = train.isContinuous() ? train : train.clone();
  const Eigen::Map<const RowMatrix> q(qc.ptr<float>(), qc.rows, qc.cols);
  const Eigen::Map<const RowMatrix> t(tc.ptr<float>(), tc.rows, tc.cols);
  const Eigen::VectorXf train_norms = t.rowwise().squaredNorm();
  std::vector<TwoNearest> out(q.rows());
  constexpr int kBlock = 128;  // queries per product: 128 x train floats stay in cache
  RowMatrix dots;
  for (int r0 = 0; r0 < q.rows(); r0 += kBlock) {
    const int rows = std::min<int>(kBlock, q.rows() - r0);
    dots.noalias() = q.middleRows(r0, rows) * t.transpose();
    for (int i = 0; i < rows; ++i) {
      const float query_norm = q.row(r0 + i).squaredNorm();
      TwoNearest& best = out[r0 + i];
      for (int j = 0; j < t.rows(); ++j) {
        const float d = std::max(0.0f, query_norm + train_norms[j] - 2 * dots(i, j));
        if (d < best.first) {
          best.second = best.first;
          best.first = d;
          best.index = j;
        } else if (d < best.second) {
          best.second = d;
        }
      }
    }
  }
  return out;
}

}  // namespace

std::vector<SiftMatch> MatchSiftRatio(const SiftFeatures& query, const SiftFeatures& train, double ratio,
                                      double relaxed_ratio, int relax_below_matches) {
  std::vector<SiftMatch> matches;
  if (query.size() < 2 || train.size() < 2) return matches;
  const std::vector<TwoNearest> nearest = NearestTwo(query.descriptors, train.descriptors);
  auto collect = [&](double r) {
    matches.clear();
    for (size_t i = 0; i < nearest.size(); ++i) {
      const TwoNearest& n = nearest[i];
      if (std::sqrt(n.first) < r * std::sqrt(n.second)) matches.push_back({static_cast<int>(i), n.index});
    }
  };
  collect(ratio);
  if (static_cast<int>(matches.size()) < relax_below_matches) collect(relaxed_ratio);
  return matches;
}

}  // namespace f2c
