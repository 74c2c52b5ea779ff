#pragma once
// Pinhole intrinsics of the depth camera (colour is assumed registered to depth), and the
// lens distortion of the images as stored, when the calibration gives one.
//
// Distortion (OpenCV's and the TUM benchmark's order k1, k2, p1, p2, k3): a pinhole point
// (x, y) = ((u - cx) / fx, (v - cy) / fy) appears in the stored image at
//   x' = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2),
//   y' = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y,   r^2 = x^2 + y^2,
// i.e. at pixel (fx x' + cx, fy y' + cy). The image loaders (io/image.h) resample every
// frame to the pinhole model, so every later stage sees a pinhole camera and uses fx, fy,
// cx, cy alone (docs/datasets.md, "Lens distortion": why the depth is resampled too).

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace f2c {

// The plausible range of a depth camera's focal length, in pixels: 10 px is a field of view of
// 176 degrees across a 640-pixel image, 100,000 px one of 0.4 degrees. Outside it the values
// are a unit mistake (metres, or a matrix entry in the wrong place), and a run would go on
// and find nothing anywhere.
constexpr double kMinFocalPixels = 10;
constexpr double kMaxFocalPixels = 100000;
constexpr double kMaxImageSide = 100000;  // pixels: no depth camera's image is this wide

struct CameraIntrinsics {
  double fx = 0, fy = 0;  // focal lengths (pixels)
  double cx = 0, cy = 0;  // principal point (pixels; pixel centres at integer coordinates)
  int width = 640, height = 480;
  // False when the source gives no image size (a 3x3 matrix file, fx,fy,cx,cy): the dataset
  // reader then takes it from the first depth image.
  bool size_known = true;
  std::array<double, 5> distortion{};  // k1, k2, p1, p2, k3 (all 0: none)

  bool HasDistortion() const {
    for (double d : distortion) {
      if (d != 0) return true;
    }
    return false;
  }
  // Where the pinhole pixel (u, v) lies in the stored, distorted image (the model above).
  Eigen::Vector2d Distort(double u, double v) const;

  // Point in camera coordinates (metres; x right, y down, z forward) of pixel (u, v) at
  // depth z.
  Eigen::Vector3d Unproject(double u, double v, double z) const { return {(u - cx) * z / fx, (v - cy) * z / fy, z}; }
  // Pixel of a point in camera coordinates (z > 0).
  Eigen::Vector2d Project(const Eigen::Vector3d& p) const { return {fx * p.x() / p.z() + cx, fy * p.y() / p.z() + cy}; }
  // InputError("<source>: ...") unless focal lengths are in [kMinFocalPixels,
  // kMaxFocalPixels], the principal point lies inside the image (in [0, kMaxImageSide) while
  // the size is unknown) and the distortion coefficients are finite.
  void Validate(const std::string& source) const;
};

// Named presets: tum-fr1, tum-fr2, tum-fr3 (the TUM RGB-D calibrations of the colour camera,
// to which TUM's depth is registered, with their published distortion: fr3's images were
// stored undistorted, so it has none), primesense (the nominal 525/319.5/239.5 of Kinect v1 /
// Xtion used by Open3D and ICL-NUIM).
std::vector<std::string> IntrinsicsPresetNames();

// Parses "fx,fy,cx,cy", "fx,fy,cx,cy,k1,k2,p1,p2" or "fx,fy,cx,cy,k1,k2,p1,p2,k3" (image size
// unknown until the images are seen) or a preset name (640x480). InputError naming `source`
// (e.g. "--intrinsics") otherwise.
CameraIntrinsics ParseIntrinsics(const std::string& text, const std::string& source);

// Reads a 3x3 camera matrix file (7-Scenes/3DMatch camera-intrinsics.txt, SUN3D
// intrinsics.txt): nine numbers in row-major order, white-space separated. The size is
// unknown (size_known = false) until the images are seen.
CameraIntrinsics ReadIntrinsicsMatrixFile(const std::filesystem::path& path);

}  // namespace f2c
