#include "f2c/odometry/depth_alignment.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <opencv2/rgbd.hpp>

#include "f2c/util/error.h"

namespace f2c {

void IcpOptions::Check() const {
  CheckFields(*this);
  if (!(max_depth > min_depth))
    ThrowInputError("max_depth", fmt::format("must exceed min_depth ({}), got {}", min_depth, max_depth));
  if (iterations.empty()) ThrowInputError("iterations", "needs at least one pyramid level");
  for (int n : iterations) {
    if (n < 1) ThrowInputError("iterations", fmt::format("must be >= 1 per level, got {}", n));
  }
}

bool AlignDepthIcp(const cv::Mat& full_source_depth, const cv::Mat& full_target_depth, const CameraIntrinsics& full_k,
                   const Rigid3d& initial_target_from_source, const IcpOptions& options, Rigid3d* target_from_source) {
  cv::Mat source_depth = full_source_depth, target_depth = full_target_depth;
  CameraIntrinsics k = full_k;
  if (options.downscale > 1) {
    // Every n-th pixel (no averaging across depth edges): OpenCV's nearest neighbour takes source
    // pixel n u for pixel u, so u = (fx / n) X / Z + cx / n.
    const double n = options.downscale;
    const cv::Size size(full_source_depth.cols / options.downscale, full_source_depth.rows / options.downscale);
    cv::resize(full_source_depth, source_depth, size, 0, 0, cv::INTER_NEAREST);
    cv::resize(full_target_depth, target_depth, size, 0, 0, cv::INTER_NEAREST);
    k.fx = full_k.fx / n;
    k.fy = full_k.fy / n;
    k.cx = full_k.cx / n;
    k.cy = full_k.cy / n;
  }
  const cv::Mat camera = (cv::Mat_<float>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  // One ICPOdometry per thread, kept between calls: it keeps its normal estimator, whose
  // set-up for an image size and camera (per-pixel tables) cost as much as the alignment.
  thread_local cv::rgbd::ICPOdometry icp;
  icp.setCameraMatrix(camera);
  icp.setMinDepth(options.min_depth);
  icp.setMaxDepth(options.max_depth);
  icp.setMaxDepthDiff(options.max_depth_difference);
  icp.setMaxPointsPart(options.max_points_part);
  icp.setIterationCounts(cv::Mat(options.iterations, true));
  icp.setMaxTranslation(options.max_translation);
  icp.setMaxRotation(options.max_rotation_deg);
  cv::Mat init(4, 4, CV_64F);
  const Eigen::Matrix4d m0 = initial_target_from_source.matrix();
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) init.at<double>(r, c) = m0(r, c);
  }
  cv::Mat rt;
  bool ok = false;
  try {
    // OpenCV: dst_p = Rt * src_p, i.e. Rt is target_from_source.
    ok = icp.compute(cv::Mat(), source_depth, cv::Mat(), cv::Mat(), target_depth, cv::Mat(), rt, init);
  } catch (const cv::Exception&) {
    ok = false;  // too few valid pixels for a pyramid level, etc.
  }
  if (!ok || rt.empty()) return false;
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) m(r, c) = rt.at<double>(r, c);
  }
  if (!m.allFinite()) return false;
  target_from_source->matrix() = m;
  return true;
}

int DepthConstraints::Degenerate(double threshold) const {
  int n = 0;
  for (int i = 0; i < 6; ++i) n += eigenvalues(i) < threshold;
  return n;
}

DepthConstraints FromInformation(const Eigen::Matrix<double, 6, 6>& information, double mean_depth, int samples) {
  DepthConstraints out;
  out.information = information;
  out.mean_depth = mean_depth;
  out.samples = samples;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen(information);
  out.eigenvalues = eigen.eigenvalues();
  out.eigenvectors = eigen.eigenvectors();
  return out;
}

DepthConstraints DepthConstraints::Along(const Eigen::Matrix<double, 6, Eigen::Dynamic>& directions) const {
  const Eigen::Matrix<double, 6, 6> p = directions * directions.transpose();
  return FromInformation(p * information * p, mean_depth, samples);
}

DepthConstraints AnalyseDepthConstraints(const cv::Mat& depth, const CameraIntrinsics& k, int stride) {
  return AnalyseViewConstraints(depth, cv::Mat(), k, stride, 0.0).depth;
}

