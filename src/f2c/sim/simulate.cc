#include "f2c/sim/simulate.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "f2c/io/image_write.h"
#include "f2c/io/ply.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/progress.h"
#include "f2c/util/text.h"

namespace f2c::sim {
namespace fs = std::filesystem;

void SimulateOptions::Check() const {
  CheckFields(*this);
  intrinsics.Validate("--intrinsics");
  // Beyond half a frame interval a colour image lies nearer another frame's depth, and the
  // folder's pairing (nearest in time) would pair it with that one.
  const double half_interval_ms = 500.0 / walk.fps;
  if (!(color_offset_ms < half_interval_ms)) {
    ThrowInputError("--color-offset", fmt::format("must be below half a frame interval ({:.3g} ms at {:g} frames/s), "
                                                  "got {:g}",
                                                  half_interval_ms, walk.fps, color_offset_ms));
  }
}

namespace {

// The walk's pose at time t (seconds of the walk): its frames' poses interpolated
// (InterpolatePose), the first or last beyond them.
Rigid3d PoseAt(const Trajectory& walk, double t) {
  const auto& times = walk.timestamps;
  if (t <= times.front()) return walk.world_from_camera.front();
  if (t >= times.back()) return walk.world_from_camera.back();
  const size_t b = std::upper_bound(times.begin(), times.end(), t) - times.begin();
  const size_t a = b - 1;
  return InterpolatePose(walk.world_from_camera[a], walk.world_from_camera[b], (t - times[a]) / (times[b] - times[a]));
}

// A point of frame a's exact geometry at pixel (u, v) seen also by frame b, or false.
bool Correspond(const Renderer& renderer, const CameraIntrinsics& k, const Rigid3d& world_from_a,
                const Rigid3d& world_from_b, double u, double v, Correspondence* c) {
  const Eigen::Vector3d ray_a = world_from_a.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
  int tri = -1;
  const double t = renderer.CastRay(world_from_a.translation(), ray_a, &tri);
  if (tri < 0 || t > 5.0) return false;
  const Eigen::Vector3d world = world_from_a.translation() + t * ray_a;
  const Eigen::Vector3d in_b = world_from_b.inverse() * world;
  if (in_b.z() < 0.4 || in_b.z() > 5.0) return false;
  const Eigen::Vector2d uv = k.Project(in_b);
  if (uv.x() < 0 || uv.y() < 0 || uv.x() > k.width - 1 || uv.y() > k.height - 1) return false;
  // Visible from b: the first surface along b's ray to the point is the point itself.
  const Eigen::Vector3d to_point = world - world_from_b.translation();
  const double distance = to_point.norm();
  const double first = renderer.CastRay(world_from_b.translation(), to_point / distance, nullptr);
  if (std::abs(first - distance) > 1e-4) return false;
  c->point_in_a = world_from_a.inverse() * world;
  c->point_in_b = in_b;
  return true;
}

}  // namespace

std::vector<Correspondence> SampleCorrespondences(const Scene& scene, const Renderer& renderer,
                                                  const CameraIntrinsics& k, const Trajectory& poses, int count,
                                                  uint64_t seed) {
  std::vector<Correspondence> out;
  const int n = static_cast<int>(poses.size());
  if (n < 2 || count == 0) return out;
  std::mt19937_64 rng(seed ^ 0xC0221E5ULL);
  std::uniform_int_distribution<int> frame(0, n - 1), offset(1, 10);
  std::uniform_real_distribution<double> pu(0, k.width - 1), pv(0, k.height - 1);
  // Loop-closure pairs: far apart in time (> 5 s), close in space and view direction.
  std::vector<std::pair<int, int>> loops;
  // The gap in frames from the mean frame interval: a scan at 30 Hz or every k-th frame of one.
  const double interval = (poses.timestamps.back() - poses.timestamps.front()) / (n - 1);
  const int gap = interval > 0 ? std::max(1, static_cast<int>(std::lround(5.0 / interval))) : 5 * 30;
  for (int a = 0; a < n; a += 5) {
    for (int b = a + gap; b < n; b += 5) {
      const Rigid3d& pa = poses.world_from_camera[a];
      const Rigid3d& pb = poses.world_from_camera[b];
      if ((pa.translation() - pb.translation()).norm() < 1.5 &&
          pa.linear().col(2).dot(pb.linear().col(2)) > std::cos(M_PI / 4)) {
        loops.emplace_back(a, b);
      }
    }
  }
  const int want_loops = loops.empty() ? 0 : count / 2;
  for (int attempts = 0; static_cast<int>(out.size()) < count && attempts < 200 * count; ++attempts) {
    const bool loop = static_cast<int>(out.size()) < want_loops;
    int a, b;
    if (loop) {
      std::tie(a, b) = loops[std::uniform_int_distribution<size_t>(0, loops.size() - 1)(rng)];
    } else {
      a = frame(rng);
      b = std::min(n - 1, a + offset(rng));
      if (a == b) continue;
    }
    Correspondence c;
    c.frame_a = a;
    c.frame_b = b;
    const double u = pu(rng), v = pv(rng);
    if (Correspond(renderer, k, poses.world_from_camera[a], poses.world_from_camera[b], u, v, &c)) out.push_back(c);
  }
  return out;
}

PlyPoints SceneSurfaces(const Scene& scene) {
  PlyPoints ply;
  for (const Triangle& t : scene.triangles) {
    const int32_t first = static_cast<int32_t>(ply.positions.size());
    for (const Eigen::Vector3d* v : {&t.a, &t.b, &t.c}) {
      ply.positions.push_back(v->cast<float>());
      ply.normals.push_back(t.normal.cast<float>());
    }
    ply.faces.push_back({first, first + 1, first + 2});
  }
  return ply;
}

Trajectory Simulate(const fs::path& dir, const SimulateOptions& options, bool quiet, bool overwrite) {
  options.Check();
  if (fs::is_directory(dir) && !fs::is_empty(dir)) {
    if (!overwrite) {
      ThrowInputError(dir, "is not empty: give a new or empty folder, or --overwrite to replace the scan in it");
    }
    for (const char* entry : {"rgb", "depth", "rgb.txt", "depth.txt", "groundtruth.txt", "camera-intrinsics.txt",
                              "correspondences.txt", "scene.ply"}) {
      fs::remove_all(dir / entry);
    }
  }
  const Scene scene = BuildScene(options.scene, options.seed);
  WalkOptions walk = options.walk;
  walk.seed = options.seed;
  const Trajectory poses = GenerateWalk(scene, walk);
  EnsureWritableDirectory(dir);
  fs::create_directories(dir / "rgb");
  fs::create_directories(dir / "depth");
  const Renderer renderer(scene);
  std::string rgb_txt = fmt::format("# color images\n# fine2coarse simulate --scene {} --seed {} --frames {}\n",
                                    options.scene, options.seed, walk.frames);
  std::string depth_txt = "# depth maps\n# metres = value / 5000\n";
  Progress progress("simulate", walk.frames, quiet);
  Trajectory stamped;
  std::vector<std::string> names(walk.frames);
  // Each frame's colour moment: an even draw in [-offset, offset] from the depth's, from the
  // seed and the frame alone.
  std::vector<double> color_offset_s(walk.frames, 0.0);
  std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> world_from_color(poses.world_from_camera.begin(),
                                                                           poses.world_from_camera.end());
  if (options.color_offset_ms > 0) {
    std::mt19937_64 rng(options.seed * 7919ULL + 17);
    std::uniform_real_distribution<double> draw(-options.color_offset_ms * 1e-3, options.color_offset_ms * 1e-3);
    for (int i = 0; i < walk.frames; ++i) {
      color_offset_s[i] = draw(rng);
      world_from_color[i] = PoseAt(poses, poses.timestamps[i] + color_offset_s[i]);
    }
  }
  for (int i = 0; i < walk.frames; ++i) {
    const double t = 1.0 + poses.timestamps[i];  // TUM-like positive stamps
    names[i] = fmt::format("{:.6f}", t);
    stamped.Add(t, poses.world_from_camera[i]);
    rgb_txt += fmt::format("{:.6f} rgb/{}.png\n", t + color_offset_s[i], names[i]);
    depth_txt += fmt::format("{} depth/{}.png\n", names[i], names[i]);
  }
  // Frames in parallel: PNG encoding is single-threaded and costs as much as rendering.
  // Each frame's noise depends only on its index, so the bytes do not depend on the order.
  tbb::parallel_for(0, walk.frames, [&](int i) {
    const uint64_t noise_seed = options.seed * 1000003ULL + i;
    const RenderedView view =
        renderer.Render(options.intrinsics, poses.world_from_camera[i], options.sensor, noise_seed);
    cv::Mat depth16;
    view.depth.convertTo(depth16, CV_16U, 5000.0);
    WritePngFile(dir / "rgb" / (names[i] + ".png"),
                 color_offset_s[i] == 0
                     ? view.color
                     : renderer.Render(options.intrinsics, world_from_color[i], options.sensor, noise_seed).color);
    WritePngFile(dir / "depth" / (names[i] + ".png"), depth16);
    progress.Advance();
  });
  progress.Finish();
  const CameraIntrinsics& k = options.intrinsics;
  WriteFileAtomic(dir / "camera-intrinsics.txt", fmt::format("{} 0 {}\n0 {} {}\n0 0 1\n", k.fx, k.cx, k.fy, k.cy));
  WriteTumTrajectory(dir / "groundtruth.txt", stamped);
  WritePly(dir / "scene.ply", SceneSurfaces(scene));
  WriteCorrespondences(dir / "correspondences.txt",
                       SampleCorrespondences(scene, renderer, k, poses, options.correspondences, options.seed));
  // The lists last: a folder with rgb.txt is complete.
  WriteFileAtomic(dir / "depth.txt", depth_txt);
  WriteFileAtomic(dir / "rgb.txt", rgb_txt);
  return stamped;
}

}  // namespace f2c::sim
