#include "f2c/features/point_grid.h"

#include <cmath>
#include <optional>
#include <string>

#include "f2c/util/error.h"

namespace f2c {

void PointGridOptions::Check() const {
  CheckFields(*this);
  if (!(max_depth > min_depth)) {
    ThrowInputError("--feature-max-depth", fmt::format("must exceed min_depth ({}), got {}", min_depth, max_depth));
  }
}

int PointGrid::ValidCount() const {
  int n = 0;
  for (size_t i = 0; i < points.size(); ++i) n += Valid(static_cast<int>(i));
  return n;
}

namespace {

float ValidDepth(float z, const PointGridOptions& o) {
  return std::isfinite(z) && z >= o.min_depth && z <= o.max_depth ? z : 0.0f;
}

// The bilateral filter evaluated only at the pixels the grid samples, over every second
// neighbour in each direction (a 2x subsampled kernel: still ~50 samples at the default
// sigma): the grid never looks at the other pixels, and a full-image bilateral filter cost
// ~90 ms per VGA frame (17 ms with the full kernel at the samples). Missing depth gets no
// weight; the range weight comes from a table (an exp per neighbour would dominate).
class SampledBilateral {
 public:
  SampledBilateral(const cv::Mat& depth, const PointGridOptions& o)
      : depth_(depth), o_(o), radius_(static_cast<int>(std::ceil(2 * o.bilateral_sigma_pixels))) {
    const int side = 2 * radius_ + 1;
    spatial_.resize(side * side);
    for (int dv = -radius_; dv <= radius_; ++dv) {
      for (int du = -radius_; du <= radius_; ++du) {
        spatial_[(dv + radius_) * side + du + radius_] = static_cast<float>(
            std::exp(-(du * du + dv * dv) / (2 * o.bilateral_sigma_pixels * o.bilateral_sigma_pixels)));
      }
    }
    range_.resize(kRangeBins + 1);
    for (int i = 0; i <= kRangeBins; ++i) {
      const double x = kRangeSigmas * i / kRangeBins;  // |dz| / sigma
      range_[i] = i == kRangeBins ? 0.0f : static_cast<float>(std::exp(-0.5 * x * x));
    }
  }

  float At(int u, int v) const {
    const float z0 = ValidDepth(depth_.at<float>(v, u), o_);
    if (z0 == 0) return 0;
    const int side = 2 * radius_ + 1;
    const float to_bin = static_cast<float>(kRangeBins / (kRangeSigmas * o_.bilateral_sigma_depth));
    float sum = 0, weight = 0;
    for (int vv = v - radius_; vv <= v + radius_; vv += 2) {
      if (vv < 0 || vv >= depth_.rows) continue;
      const float* row = depth_.ptr<float>(vv);
      // The kernel row of this vv, indexed by uu - u + radius_ (a pointer offset by -u would
      // point outside the kernel: undefined behaviour, UBSan's pointer-overflow check).
      const float* spatial = &spatial_[(vv - v + radius_) * side];
      for (int uu = u - radius_; uu <= u + radius_; uu += 2) {
        if (uu < 0 || uu >= depth_.cols) continue;
        const float z = ValidDepth(row[uu], o_);
        if (z == 0) continue;
        const int bin = std::min(kRangeBins, static_cast<int>(std::abs(z - z0) * to_bin));
        const float w = spatial[uu - u + radius_] * range_[bin];
        sum += w * z;
        weight += w;
      }
    }
    return sum / weight;  // weight >= 1: the centre pixel itself
  }