ViewConstraints AnalyseViewConstraints(const cv::Mat& depth, const cv::Mat& gray, const CameraIntrinsics& k, int stride,
                                       double min_gradient) {
  ViewConstraints out;
  // Normals from the depth averaged over (2 stride + 1)^2 pixels (invalid pixels left out):
  // raw depth noise (1-2 cm at 3 m) over a few pixels would tilt them by tens of degrees and
  // invent constraints a plain wall does not give.
  const int h = std::max(stride, 2);
  cv::Mat valid, sum, count;
  cv::threshold(depth, valid, 0.0, 1.0, cv::THRESH_BINARY);
  const cv::Size box(2 * h + 1, 2 * h + 1);
  cv::boxFilter(depth, sum, CV_32F, box, cv::Point(-1, -1), true, cv::BORDER_CONSTANT);
  cv::boxFilter(valid, count, CV_32F, box, cv::Point(-1, -1), true, cv::BORDER_CONSTANT);
  auto point = [&](int u, int v, Eigen::Vector3d* p) {
    const float c = count.at<float>(v, u);
    if (c < 0.9f) return false;  // near the border, a hole or a depth edge
    const float z = sum.at<float>(v, u) / c;
    const float raw = depth.at<float>(v, u);
    if (!(raw > 0) || std::abs(raw - z) > 0.05f * z) return false;
    *p = k.Unproject(u, v, z);
    return true;
  };
  CV_Assert(gray.empty() || (gray.type() == CV_8UC1 && gray.size() == depth.size()));
  cv::Mat smooth;
  if (!gray.empty()) cv::GaussianBlur(gray, smooth, cv::Size(7, 7), 1.0, 1.0, cv::BORDER_REPLICATE);
  // The unit gradient direction at (u, v), where the gradient is strong enough to measure.
  auto gradient = [&](int u, int v, Eigen::Vector2d* g) {
    if (smooth.empty() || u < 1 || v < 1 || u + 1 >= smooth.cols || v + 1 >= smooth.rows) return false;
    const auto at = [&](int x, int y) { return static_cast<double>(smooth.at<uint8_t>(y, x)); };
    *g = Eigen::Vector2d(at(u + 1, v) - at(u - 1, v), at(u, v + 1) - at(u, v - 1)) / 2.0;
    if (!(g->norm() >= min_gradient) || g->norm() <= 0) return false;
    g->normalize();
    return true;
  };
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> samples;   // point, normal
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> sideways;  // point, a_i (header)
  double depth_sum = 0;
  for (int v = h; v + h < depth.rows; v += stride) {
    for (int u = h; u + h < depth.cols; u += stride) {
      Eigen::Vector3d p, left, right, up, down;
      if (!point(u, v, &p) || !point(u - h, v, &left) || !point(u + h, v, &right) || !point(u, v - h, &up) ||
          !point(u, v + h, &down)) {
        continue;
      }
      Eigen::Vector3d n = (right - left).cross(down - up);
      if (n.norm() <= 0) continue;
      n.normalize();
      samples.push_back({p, n});
      depth_sum += p.z();
      Eigen::Vector2d g;
      if (gradient(u, v, &g)) sideways.push_back({p, {g.x(), g.y(), -(g.x() * p.x() + g.y() * p.y()) / p.z()}});
    }
  }
  if (samples.empty()) return out;
  const double mean_depth = depth_sum / samples.size();
  // H = sum J_i^T J_i / N over one kind of row.
  auto information = [&](const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& rows) {
    Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
    for (const auto& [p, n] : rows) {
      Eigen::Matrix<double, 6, 1> j;
      j << p.cross(n) / mean_depth, n;
      h += j * j.transpose();
    }
    return Eigen::Matrix<double, 6, 6>(h / static_cast<double>(samples.size()));
  };
  const int n = static_cast<int>(samples.size());
  out.depth = FromInformation(information(samples), mean_depth, n);
  out.image = FromInformation(information(sideways), mean_depth, n);
  return out;
}

namespace {

// The left difference a = exp(w, v) b in (w L, v) units: R_w = R_a R_b^T, v = t_a - R_w t_b.
Eigen::Matrix<double, 6, 1> LeftDifference(const Rigid3d& a, const Rigid3d& b, double lever) {
  const Eigen::Matrix3d r_w = a.linear() * b.linear().transpose();
  const Eigen::AngleAxisd w_axis(r_w);
  Eigen::Matrix<double, 6, 1> delta;
  delta << w_axis.angle() * w_axis.axis() * lever, a.translation() - r_w * b.translation();
  return delta;
}

}  // namespace

Eigen::Matrix<double, 6, Eigen::Dynamic> PhotometricDirections(const ViewConstraints& view, double prior_information) {
  const DepthConstraints& d = view.depth;
  // The information on e_i with the image added, every other direction free: 1 / (e_i^T (H_depth
  // + p I + H_image)^-1 e_i); without the image it is lambda_i + p (e_i is H_depth's).
  const Eigen::Matrix<double, 6, 6> both =
      d.information + prior_information * Eigen::Matrix<double, 6, 6>::Identity() + view.image.information;
  const Eigen::Matrix<double, 6, 6> covariance = both.ldlt().solve(Eigen::Matrix<double, 6, 6>::Identity());
  std::vector<int> chosen;
  for (int i = 0; i < 6; ++i) {
    const Eigen::Matrix<double, 6, 1> e = d.eigenvectors.col(i);
    const double depth = std::max(d.eigenvalues(i), 0.0) + prior_information;
    if (d.eigenvalues(i) < prior_information || 1.0 / e.dot(covariance * e) > 2.0 * depth) chosen.push_back(i);
  }
  Eigen::Matrix<double, 6, Eigen::Dynamic> out(6, static_cast<int>(chosen.size()));
  for (size_t j = 0; j < chosen.size(); ++j) out.col(static_cast<int>(j)) = d.eigenvectors.col(chosen[j]);
  return out;
}

