#include "apps/common.h"

#include <fmt/format.h>

#include <Eigen/Core>
#include <cmath>
#include <opencv2/core/version.hpp>

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

}  // namespace f2c::app
