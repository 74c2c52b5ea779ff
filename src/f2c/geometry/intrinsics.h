#pragma once
// Pinhole intrinsics of the depth camera (colour is assumed registered to depth).

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace f2c {

struct CameraIntrinsics {
  double fx = 0, fy = 0;  // focal lengths (pixels)
  double cx = 0, cy = 0;  // principal point (pixels; pixel centres at integer coordinates)
  int width = 640, height = 480;
  // False when the source gives no image size (a 3x3 matrix file, fx,fy,cx,cy): the dataset
  // reader then takes it from the first depth image.
  bool size_known = true;

  // Point in camera coordinates (metres; x right, y down, z forward) of pixel (u, v) at
  // depth z.
  Eigen::Vector3d Unproject(double u, double v, double z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
  // Pixel of a point in camera coordinates (z > 0).
  Eigen::Vector2d Project(const Eigen::Vector3d& p) const {
    return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy};
  }
  // InputError("<source>: ...") unless focal lengths are positive and finite and the
  // principal point lies inside the image (at least non-negative while the size is unknown).
  void Validate(const std::string& source) const;
};

// Named presets: tum-fr1, tum-fr2, tum-fr3 (the TUM RGB-D calibrations), primesense (the
// nominal 525/319.5/239.5 of Kinect v1 / Xtion used by Open3D and ICL-NUIM).
std::vector<std::string> IntrinsicsPresetNames();

// Parses "fx,fy,cx,cy" (image size unknown until the images are seen) or a preset name
// (640x480). InputError naming `source` (e.g. "--intrinsics") otherwise.
CameraIntrinsics ParseIntrinsics(const std::string& text, const std::string& source);

// Reads a 3x3 camera matrix file (7-Scenes/3DMatch camera-intrinsics.txt, SUN3D
// intrinsics.txt): nine numbers in row-major order, white-space separated. The size is
// unknown (size_known = false) until the images are seen.
CameraIntrinsics ReadIntrinsicsMatrixFile(const std::filesystem::path& path);

}  // namespace f2c
