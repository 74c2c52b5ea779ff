#pragma once
// ROS 2 bags written byte by byte from the formats' specifications (rosbag2's SQLite schema,
// MCAP's records, CDR serialisation), for the reader's tests: a TUM-layout folder's frames
// as sensor_msgs/msg/Image (rgb8 colour, 32FC1 depth in metres) with CameraInfo beside each
// image topic, on /camera/color/image_raw and /camera/depth/image_rect_raw.

#include <filesystem>
#include <optional>
#include <string>

#include "f2c/geometry/intrinsics.h"

namespace f2c::testing {

struct Ros2BagOptions {
  std::string storage = "mcap";  // or "db3"
  std::string compression;       // MCAP chunks: "" (none), "zstd" or "lz4"
  CameraIntrinsics intrinsics;   // the CameraInfo messages'
  // Where set, the colour camera's info differs (these intrinsics) and /tf_static places it
  // at `color_in_depth` (a translation in the depth camera's frame) under camera_link.
  std::optional<CameraIntrinsics> color_intrinsics;
  Eigen::Vector3d color_in_depth = Eigen::Vector3d::Zero();
};

// Writes `out_dir` (metadata.yaml and scan.db3 or scan.mcap) from the TUM folder `tum_dir`.
// Returns the storage file's path.
std::filesystem::path WriteRos2Bag(const std::filesystem::path& tum_dir, const std::filesystem::path& out_dir,
                                   const Ros2BagOptions& options);

}  // namespace f2c::testing
