#include "f2c/io/trajectory.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Geometry>

#include "f2c/io/conf.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/text.h"

namespace f2c {

Trajectory ReadTumTrajectory(const std::filesystem::path& path) {
  Trajectory trajectory;
  for (const TextLine& line : ReadDataLines(path)) {
    const auto tokens = SplitWhitespace(line.text);
    if (tokens.size() != 8) {
      ThrowInputError(path, line.number,
                      fmt::format("expected 'timestamp tx ty tz qx qy qz qw', got {} fields", tokens.size()));
    }
    const auto v = ParseDoublesOrThrow(tokens, 0, path, line.number, "'timestamp tx ty tz qx qy qz qw'");
    const Rigid3d pose = RigidFromQuaternionOrThrow({v[1], v[2], v[3]}, {v[4], v[5], v[6], v[7]}, path, line.number);
    if (!trajectory.empty() && v[0] <= trajectory.timestamps.back()) {
      ThrowInputError(path, line.number, "time stamps are not increasing");
    }
    trajectory.Add(v[0], pose);
  }
  if (trajectory.empty()) ThrowInputError(path, "trajectory holds no pose");
  return trajectory;
}

void WriteTumTrajectory(const std::filesystem::path& path, const Trajectory& trajectory) {
  std::string out = "# timestamp tx ty tz qx qy qz qw (camera-to-world), written by fine2coarse\n";
  for (size_t i = 0; i < trajectory.size(); ++i) {
    const Rigid3d& pose = trajectory.world_from_camera[i];
    const Eigen::Quaterniond q(pose.linear());
    const Eigen::Vector3d t = pose.translation();
    out += fmt::format("{:.6f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f}\n", trajectory.timestamps[i], t.x(),
                       t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  }
  WriteFileAtomic(path, out);
}

Trajectory ReadLogTrajectory(const std::filesystem::path& path) {
  const auto lines = ReadDataLines(path);
  if (lines.empty()) ThrowInputError(path, "trajectory holds no pose");
  if (lines.size() % 5 != 0) {
    ThrowInputError(path, fmt::format("expected blocks of 5 lines ('i j n' and a 4x4 matrix), "
                                      "got {} lines",
                                      lines.size()));
  }
  Trajectory trajectory;
  trajectory.has_timestamps = false;
  for (size_t b = 0; b < lines.size(); b += 5) {
    const auto header = SplitWhitespace(lines[b].text);
    long id = 0, j = 0, n = 0;
    if (header.size() != 3 || !ParseInt(header[0], &id) || !ParseInt(header[1], &j) || !ParseInt(header[2], &n)) {
      ThrowInputError(path, lines[b].number, "expected a block header 'i j n' of three integers");
    }
    // One block per frame, numbered in order: a repeated id is a pair file (3DMatch's gt.log)
    // or a pasted block, a gap a frame without its pose; either would place poses wrongly.
    if (id < 0) ThrowInputError(path, lines[b].number, fmt::format("frame id {} is negative", id));
    if (!trajectory.empty()) {
      const long previous = static_cast<long>(trajectory.timestamps.back());
      if (id <= previous) {
        ThrowInputError(path, lines[b].number,
                        fmt::format("frame id {} after {} (one block per frame, ids in order; a file of "
                                    "frame pairs is not a trajectory)",
                                    id, previous));
      }
      if (id != previous + 1) {
        ThrowInputError(path, lines[b].number,
                        fmt::format("frame id {} after {}: frame {} has no pose", id, previous, previous + 1));
      }
    }
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      const TextLine& row = lines[b + 1 + r];
      const auto tokens = SplitWhitespace(row.text);
      if (tokens.size() != 4) {
        ThrowInputError(path, row.number,
                        fmt::format("expected a matrix row of 4 numbers, got {} fields", tokens.size()));
      }
      const auto v = ParseDoublesOrThrow(tokens, 0, path, row.number, "a matrix row of 4 numbers");
      m.row(r) << v[0], v[1], v[2], v[3];
    }
    trajectory.Add(static_cast<double>(id), RigidFromMatrixOrThrow(m, path, lines[b + 1].number));
  }
  return trajectory;
}

void WriteLogTrajectory(const std::filesystem::path& path, const Trajectory& trajectory) {
  std::string out;
  for (size_t i = 0; i < trajectory.size(); ++i) {
    out += fmt::format("{} {} {}\n", i, i, i + 1);
    const Eigen::Matrix4d m = trajectory.world_from_camera[i].matrix();
    for (int r = 0; r < 4; ++r) {
      out += fmt::format("{:.12g} {:.12g} {:.12g} {:.12g}\n", m(r, 0), m(r, 1), m(r, 2), m(r, 3));
    }
  }
  WriteFileAtomic(path, out);
}

Trajectory ReadTrajectoryFile(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".log") return ReadLogTrajectory(path);
  if (ext == ".conf") return ReadConf(path).trajectory;
  return ReadTumTrajectory(path);
}

