#pragma once
// Ground-truth point correspondences between frames, in the authors' benchmark format (the
// paper's SUN3D evaluation; our simulator writes them too):
//
//   n_correspondences N
//   point3d SCAN:<a> SCAN:<b> xA yA zA xB yB zB    (one surface point seen in frames a and
//                                                   b, each in that frame's camera
//                                                   coordinates, metres; a, b frame indices)

#include <Eigen/Core>
#include <filesystem>
#include <vector>

namespace f2c {

struct Correspondence {
  int frame_a = 0, frame_b = 0;
  Eigen::Vector3d point_in_a = Eigen::Vector3d::Zero();  // camera coordinates, metres
  Eigen::Vector3d point_in_b = Eigen::Vector3d::Zero();
};

void WriteCorrespondences(const std::filesystem::path& path, const std::vector<Correspondence>& correspondences);
// InputError naming the file and line on a malformed line or a wrong count.
std::vector<Correspondence> ReadCorrespondences(const std::filesystem::path& path);

}  // namespace f2c