 private:
  static constexpr int kRangeBins = 256;
  static constexpr double kRangeSigmas = 4.0;  // beyond 4 sigma the range weight is 0
  const cv::Mat& depth_;
  const PointGridOptions& o_;
  int radius_;
  std::vector<float> spatial_, range_;
};

// The eigenvector of a 3x3 covariance's smallest eigenvalue, without an eigen-solver (which
// took a third of the feature time: trigonometric closed form or iterations per cell). The
// adjugate of C = sum lambda_k v_k v_k^T is sum_k (product of the other two lambdas) v_k
// v_k^T, dominated by lambda_1 lambda_2 v_0 v_0^T when lambda_0 is small, and exactly that
// on a perfect plane (singular C): its largest column is the normal, and one multiplication
// by the adjugate (a power-iteration step on C^-1) sharpens it. Also the curvature
// lambda_0 / trace (Rayleigh quotient). False when the points are collinear
// (lambda_1 << lambda_2): no plane.
bool SmallestEigenvector(const Eigen::Matrix3d& c, Eigen::Vector3d* normal, double* curvature) {
  Eigen::Matrix3d adj;
  adj(0, 0) = c(1, 1) * c(2, 2) - c(1, 2) * c(1, 2);
  adj(0, 1) = c(0, 2) * c(1, 2) - c(0, 1) * c(2, 2);
  adj(0, 2) = c(0, 1) * c(1, 2) - c(0, 2) * c(1, 1);
  adj(1, 1) = c(0, 0) * c(2, 2) - c(0, 2) * c(0, 2);
  adj(1, 2) = c(0, 1) * c(0, 2) - c(0, 0) * c(1, 2);
  adj(2, 2) = c(0, 0) * c(1, 1) - c(0, 1) * c(0, 1);
  adj(1, 0) = adj(0, 1), adj(2, 0) = adj(0, 2), adj(2, 1) = adj(1, 2);
  const double trace = c.trace();
  int k = 0;
  const double largest = adj.colwise().squaredNorm().maxCoeff(&k);
  // ||adj|| ~ lambda_1 lambda_2 and trace ~ lambda_2: collinear when lambda_1 < 1e-3 lambda_2.
  if (!(trace > 0) || !(std::sqrt(largest) > 1e-3 * trace * trace)) return false;
  Eigen::Vector3d x = adj.col(k).normalized();
  x = (adj * x).normalized();
  *normal = x;
  *curvature = std::max(0.0, x.dot(c * x)) / trace;
  return true;
}

}  // namespace

PointGrid BuildPointGrid(const cv::Mat& depth, const CameraIntrinsics& k, const PointGridOptions& o) {
  F2C_CHECK(depth.type() == CV_32F, "depth is CV_32F metres");
  std::optional<SampledBilateral> bilateral;
  if (o.bilateral) bilateral.emplace(depth, o);
  PointGrid g;
  g.step = o.step;
  g.width = depth.cols / o.step;
  g.height = depth.rows / o.step;
  const int n = g.width * g.height;
  g.points.assign(n, Eigen::Vector3f::Zero());
  g.normals.assign(n, Eigen::Vector3f::Zero());
  g.curvature.assign(n, 0.0f);
  g.residual.assign(n, 0.0f);
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const int u = g.PixelU(x), v = g.PixelV(y);
      const float z = bilateral ? bilateral->At(u, v) : ValidDepth(depth.at<float>(v, u), o);
      if (z > 0) g.points[g.Index(x, y)] = k.Unproject(u, v, z).cast<float>();
    }
  }

  // Normals: covariance of the neighbours, smallest eigenvector. Centred on the cell's own
  // point (not the neighbours' mean) while accumulating, for numerical stability in float.
  // The points are read from planar copies (x, y, z apart) and the covariance accumulated in
  // its six distinct entries: this loop is most of the grid's cost.
  const int r = std::max(1, o.normal_radius_pixels / o.step);
  const float r2 = static_cast<float>(o.normal_radius * o.normal_radius);
  std::vector<float> px(n), py(n), pz(n);
  for (int i = 0; i < n; ++i) px[i] = g.points[i].x(), py[i] = g.points[i].y(), pz[i] = g.points[i].z();
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const int i = g.Index(x, y);
      if (!(pz[i] > 0)) continue;
      const float cx = px[i], cy = py[i], cz = pz[i];
      float sx = 0, sy = 0, sz = 0, sxx = 0, sxy = 0, sxz = 0, syy = 0, syz = 0, szz = 0;
      int count = 0;
      const int x0 = std::max(0, x - r), x1 = std::min(g.width - 1, x + r);
      for (int yy = std::max(0, y - r); yy <= std::min(g.height - 1, y + r); ++yy) {
        for (int j = g.Index(x0, yy), end = g.Index(x1, yy); j <= end; ++j) {
          // Without branches (whether a neighbour counts is unpredictable): a neighbour that
          // does not count adds exact zeros, which leaves every sum as it was.
          const float dx = px[j] - cx, dy = py[j] - cy, dz = pz[j] - cz;
          const bool in = pz[j] > 0 && dx * dx + dy * dy + dz * dz <= r2;
          const float w = in ? 1.0f : 0.0f;
          const float wx = w * dx, wy = w * dy, wz = w * dz;
          sx += wx, sy += wy, sz += wz;
          sxx += wx * dx, sxy += wx * dy, sxz += wx * dz;
          syy += wy * dy, syz += wy * dz, szz += wz * dz;
          count += in;
        }
      }
      if (count < o.min_normal_points) continue;
      const Eigen::Vector3f sum(sx, sy, sz);
      Eigen::Matrix3f sum2;
      sum2 << sxx, sxy, sxz, sxy, syy, syz, sxz, syz, szz;
      const Eigen::Vector3d mean = (sum / count).cast<double>();
      const Eigen::Matrix3d cov = (sum2 / count).cast<double>() - mean * mean.transpose();
      double curvature = 0;
      Eigen::Vector3d normal;
      if (!SmallestEigenvector(cov, &normal, &curvature)) continue;
      if (normal.dot(g.points[i].cast<double>()) > 0) normal = -normal;  // towards the camera
      g.normals[i] = normal.cast<float>();
      g.curvature[i] = static_cast<float>(curvature);
      g.residual[i] = static_cast<float>(std::sqrt(curvature * cov.trace()));
    }
  }
  return g;
}

}  // namespace f2c
