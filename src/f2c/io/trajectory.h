#pragma once
// Camera trajectories and their files: TUM (`timestamp tx ty tz qx qy qz qw`) and the
// Redwood/Open3D `.log` (a line `i j n`, then a row-major 4x4 camera-to-world).

#include <filesystem>
#include <string>
#include <vector>

#include "f2c/geometry/rigid.h"

namespace f2c {

struct Trajectory {
  // Seconds. Layouts without time stamps use frame_number / assumed fps; files without any
  // (.log) hold frame ids here and set has_timestamps = false.
  std::vector<double> timestamps;
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> world_from_camera;
  bool has_timestamps = true;
  // A .conf's poses name their frames: the depth image of each scan line (empty otherwise).
  // They are matched to a dataset's frames by these names, never by line order.
  std::vector<std::string> frame_names;

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

// For a trajectory without time stamps: the dataset frame each pose belongs to, or -1 for a
// pose of a frame the dataset (or its selection) does not hold. A .conf's poses are matched by
// their depth image's name (`frame_names`: the frames' RgbdFrame::name); a .log's by frame id
// (the id-th frame). InputError naming `path` when a .log id is out of range, when no pose
// names a frame, or when the dataset's frames share a name a .conf would need.
std::vector<long> FramesOfPoses(const Trajectory& trajectory, const std::vector<std::string>& frame_names,
                                const std::filesystem::path& path);

// One pose of `trajectory` (read from `path`) per frame of a sequence (`frame_times`, and
// `frame_names` for a .conf): the pose within max_difference seconds of the frame's time
// stamp, or else one interpolated between the two around it when they are at most max_span
// seconds apart (a ground truth recorded at its own rate); for a file without time stamps,
// the pose FramesOfPoses gives it. InputError naming `path` and the first frame without a
// pose otherwise.
std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> PosesForFrames(
    const Trajectory& trajectory, const std::vector<double>& frame_times, const std::vector<std::string>& frame_names,
    const std::filesystem::path& path, double max_difference = 1e-3, double max_span = 0.25);

}  // namespace f2c
