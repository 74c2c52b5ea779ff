#pragma once
// A simulated scan on disk, in TUM layout so every tool reads it: rgb/, depth/ (uint16,
// metres * 5000), rgb.txt, depth.txt, groundtruth.txt, camera-intrinsics.txt, and a
// ground-truth correspondence file in the authors' benchmark format:
//
//   n_correspondences N
//   point3d SCAN:<a> SCAN:<b> xA yA zA xB yB zB     (one surface point in frames a and b,
//                                                    each in that frame's camera coordinates)

#include <filesystem>
#include <string>

#include "f2c/sim/render.h"
#include "f2c/sim/walk.h"

namespace f2c::sim {

struct SimulateOptions {
  std::string scene = "apartment";
  uint64_t seed = 0;                       // scene furniture, walk and noise
  CameraIntrinsics intrinsics{525.0, 525.0, 319.5, 239.5, 640, 480};
  SensorOptions sensor;
  WalkOptions walk;                        // walk.frames = number of frames
  int correspondences = 400;               // about half nearby pairs, half loop closures
  void Check() const;
};

struct Correspondence {
  int frame_a = 0, frame_b = 0;
  Eigen::Vector3d point_in_a, point_in_b;  // camera coordinates, metres
};

// Writes the scan into `dir` (created; files written atomically). Returns the poses.
Trajectory Simulate(const std::filesystem::path& dir, const SimulateOptions& options, bool quiet);

// Ground-truth correspondences on exact geometry (no sensor noise), visible in both frames.
std::vector<Correspondence> SampleCorrespondences(const Scene& scene, const Renderer& renderer,
                                                  const CameraIntrinsics& intrinsics,
                                                  const Trajectory& poses, int count, uint64_t seed);
void WriteCorrespondences(const std::filesystem::path& path, const std::vector<Correspondence>& c);
std::vector<Correspondence> ReadCorrespondences(const std::filesystem::path& path);

}  // namespace f2c::sim
