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

void AddFeatureOptions(CLI::App* cmd, f2c::FeatureOptions* f) {
  const std::string group = "Features (paper 4.1; DESIGN.md section 2)";
  auto add = [&](const std::string& name, auto* value, const std::string& help) {
    cmd->add_option(name, *value, help)->capture_default_str()->group(group);
  };
  add("--feature-step", &f->grid.step, "pixels per grid cell of the feature extraction");
  add("--feature-max-depth", &f->grid.max_depth, "farthest depth used for features (m)");
  add("--normal-radius", &f->grid.normal_radius, "normals: neighbours within this distance (m)");
  add("--normal-radius-pixels", &f->grid.normal_radius_pixels, "normals: neighbours within this many pixels");
  add("--min-spacing", &f->min_spacing, "features of one type at least this far apart (m)");
  add("--proxy-min-points", &f->proxies.min_points, "smallest planar proxy (grid cells)");
  add("--proxy-max-distance", &f->proxies.max_distance, "clusters merge when their planes are this close (m)");
  add("--proxy-max-angle", &f->proxies.max_normal_angle, "...and their normals this close (radians)");
  add("--edge-jump-fraction", &f->edge_jump_fraction, "contours: depth jump above this fraction of depth...");
  add("--edge-min-jump", &f->edge_min_jump, "...and at least this many metres");
  add("--crease-angle", &f->crease_angle, "ridges/valleys where proxies meet at more than this (radians)");
  add("--depth-noise-a", &f->proxies.sensor_sigma_a,
      "sensor depth noise sigma(z) = a + b (z - 0.4)^2 (m; Kinect v1 defaults; 0 and 0 for noise-free depth)");
  add("--depth-noise-b", &f->proxies.sensor_sigma_b, "...its b (m per m^2)");
  cmd->add_flag("--bilateral", f->grid.bilateral, "bilateral-filter depth first (noisy sensors, e.g. SUN3D)")
      ->group(group);
}

void AddFusionOptions(CLI::App* cmd, FusionOptions* f) {
  const std::string group = "Mesh (TSDF fusion, marching cubes; docs/fusion.md)";
  auto add = [&](const std::string& name, auto* value, const std::string& help) {
    cmd->add_option(name, *value, help)->capture_default_str()->group(group);
  };
  add("--voxel-size", &f->tsdf.voxel_size, "TSDF voxel edge (m)");
  add("--truncation-voxels", &f->tsdf.truncation_voxels, "signed distances are truncated at this many voxels");
  add("--fuse-max-depth", &f->tsdf.max_depth, "depth beyond this (m) is not fused");
  add("--fuse-every", &f->every, "fuse every N-th frame that has a pose");
  add("--mesh-min-weight", &f->mesh.min_weight, "mesh only where every voxel was seen this often");
}

json ToJson(const FusionOptions& f) {
  return {{"voxel_size", f.tsdf.voxel_size},      {"truncation_voxels", f.tsdf.truncation_voxels},
          {"min_depth", f.tsdf.min_depth},        {"max_depth", f.tsdf.max_depth},
          {"every", f.every},                     {"mesh_min_weight", f.mesh.min_weight}};
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
