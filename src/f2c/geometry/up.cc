#include "f2c/geometry/up.h"

#include <algorithm>
#include <cmath>

namespace f2c {

Eigen::Vector3d UpFromNormals(const std::vector<Eigen::Vector3f>& all, const Eigen::Vector3d& prior_in) {
  const Eigen::Vector3d prior = prior_in.normalized();
  const size_t step = std::max<size_t>(1, all.size() / 20000);
  std::vector<Eigen::Vector3d> normals;  // a subsample, each flipped to the prior's side
  for (size_t i = 0; i < all.size(); i += step) {
    Eigen::Vector3d v = all[i].cast<double>();
    if (v.squaredNorm() == 0) continue;
    v.normalize();
    if (v.dot(prior) < 0) v = -v;
    normals.push_back(v);
  }
  // Candidates: every k-th normal inside the cone; the one with the most neighbours wins.
  const double near = std::cos(10 * M_PI / 180), cone = std::cos(45 * M_PI / 180);
  size_t best_count = 0;
  Eigen::Vector3d best = prior;
  for (size_t c = 0; c < normals.size(); c += std::max<size_t>(1, normals.size() / 1000)) {
    if (normals[c].dot(prior) < cone) continue;
    size_t count = 0;
    for (const Eigen::Vector3d& v : normals) count += v.dot(normals[c]) > near;
    if (count > best_count) best_count = count, best = normals[c];
  }
  if (best_count < 20) return prior;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& v : normals) {
    if (v.dot(best) > near) sum += v;
  }
  return sum.normalized();
}

}  // namespace f2c
