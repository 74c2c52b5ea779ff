#include "apps/common.h"

#include <fmt/format.h>

#include <Eigen/Core>
#include <cmath>
#include <opencv2/core/version.hpp>

namespace f2c::app {
using nlohmann::json;

CLI::Validator Finite() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v)) return "'" + text + "' is not a number";
        return std::isfinite(v) ? std::string() : "'" + text + "' is not a finite number";
      },
      "FINITE");
}

json Versions() {
  return {{"fine2coarse", F2C_VERSION},
          {"opencv", CV_VERSION},
          {"eigen", fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)}};
}

json ToJson(const IoOptions& io) {
  return {{"intrinsics", io.intrinsics}, {"every", io.every},   {"first", io.first},
          {"last", io.last},             {"max_time_difference", io.max_time_difference},
          {"assumed_fps", io.assumed_fps}, {"sequence", io.sequence}};
}

void AddFrameSelection(CLI::App* cmd, f2c::IoOptions* io) {
  cmd->add_option("--intrinsics", io->intrinsics,
                  "fx,fy,cx,cy or a preset: tum-fr1, tum-fr2, tum-fr3, primesense (TUM folders "
                  "carry none; overrides a dataset's own)");
  cmd->add_option("--every", io->every, "use every N-th frame")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_option("--first", io->first, "first frame (0-based)")->check(CLI::NonNegativeNumber)->capture_default_str();
  cmd->add_option("--last", io->last, "last frame, inclusive (-1: the end)")->capture_default_str();
  cmd->add_option("--sequence", io->sequence,
                  "7-Scenes/3DMatch: read only this seq-XX subfolder (default: all, joined)")
      ->capture_default_str();
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

}  // namespace f2c::app
