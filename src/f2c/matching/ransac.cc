#include "f2c/matching/ransac.h"

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "f2c/util/error.h"

namespace f2c {

void RansacOptions::Check() const {
  CheckFields(*this);
  if (!(depth_noise_a + depth_noise_b > 0)) ThrowInputError("depth_noise_a", "and depth_noise_b must not both be 0");
}

Rigid3d FitRigid(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                 const std::vector<int>& indices) {
  const int n = indices.empty() ? static_cast<int>(a.size()) : static_cast<int>(indices.size());
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (int i = 0; i < n; ++i) {
    const int k = indices.empty() ? i : indices[i];
    src.col(i) = a[k];
    dst.col(i) = b[k];
  }
  Rigid3d t = Rigid3d::Identity();
  t.matrix() = Eigen::umeyama(src, dst, false);
  return t;
}

Rigid3d FitRigidWeighted(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                         const std::vector<int>& indices, const std::vector<double>& weights) {
  F2C_CHECK(indices.size() == weights.size(), "one weight per point");
  double total = 0;
  Eigen::Vector3d mean_a = Eigen::Vector3d::Zero(), mean_b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < indices.size(); ++i) {
    total += weights[i];
    mean_a += weights[i] * a[indices[i]];
    mean_b += weights[i] * b[indices[i]];
  }
  mean_a /= total;
  mean_b /= total;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();  // sum w (b - mb)(a - ma)^T
  for (size_t i = 0; i < indices.size(); ++i) {
    cov += weights[i] * (b[indices[i]] - mean_b) * (a[indices[i]] - mean_a).transpose();
  }
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(cov, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0) d(2, 2) = -1;
  Rigid3d t = Rigid3d::Identity();
  t.linear() = svd.matrixU() * d * svd.matrixV().transpose();
  t.translation() = mean_b - t.linear() * mean_a;
  return t;
}