Rigid3d FusePhotometric(const Rigid3d& refined, const Rigid3d& fused, const ViewConstraints& view,
                        const Eigen::Matrix<double, 6, Eigen::Dynamic>& b, double prior_information, int* degenerate) {
  const int m = static_cast<int>(b.cols());
  const Eigen::MatrixXd a_f =
      b.transpose() * (view.depth.information + prior_information * Eigen::Matrix<double, 6, 6>::Identity()) * b;
  const Eigen::MatrixXd a_i = b.transpose() * view.image.information * b;
  if (degenerate != nullptr) {
    const Eigen::MatrixXd both = b.transpose() * (view.depth.information + view.image.information) * b;
    const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(both).eigenvalues();
    *degenerate = 0;
    for (int i = 0; i < m; ++i) *degenerate += lambda(i) < prior_information;
  }
  if (m == 0) return fused;
  const double lever = view.depth.mean_depth;
  const Eigen::VectorXd s = b.transpose() * LeftDifference(refined, fused, lever);
  const Eigen::VectorXd kept = (a_f + a_i).ldlt().solve(a_i * s);
  return ExpScaled(b * kept, lever) * fused;
}

Rigid3d ConstrainToGeometry(const Rigid3d& icp, const Rigid3d& prior, const DepthConstraints& c,
                            double prior_information) {
  if (c.samples == 0 || !(prior_information > 0)) return icp;
  const Eigen::Matrix<double, 6, 1> delta = LeftDifference(icp, prior, c.mean_depth);
  Eigen::Matrix<double, 6, 1> kept = Eigen::Matrix<double, 6, 1>::Zero();
  for (int i = 0; i < 6; ++i) {
    const double share = std::max(c.eigenvalues(i), 0.0) / (std::max(c.eigenvalues(i), 0.0) + prior_information);
    kept += share * c.eigenvectors.col(i) * c.eigenvectors.col(i).dot(delta);
  }
  return ExpScaled(kept, c.mean_depth) * prior;
}

Eigen::Matrix<double, 6, 6> MeasuredInformation(const ViewConstraints& view,
                                                const Eigen::Matrix<double, 6, Eigen::Dynamic>& directions,
                                                double prior_information, double prior_sigma, double prior_widening) {
  using Matrix6d = Eigen::Matrix<double, 6, 6>;
  F2C_CHECK(prior_information > 0 && prior_sigma > 0 && prior_widening >= 1,
            "the prior's information and sigma are positive, its widening at least 1");
  // The measurements' part keeps the fusion's scale; the prior's own part is what it is worth.
  Matrix6d h = view.depth.information + prior_information / (prior_widening * prior_widening) * Matrix6d::Identity();
  if (directions.cols() > 0) {
    const Matrix6d along = directions * directions.transpose();
    h += along * view.image.information * along;
  }
  Eigen::Matrix<double, 6, 1> d;
  d << Eigen::Vector3d::Constant(view.depth.mean_depth), Eigen::Vector3d::Ones();
  const Matrix6d scaled = d.asDiagonal() * h * d.asDiagonal();
  return (0.5 * (scaled + scaled.transpose())) / (prior_information * prior_sigma * prior_sigma);
}

DepthOverlap MeasureDepthOverlap(const cv::Mat& source_depth, const cv::Mat& target_depth, const CameraIntrinsics& k,
                                 const Rigid3d& target_from_source, double threshold, int stride) {
  DepthOverlap overlap;
  int inside = 0, agree = 0;
  double sum = 0;
  const Eigen::Matrix3f r = target_from_source.linear().cast<float>();
  const Eigen::Vector3f t = target_from_source.translation().cast<float>();
  for (int v = 0; v < source_depth.rows; v += stride) {
    const float* row = source_depth.ptr<float>(v);
    for (int u = 0; u < source_depth.cols; u += stride) {
      const float z = row[u];
      if (!(z > 0)) continue;
      const Eigen::Vector3f p((u - k.cx) * z / k.fx, (v - k.cy) * z / k.fy, z);
      const Eigen::Vector3f q = r * p + t;
      if (q.z() <= 0) continue;
      const int tu = static_cast<int>(std::lround(k.fx * q.x() / q.z() + k.cx));
      const int tv = static_cast<int>(std::lround(k.fy * q.y() / q.z() + k.cy));
      if (tu < 0 || tv < 0 || tu >= target_depth.cols || tv >= target_depth.rows) continue;
      const float zt = target_depth.at<float>(tv, tu);
      if (!(zt > 0)) continue;
      ++inside;
      const double e = std::abs(zt - q.z());
      if (e < threshold) {
        ++agree;
        sum += e * e;
      }
    }
  }
  overlap.samples = inside;
  overlap.fitness = inside > 0 ? static_cast<double>(agree) / inside : 0.0;
  overlap.rmse = agree > 0 ? std::sqrt(sum / agree) : 0.0;
  return overlap;
}

}  // namespace f2c
