#pragma once
// A box-shaped room with solid boxes in it, ray cast exactly: depth (CV_32F metres) and a
// blocky procedural texture SIFT can match. Tests build scenes with known answers from it.

#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "f2c/geometry/intrinsics.h"
#include "f2c/geometry/rigid.h"

namespace f2c::testing {

inline constexpr double kDeg = M_PI / 180;  // radians in a degree

struct Box {
  Eigen::Vector3d min, max;
};

struct SyntheticScene {
  Box room{{-2.5, -1.5, -2.5}, {2.5, 1.5, 2.5}};  // the camera stays inside it
  std::vector<Box> solids{{{-0.6, 0.7, 1.0}, {0.4, 1.5, 1.8}}, {{0.8, -0.2, 1.6}, {1.6, 1.5, 2.2}}};
  bool textured = true;
};

struct RenderedFrame {
  cv::Mat color;  // CV_8UC3
  cv::Mat depth;  // CV_32F metres, 0 where nothing is hit
};

RenderedFrame Render(const SyntheticScene& scene, const CameraIntrinsics& intrinsics, const Rigid3d& world_from_camera);

// Depth (CV_32F metres) of the plane {x : n . x = d} (camera frame) along each pixel's ray:
// z = d / (n . r), r = ((u - cx) / fx, (v - cy) / fy, 1).
cv::Mat PlaneDepth(const CameraIntrinsics& intrinsics, const Eigen::Vector3d& n, double d);

// Distance (m) from p to the nearest surface of the scene: the room's walls and the solids'
// faces (tests of reconstructed surfaces).
double SurfaceDistance(const SyntheticScene& scene, const Eigen::Vector3d& p);

// Intrinsics of a 640x480 PrimeSense-like camera.
inline CameraIntrinsics TestIntrinsics() { return {525.0, 525.0, 319.5, 239.5, 640, 480}; }

}  // namespace f2c::testing

#include <filesystem>
#include <functional>
#include <string>

#include "f2c/io/trajectory.h"

namespace f2c::testing {

// Renders `world_from_camera` (time stamps 1/30 s apart) and writes a TUM folder: rgb/,
// depth/ (uint16, metres * 5000), rgb.txt, depth.txt, groundtruth.txt. Returns the poses.
Trajectory WriteTumSequence(const std::filesystem::path& dir, const SyntheticScene& scene,
                            const CameraIntrinsics& intrinsics,
                            const std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>& world_from_camera);

// The message of the InputError `f` raises, or "no error".
std::string InputErrorMessage(const std::function<void()>& f);

// A fresh empty temporary folder for a test, unique to this process (so that test runs side
// by side do not collide), removed when the process exits.
std::filesystem::path FreshTempDir(const std::string& name);

// A temporary folder that the processes of this test binary share, for data that a whole
// suite makes once: ctest runs each test in a process of its own, so a suite's set-up runs
// once per test. Named after the executable's path, size and modification time, so that a
// rebuilt binary never reads what an older one wrote (and removes the older one's folder).
// Write into it atomically (WriteFileAtomic): two processes may fill it at once.
std::filesystem::path SharedTestDataDir();

}  // namespace f2c::testing
