#include "f2c/fusion/fuse.h"

#include <fmt/format.h>

#include <nlohmann/json.hpp>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "f2c/io/image.h"
#include "f2c/util/error.h"
#include "f2c/util/progress.h"
#include "f2c/util/timer.h"

namespace f2c {

void FusionOptions::Check() const { CheckFields(*this); }

std::vector<std::optional<Rigid3d>> PosesForFrames(const RgbdSequence& seq, const Trajectory& t,
                                                   double max_time_difference, const std::filesystem::path& file) {
  const size_t n = seq.frames.size();
  std::vector<std::optional<Rigid3d>> poses(n);
  if (!t.has_timestamps) {
    const std::vector<long> frames = FramesOfPoses(t, FrameNames(seq), file);
    for (size_t i = 0; i < frames.size(); ++i) {
      if (frames[i] >= 0) poses[frames[i]] = t.world_from_camera[i];
    }
  } else {
    // Both sorted by time: one merge-like pass.
    std::vector<size_t> order(t.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return t.timestamps[a] < t.timestamps[b]; });
    for (size_t k = 0; k < n; ++k) {
      const double time = seq.frames[k].timestamp;
      const auto it =
          std::lower_bound(order.begin(), order.end(), time, [&](size_t i, double x) { return t.timestamps[i] < x; });
      double best = max_time_difference;
      for (auto c : {it, it == order.begin() ? it : it - 1}) {
        if (c == order.end()) continue;
        const double dt = std::abs(t.timestamps[*c] - time);
        if (dt <= best) best = dt, poses[k] = t.world_from_camera[*c];
      }
    }
  }
  if (std::none_of(poses.begin(), poses.end(), [](const auto& p) { return p.has_value(); })) {
    ThrowInputError(file, fmt::format("no pose matches a frame of {} (time stamps {} s apart at most)",
                                      seq.root.string(), max_time_difference));
  }
  return poses;
}

FusionResult FuseTsdf(const RgbdSequence& seq, const std::vector<std::optional<Rigid3d>>& poses,
                      const FusionOptions& options, bool quiet) {
  options.Check();
  RequireIntrinsics(seq);
  F2C_CHECK(poses.size() == seq.frames.size(), "one pose slot per frame");
  Timer wall;
  FusionResult result;
  FusionTimings& t = result.timings;
  std::vector<int> frames;
  for (int k = 0, with_pose = 0; k < static_cast<int>(poses.size()); ++k) {
    if (!poses[k]) {
      ++t.frames_without_pose;
      continue;
    }
    if (with_pose++ % options.every == 0) frames.push_back(k);
  }
  TsdfVolume volume(options.tsdf);
  const CameraIntrinsics& k = *seq.intrinsics;
  Progress progress("fusion", static_cast<long>(frames.size()), quiet);
  struct Decoded {
    int frame = -1;
    cv::Mat depth, color;
  };
  std::atomic<int64_t> decode_ns{0};
  size_t next = 0;
  Timer integrate_wall;
  // Frames decode in parallel ahead of the integration, which takes them in order (each
  // integration is itself parallel over blocks), so the volume is the same for any thread count.
  tbb::parallel_pipeline(2 * tbb::this_task_arena::max_concurrency() + 2,
                         tbb::make_filter<void, int>(tbb::filter_mode::serial_in_order, [&](tbb::flow_control& fc) {
                           if (next >= frames.size()) {
                             fc.stop();
                             return 0;
                           }
                           return frames[next++];
                         }) & tbb::make_filter<int, Decoded>(tbb::filter_mode::parallel, [&](int frame) {
                           Timer timer;
                           Decoded d;
                           d.frame = frame;
                           d.depth = LoadDepthMeters(seq, seq.frames[frame]);
                           d.color = LoadColor(seq, seq.frames[frame], d.depth.size());
                           decode_ns += static_cast<int64_t>(timer.Seconds() * 1e9);
                           return d;
                         }) & tbb::make_filter<Decoded, void>(tbb::filter_mode::serial_in_order, [&](Decoded d) {
                           volume.Integrate(d.depth, d.color, k, *poses[d.frame]);
                           progress.Advance();
                         }));
  progress.Finish();
  t.integrate = integrate_wall.Seconds();
  t.decode_cpu = decode_ns * 1e-9;
  t.frames_fused = static_cast<int>(frames.size());
  t.blocks = volume.BlockCount();
  t.volume_bytes = volume.MemoryBytes();
  Timer mesh_timer;
  result.mesh = ExtractMesh(volume, options.mesh);
  t.mesh = mesh_timer.Seconds();
  t.wall = wall.Seconds();
  return result;
}

nlohmann::json ToJson(const FusionTimings& t, const PlyPoints& mesh) {
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

}  // namespace f2c