std::vector<long> FramesOfPoses(const Trajectory& trajectory, const std::vector<std::string>& frame_names,
                                const std::filesystem::path& path) {
  F2C_CHECK(!trajectory.has_timestamps, "poses without time stamps");
  const long n = static_cast<long>(frame_names.size());
  std::vector<long> frames(trajectory.size(), -1);
  if (trajectory.frame_names.empty()) {
    for (size_t i = 0; i < trajectory.size(); ++i) {
      const double id = trajectory.timestamps[i];
      if (!(id >= 0 && id < static_cast<double>(n))) {
        ThrowInputError(path, fmt::format("frame id {} but the dataset has {} frames", id, n));
      }
      frames[i] = static_cast<long>(id);
    }
    return frames;
  }
  F2C_CHECK(trajectory.frame_names.size() == trajectory.size(), "one name per pose");
  std::unordered_map<std::string, long> frame_of_name;
  for (long k = 0; k < n; ++k) {
    if (!frame_of_name.emplace(frame_names[k], k).second) {
      ThrowInputError(path, fmt::format("its poses name their frames, but frames {} and {} of the dataset are both "
                                        "named '{}'",
                                        frame_of_name[frame_names[k]], k, frame_names[k]));
    }
  }
  bool any = false;
  for (size_t i = 0; i < trajectory.size(); ++i) {
    const auto it = frame_of_name.find(trajectory.frame_names[i]);
    if (it != frame_of_name.end()) frames[i] = it->second, any = true;
  }
  if (!any && n > 0) {
    ThrowInputError(path, fmt::format("none of its {} poses names a frame of the dataset (its first: '{}', the "
                                      "dataset's first: '{}')",
                                      trajectory.size(), trajectory.frame_names[0], frame_names[0]));
  }
  return frames;
}

std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> PosesForFrames(const Trajectory& trajectory,
                                                                       const std::vector<double>& frame_times,
                                                                       const std::vector<std::string>& frame_names,
                                                                       const std::filesystem::path& path,
                                                                       double max_difference, double max_span) {
  const size_t n = frame_times.size();
  if (!trajectory.has_timestamps) {
    F2C_CHECK(frame_names.size() == n, "one name per frame");
    const std::vector<long> frame_of_pose = FramesOfPoses(trajectory, frame_names, path);
    std::vector<long> pose_of_frame(n, -1);
    for (size_t i = 0; i < frame_of_pose.size(); ++i) {
      if (frame_of_pose[i] >= 0) pose_of_frame[frame_of_pose[i]] = static_cast<long>(i);
    }
    std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> poses;
    poses.reserve(n);
    for (size_t f = 0; f < n; ++f) {
      if (pose_of_frame[f] < 0) {
        ThrowInputError(path, fmt::format("no pose for frame {} ('{}')", f, frame_names[f]));
      }
      poses.push_back(trajectory.world_from_camera[pose_of_frame[f]]);
    }
    return poses;
  }
  // Time stamps in any order: sorted once, then a binary search per frame.
  std::vector<size_t> order(trajectory.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return trajectory.timestamps[a] < trajectory.timestamps[b]; });
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> poses;
  poses.reserve(n);
  for (size_t f = 0; f < n; ++f) {
    const double t = frame_times[f];
    const auto after = std::lower_bound(order.begin(), order.end(), t,
                                        [&](size_t i, double value) { return trajectory.timestamps[i] < value; });
    const bool has_after = after != order.end(), has_before = after != order.begin();
    const double t_after = has_after ? trajectory.timestamps[*after] : 0;
    const double t_before = has_before ? trajectory.timestamps[*(after - 1)] : 0;
    if (has_after && t_after - t <= max_difference && (!has_before || t_after - t <= t - t_before)) {
      poses.push_back(trajectory.world_from_camera[*after]);
    } else if (has_before && t - t_before <= max_difference) {
      poses.push_back(trajectory.world_from_camera[*(after - 1)]);
    } else if (has_before && has_after && t_after - t_before <= max_span) {
      // Between two poses (a motion-capture trajectory at its own rate): translation
      // linearly, rotation along the shortest arc.
      poses.push_back(InterpolatePose(trajectory.world_from_camera[*(after - 1)], trajectory.world_from_camera[*after],
                                      (t - t_before) / (t_after - t_before)));
    } else {
      ThrowInputError(path, fmt::format("no pose within {:g} ms of frame {} (time stamp {:.6f} s), nor two within {:g} "
                                        "s around it",
                                        max_difference * 1e3, f, t, max_span));
    }
  }
  return poses;
}

}  // namespace f2c
