#include "f2c/odometry/photometric.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "f2c/util/error.h"

namespace f2c {

void PhotometricOptions::Check() const {
  CheckFields(*this);
  if (blur_sigmas.empty() || blur_sigmas.size() != strides.size()) {
    ThrowInputError("blur_sigmas", fmt::format("needs one value per level, as strides ({}), got {}", strides.size(),
                                               blur_sigmas.size()));
  }
  for (double s : blur_sigmas) {
    if (!(s >= 0)) ThrowInputError("blur_sigmas", fmt::format("must be >= 0, got {}", s));
  }
  for (int s : strides) {
    if (s < 1) ThrowInputError("strides", fmt::format("must be >= 1, got {}", s));
  }
}

namespace {

// One level: a blurred image and its gradient (grey levels per pixel), all CV_32F.
struct Level {
  cv::Mat image, dx, dy;
};

// The gradient only where it is sampled: the frame's image, not the reference's.
Level MakeLevel(const cv::Mat& gray, double sigma, bool gradient) {
  Level l;
  gray.convertTo(l.image, CV_32F);
  if (sigma > 0) cv::GaussianBlur(l.image, l.image, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);
  if (!gradient) return l;
  // Central differences: (I(u + 1) - I(u - 1)) / 2.
  const cv::Mat kx = (cv::Mat_<float>(1, 3) << -0.5f, 0.0f, 0.5f);
  cv::filter2D(l.image, l.dx, CV_32F, kx, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
  cv::filter2D(l.image, l.dy, CV_32F, kx.t(), cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
  return l;
}

// Bilinear sample at (x, y); false outside the image's interior.
bool Sample(const cv::Mat& m, double x, double y, double* value) {
  if (!(x >= 0 && y >= 0 && x < m.cols - 1 && y < m.rows - 1)) return false;
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const float* r0 = m.ptr<float>(y0);
  const float* r1 = m.ptr<float>(y0 + 1);
  *value = (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  return true;
}

struct Point {
  Eigen::Vector3d p;  // reference frame
  double intensity;   // I_r(u) at this level
};

// Gauss-Newton normal equations of E at T (unknowns s and b), and the error's RMS.
struct Normal {
  Eigen::MatrixXd h;
  Eigen::VectorXd g;
  double sum_sq = 0;
  int n = 0;
};

Normal Accumulate(const std::vector<Point>& points, const Level& frame, const CameraIntrinsics& k,
                  const Eigen::Matrix<double, 6, Eigen::Dynamic>& b_dirs, double lever, double bias, double huber,
                  const Rigid3d& t) {
  const int m = static_cast<int>(b_dirs.cols());
  Normal out;
  out.h = Eigen::MatrixXd::Zero(m + 1, m + 1);
  out.g = Eigen::VectorXd::Zero(m + 1);
  const Eigen::Matrix3d rt = t.linear().transpose();
  const Eigen::Vector3d tt = t.translation();
  Eigen::VectorXd j(m + 1);
  for (const Point& pt : points) {
    const Eigen::Vector3d q = rt * (pt.p - tt);
    if (q.z() <= 0) continue;
    const double x = k.fx * q.x() / q.z() + k.cx, y = k.fy * q.y() / q.z() + k.cy;
    double value, gx, gy;
    if (!Sample(frame.image, x, y, &value) || !Sample(frame.dx, x, y, &gx) || !Sample(frame.dy, x, y, &gy)) continue;
    const double r = value - pt.intensity - bias;
    // grad^T J_pi, then through dq/d(w, v) = R^T [[p]_x, -I].
    const Eigen::Vector3d gp(gx * k.fx / q.z(), gy * k.fy / q.z(),
                             -(gx * k.fx * q.x() + gy * k.fy * q.y()) / (q.z() * q.z()));
    const Eigen::Vector3d a = t.linear() * gp;  // (R^T)^T gp
    Eigen::Matrix<double, 6, 1> full;
    full.head<3>() = a.cross(pt.p) / lever;  // a . (p x w) = (a x p) . w, per unit of w L
    full.tail<3>() = -a;
    j.head(m) = b_dirs.transpose() * full;
    j(m) = -1.0;
    const double w = std::abs(r) <= huber ? 1.0 : huber / std::abs(r);
    out.h.noalias() += w * j * j.transpose();
    out.g.noalias() += w * r * j;
    out.sum_sq += r * r;
    ++out.n;
  }
  return out;
}

}  // namespace

Rigid3d ExpScaled(const Eigen::Matrix<double, 6, 1>& scaled, double lever) {
  const Eigen::Vector3d w = scaled.head<3>() / lever;
  Rigid3d t = Rigid3d::Identity();
  if (w.norm() > 0) t.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  t.translation() = scaled.tail<3>();
  return t;
}

PhotometricResult AlignPhotometric(const cv::Mat& reference_gray, const cv::Mat& reference_depth,
                                   const cv::Mat& frame_gray, const CameraIntrinsics& k,
                                   const Eigen::Matrix<double, 6, Eigen::Dynamic>& directions, double lever,
                                   const PhotometricOptions& options, Rigid3d* reference_from_frame) {
  CV_Assert(reference_gray.type() == CV_8UC1 && frame_gray.type() == CV_8UC1 && reference_depth.type() == CV_32F);
  CV_Assert(reference_gray.size() == reference_depth.size() && frame_gray.size() == reference_depth.size());
  PhotometricResult result;
  const int m = static_cast<int>(directions.cols());
  if (m == 0 || !(lever > 0)) return result;
  Rigid3d t = *reference_from_frame;
  double bias = 0;
  const int levels = static_cast<int>(options.blur_sigmas.size());
  // The reference's pixels with depth, every `stride`, with their intensity at this blur.
  auto points_of = [&](const Level& ref, int stride) {
    std::vector<Point> points;
    for (int v = 0; v < reference_depth.rows; v += stride) {
      const float* z = reference_depth.ptr<float>(v);
      const float* in = ref.image.ptr<float>(v);
      for (int u = 0; u < reference_depth.cols; u += stride) {
        if (z[u] > 0) points.push_back({k.Unproject(u, v, z[u]), in[u]});
      }
    }
    return points;
  };
  auto rmse = [](const Normal& n) { return n.n > 0 ? std::sqrt(n.sum_sq / n.n) : 0.0; };
  for (int level = 0; level < levels; ++level) {
    const Level ref = MakeLevel(reference_gray, options.blur_sigmas[level], false);
    const Level frame = MakeLevel(frame_gray, options.blur_sigmas[level], true);
    const std::vector<Point> points = points_of(ref, options.strides[level]);
    const bool finest = level + 1 == levels;
    if (finest) {
      // The error the finest level starts from, at the caller's transform (brightness matched).
      Normal start = Accumulate(points, frame, k, directions, lever, 0.0, options.huber, *reference_from_frame);
      if (start.n > 0) start.sum_sq -= start.g(m) * start.g(m) / start.n;  // the best offset's share (unweighted)
      result.rmse_before = rmse(start);
    }
    Normal normal = Accumulate(points, frame, k, directions, lever, bias, options.huber, t);
    for (int it = 0; it < options.iterations && normal.n > m; ++it) {
      const Eigen::VectorXd step = normal.h.ldlt().solve(-normal.g);
      if (!step.allFinite()) break;
      const Rigid3d next = ExpScaled(directions * step.head(m), lever) * t;
      const Normal after = Accumulate(points, frame, k, directions, lever, bias + step(m), options.huber, next);
      if (after.n <= m || after.sum_sq / after.n > normal.sum_sq / normal.n) break;  // no longer descending
      t = next;
      bias += step(m);
      normal = after;
      if (step.head(m).norm() < 1e-7) break;
    }
    if (finest) {
      result.samples = normal.n;
      result.rmse_after = rmse(normal);
    }
  }
  if (result.samples == 0 || result.rmse_after > result.rmse_before) return result;
  t.linear() = Eigen::Quaterniond(t.linear()).normalized().toRotationMatrix();
  *reference_from_frame = t;
  result.ok = true;
  return result;
}

}  // namespace f2c
