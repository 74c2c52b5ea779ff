#pragma once
// Camera trajectories and their files: TUM (`timestamp tx ty tz qx qy qz qw`) and the
// Redwood/Open3D `.log` (a line `i j n`, then a row-major 4x4 camera-to-world).

#include <filesystem>
#include <vector>

#include "f2c/geometry/rigid.h"

namespace f2c {

struct Trajectory {
  // Seconds. Layouts without time stamps use frame_number / assumed fps; files without any
  // (.log) hold frame ids here and set has_timestamps = false.
  std::vector<double> timestamps;
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> world_from_camera;
  bool has_timestamps = true;

  size_t size() const { return timestamps.size(); }
  bool empty() const { return timestamps.empty(); }
  void Add(double timestamp, const Rigid3d& pose) {
    timestamps.push_back(timestamp);
    world_from_camera.push_back(pose);
  }
};

// Reads a TUM trajectory. Lines: `timestamp tx ty tz qx qy qz qw`; '#' comments. Poses are
// checked (finite, unit quaternion); InputError at file:line otherwise, or if it is empty.
Trajectory ReadTumTrajectory(const std::filesystem::path& path);
void WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory);

// Reads a Redwood/Open3D .log: blocks of `id id n` then four rows of the 4x4
// camera-to-world. The first id becomes the time stamp slot (has_timestamps = false).
Trajectory ReadLogTrajectory(const std::filesystem::path& path);
// Writes one block per pose, `i i i+1` as Open3D does.
void WriteLogTrajectory(const std::filesystem::path& path, const Trajectory& trajectory);

// Reads a trajectory file by its ending: .log, .conf (the authors' format) or TUM text.
Trajectory ReadTrajectoryFile(const std::filesystem::path& path);

// One pose of `trajectory` (read from `path`) per frame time stamp in `frame_times`: the pose
// within max_difference seconds of the frame's time stamp, or else one interpolated between
// the two around it when they are at most max_span seconds apart (a ground truth recorded at
// its own rate); for a file without time stamps (.log, .conf), the poses in order, exactly
// one per frame. InputError naming `path` and the first frame without a pose otherwise.
std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> PosesForFrames(const Trajectory& trajectory,
                                                                       const std::vector<double>& frame_times,
                                                                       const std::filesystem::path& path,
                                                                       double max_difference = 1e-3,
                                                                       double max_span = 0.25);

}  // namespace f2c