namespace {

// A sample defines a transform only if its points are spread (not nearly coincident or
// collinear) and rigid (pairwise distances agree on both sides, up to the noise allowed).
bool GoodSample(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, const int s[3],
                double threshold) {
  for (int i = 0; i < 3; ++i) {
    for (int j = i + 1; j < 3; ++j) {
      const double da = (a[s[i]] - a[s[j]]).norm(), db = (b[s[i]] - b[s[j]]).norm();
      if (da < 2 * threshold || std::abs(da - db) > 2 * threshold) return false;
    }
  }
  const double area = (a[s[1]] - a[s[0]]).cross(a[s[2]] - a[s[0]]).norm();
  return area > threshold * threshold;
}

std::vector<int> Inliers(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, const Rigid3d& t,
                         double threshold, double* rmse) {
  std::vector<int> inliers;
  double sum = 0;
  const double t2 = threshold * threshold;
  for (int i = 0; i < static_cast<int>(a.size()); ++i) {
    const double e2 = (t * a[i] - b[i]).squaredNorm();
    if (e2 < t2) {
      inliers.push_back(i);
      sum += e2;
    }
  }
  if (rmse) *rmse = inliers.empty() ? 0.0 : std::sqrt(sum / inliers.size());
  return inliers;
}

// A point's covariance in its camera: sigma_ray^2 along the ray, sigma_perp^2 across it.
Eigen::Matrix3d PointCovariance(const Eigen::Vector3d& p, const RansacOptions& o) {
  const double range = p.norm();
  const Eigen::Vector3d d = p / range;
  const double z = std::abs(p.z());
  const double sigma_z = o.depth_noise_a + o.depth_noise_b * z * z;
  const double sigma_ray = sigma_z / std::max(std::abs(d.z()), 0.1);  // depth noise, measured along z
  const double sigma_perp = o.bearing_sigma * range;
  return sigma_perp * sigma_perp * Eigen::Matrix3d::Identity() +
         (sigma_ray * sigma_ray - sigma_perp * sigma_perp) * d * d.transpose();
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// The ray-aware normal equations at t: with each residual R a + t - b under the left
// perturbation b ~ exp(w, v) t a = R_w (R a + t) + v, d(residual) = -[t a]_x w + v, weighted
// by (C_b + R C_a R^T)^-1 and, if `robust`, Cauchy weights at anisotropic_scale of that
// Mahalanobis distance.
void RayAwareNormalEquations(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                             const std::vector<int>& indices, const Rigid3d& t, const RansacOptions& o, bool robust,
                             Eigen::Matrix<double, 6, 6>* h, Eigen::Matrix<double, 6, 1>* g) {
  h->setZero();
  g->setZero();
  const double c2 = o.anisotropic_scale * o.anisotropic_scale;
  const Eigen::Matrix3d r = t.linear();
  for (const int k : indices) {
    const Eigen::Vector3d moved = t * a[k];
    const Eigen::Vector3d residual = moved - b[k];
    const Eigen::Matrix3d info = (PointCovariance(b[k], o) + r * PointCovariance(a[k], o) * r.transpose()).inverse();
    const double w = robust ? 1.0 / (1.0 + residual.dot(info * residual) / c2) : 1.0;
    Eigen::Matrix<double, 3, 6> j;
    j << -Skew(moved), Eigen::Matrix3d::Identity();
    *h += w * j.transpose() * info * j;
    *g += w * j.transpose() * info * residual;
  }
}

}  // namespace

Rigid3d RefineRigidAnisotropic(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                               const std::vector<int>& indices, const Rigid3d& initial, const RansacOptions& o) {
  Rigid3d t = initial;
  if (indices.size() < 3) return t;
  for (int it = 0; it < o.anisotropic_iterations; ++it) {
    Eigen::Matrix<double, 6, 6> h;
    Eigen::Matrix<double, 6, 1> g;
    RayAwareNormalEquations(a, b, indices, t, o, /*robust=*/true, &h, &g);
    const Eigen::Matrix<double, 6, 1> step = -h.ldlt().solve(g);
    if (!step.allFinite()) break;
    const Eigen::Vector3d omega = step.head<3>();
    const Eigen::Matrix3d rotate = omega.norm() > 0
                                       ? Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix()
                                       : Eigen::Matrix3d::Identity();
    t.linear() = rotate * t.linear();
    t.translation() = rotate * t.translation() + step.tail<3>();
    if (step.norm() < 1e-9) break;
  }
  t.linear() = Eigen::Quaterniond(t.linear()).normalized().toRotationMatrix();
  return t;
}

Eigen::Matrix<double, 6, 6> RigidFitInformation(const std::vector<Eigen::Vector3d>& a,
                                                const std::vector<Eigen::Vector3d>& b, const std::vector<int>& indices,
                                                const Rigid3d& b_from_a, const RansacOptions& options) {
  Eigen::Matrix<double, 6, 6> h;
  Eigen::Matrix<double, 6, 1> g;
  RayAwareNormalEquations(a, b, indices, b_from_a, options, /*robust=*/false, &h, &g);
  return h;
}

RansacResult EstimateRigidRansac(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                                 const RansacOptions& options, uint64_t seed) {
  F2C_CHECK(a.size() == b.size(), "matched point sets");
  RansacResult result;
  const int n = static_cast<int>(a.size());
  if (n < 3) return result;
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  size_t best = 0;
  int needed = options.max_iterations;
  for (int it = 0; it < needed; ++it) {
    ++result.iterations;
    int s[3] = {pick(rng), pick(rng), pick(rng)};
    if (s[0] == s[1] || s[0] == s[2] || s[1] == s[2]) continue;
    if (!GoodSample(a, b, s, options.inlier_threshold)) continue;
    const Rigid3d t = FitRigid(a, b, {s[0], s[1], s[2]});
    std::vector<int> inliers = Inliers(a, b, t, options.inlier_threshold, nullptr);
    if (inliers.size() > best) {
      best = inliers.size();
      result.b_from_a = t;
      result.inliers = std::move(inliers);
      // Iterations for `confidence` of one all-inlier sample, at the best ratio so far.
      const double w = static_cast<double>(best) / n;
      const double p_fail = 1.0 - w * w * w;
      if (p_fail <= 0) {
        needed = it + 1;
      } else {
        const double k = std::log(1.0 - options.confidence) / std::log(p_fail);
        needed = std::min<double>(options.max_iterations, std::ceil(k));
      }
    }
  }
  if (result.inliers.size() < 3) {
    result.inliers.clear();
    result.b_from_a = Rigid3d::Identity();
    return result;
  }
  for (int round = 0; round < options.refit_rounds; ++round) {
    const Rigid3d t = FitRigid(a, b, result.inliers);
    std::vector<int> inliers = Inliers(a, b, t, options.inlier_threshold, nullptr);
    if (inliers.size() < result.inliers.size()) break;  // the refit made it worse: keep the last
    result.b_from_a = t;
    const bool same = inliers == result.inliers;
    result.inliers = std::move(inliers);
    if (same) break;
  }
  if (options.robust_scale > 0) {
    std::vector<double> weights(result.inliers.size());
    const double c2 = options.robust_scale * options.robust_scale;
    for (int it = 0; it < options.robust_iterations; ++it) {
      for (size_t i = 0; i < result.inliers.size(); ++i) {
        const int k = result.inliers[i];
        weights[i] = 1.0 / (1.0 + (result.b_from_a * a[k] - b[k]).squaredNorm() / c2);
      }
      result.b_from_a = FitRigidWeighted(a, b, result.inliers, weights);
    }
  }
  if (options.anisotropic_iterations > 0) {
    result.b_from_a = RefineRigidAnisotropic(a, b, result.inliers, result.b_from_a, options);
  }
  Inliers(a, b, result.b_from_a, options.inlier_threshold, &result.inlier_rmse);
  result.information = RigidFitInformation(a, b, result.inliers, result.b_from_a, options);
  return result;
}

}  // namespace f2c
