#include "apps/common.h"

#include <fmt/format.h>

#include <Eigen/Core>
#include <cmath>
#include <opencv2/core/version.hpp>

#include "f2c/util/error.h"

namespace f2c::app {
using nlohmann::json;

json Versions() {
  return {{"fine2coarse", F2C_VERSION},
          {"opencv", CV_VERSION},
          {"eigen", fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)}};
}

json ToJson(const FusionTimings& t, const PlyPoints& mesh) {
  const double frames = std::max(t.frames_fused, 1);
  return {{"frames_fused", t.frames_fused},
          {"frames_without_pose", t.frames_without_pose},
          {"wall_s", t.wall},
          {"integrate_s", t.integrate},
          {"mesh_s", t.mesh},
          {"decode_cpu_s", t.decode_cpu},
          {"ms_per_frame", 1000.0 * t.wall / frames},
          {"blocks", t.blocks},
          {"volume_bytes", t.volume_bytes},
          {"vertices", mesh.positions.size()},
          {"triangles", mesh.faces.size()}};
}

Trajectory LoadGroundTruth(const std::filesystem::path& path, IoOptions io, std::optional<RgbdSequence>* dataset) {
  if (std::filesystem::is_directory(path) || path.extension() == ".conf") {
    io.check_files = false;
    *dataset = ReadSequence(path, io);
    if (!(*dataset)->ground_truth) ThrowInputError(path, "dataset has no ground-truth trajectory");
    return *(*dataset)->ground_truth;
  }
  return ReadTrajectoryFile(path);
}

}  // namespace f2c::app
