#include "f2c/report/slice.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "f2c/geometry/up.h"
#include "f2c/util/error.h"

namespace f2c {

void SliceOptions::Check() const { CheckFields(*this); }

SliceBand ChooseSliceBand(const std::vector<SliceFrame>& frames, const std::vector<std::optional<Rigid3d>>& poses,
                          const SliceOptions& options) {
  options.Check();
  F2C_CHECK(frames.size() == poses.size(), "one pose slot per frame");
  SliceBand band;
  band.thickness = options.thickness;
  Eigen::Vector3d camera_up = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3f> normals;
  for (size_t k = 0; k < frames.size(); ++k) {
    if (!poses[k]) continue;
    camera_up -= poses[k]->linear().col(1);
    const Eigen::Matrix3f r = poses[k]->linear().cast<float>();
    for (const Eigen::Vector3f& n : frames[k].normals) normals.push_back(r * n);
  }
  if (camera_up.norm() < 1e-9) return band;  // no posed frame
  band.up = UpFromNormals(normals, camera_up);
  std::map<long, size_t> walls;  // height bin -> wall points
  for (size_t k = 0; k < frames.size(); ++k) {
    if (!poses[k]) continue;
    const Eigen::Vector3d up_in_camera = poses[k]->linear().transpose() * band.up;
    const double camera_height = poses[k]->translation().dot(band.up);
    const Eigen::Vector3f up_f = up_in_camera.cast<float>();
    for (size_t i = 0; i < frames[k].points.size(); ++i) {
      const Eigen::Vector3f& n = frames[k].normals[i];
      if (n.squaredNorm() == 0 || std::abs(n.dot(up_f)) >= options.wall_max_cos) continue;
      const double h = camera_height + frames[k].points[i].cast<double>().dot(up_in_camera);
      ++walls[static_cast<long>(std::floor(h / options.bin))];
    }
  }
  if (walls.empty()) {
    band.height = 0;
    for (const auto& p : poses) {
      if (p) band.height += p->translation().dot(band.up);
    }
    band.height /=
        static_cast<double>(std::count_if(poses.begin(), poses.end(), [](const auto& p) { return p.has_value(); }));
    return band;
  }
  const auto best =
      std::max_element(walls.begin(), walls.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  band.height = (static_cast<double>(best->first) + 0.5) * options.bin;
  return band;
}

std::vector<Eigen::Vector3d> SlicePoints(const std::vector<SliceFrame>& frames,
                                         const std::vector<std::optional<Rigid3d>>& poses, const SliceBand& band) {
  F2C_CHECK(frames.size() == poses.size(), "one pose slot per frame");
  std::vector<Eigen::Vector3d> out;
  const double half = 0.5 * band.thickness;
  for (size_t k = 0; k < frames.size(); ++k) {
    if (!poses[k]) continue;
    for (const Eigen::Vector3f& p : frames[k].points) {
      const Eigen::Vector3d w = *poses[k] * p.cast<double>();
      if (std::abs(w.dot(band.up) - band.height) <= half) out.push_back(w);
    }
  }
  return out;
}

}  // namespace f2c
