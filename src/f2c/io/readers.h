#pragma once
// The per-layout readers behind ReadSequence (internal to f2c_io).

#include <filesystem>

#include "f2c/io/sequence.h"

namespace f2c::internal {

RgbdSequence ReadTum(const std::filesystem::path& dir, const IoOptions& options);
RgbdSequence ReadSevenScenes(const std::filesystem::path& dir, const IoOptions& options);
RgbdSequence ReadRedwood(const std::filesystem::path& dir, const IoOptions& options);
RgbdSequence ReadSun3d(const std::filesystem::path& dir, const IoOptions& options);
// A ScanNet / BundleFusion .sens recording (readers_sens.cc), and whether a file starts as one.
RgbdSequence ReadSens(const std::filesystem::path& path, const IoOptions& options);
bool LooksLikeSens(const std::filesystem::path& path);
// A ROS 1 bag (readers_rosbag.cc), and whether a file starts as one (any version).
RgbdSequence ReadRosbag(const std::filesystem::path& path, const IoOptions& options);
bool LooksLikeRosbag(const std::filesystem::path& path);

// Open3D's PinholeCameraIntrinsic JSON: width, height, intrinsic_matrix (column-major 3x3).
CameraIntrinsics ReadOpen3dIntrinsics(const std::filesystem::path& path);

// Image files (.png, .jpg, .jpeg, .ppm, .pgm) directly in `dir`, sorted by name.
std::vector<std::filesystem::path> ListImages(const std::filesystem::path& dir);

// Pairs each of `a` with the nearest unused of `b` within `max_difference`, as the TUM
// tools' associate.py does (greedy by smallest difference). Returns (index_a, index_b)
// sorted by index_a.
std::vector<std::pair<size_t, size_t>> AssociateTimestamps(const std::vector<double>& a, const std::vector<double>& b,
                                                           double max_difference);

// Sets a paired frame's time stamp (the depth's or the colour's, IoOptions::stamp) and its
// colour image's offset from it.
void StampFrame(double color_stamp, double depth_stamp, FrameStamp stamp, RgbdFrame& frame);

// Orders frames by time stamp: greedy pairing (AssociateTimestamps) may cross two pairs, whose
// depth stamps then run against the colour order.
void SortFramesByTime(std::vector<RgbdFrame>& frames);

}  // namespace f2c::internal
