#pragma once
// ScanNet .sens recordings written byte by byte from the format's description
// (io/readers_sens.cc), for the reader's tests: a synthetic scene rendered by a depth camera
// and by a colour camera of its own (another resolution, intrinsics and place).

#include <filesystem>
#include <vector>

#include "f2c/testing/synthetic_scene.h"

namespace f2c::testing {

struct SensOptions {
  CameraIntrinsics depth = TestIntrinsics();
  CameraIntrinsics color = TestIntrinsics();
  Rigid3d color_from_depth = Rigid3d::Identity();
  int color_compression = 2;  // 0 raw RGB, 1 PNG, 2 JPEG
  int depth_compression = 1;  // 0 raw uint16, 1 zlib uint16
  float depth_shift = 1000;   // units per metre
};

// Renders each pose (the depth camera's world_from_camera; time stamps 1/30 s apart) and
// writes the recording. Returns its bytes' length.
uint64_t WriteSyntheticSens(const std::filesystem::path& path, const SyntheticScene& scene,
                            const std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>>& world_from_camera,
                            const SensOptions& options = {});

}  // namespace f2c::testing
