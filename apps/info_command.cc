// fine2coarse info: what a dataset folder holds.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>

#include "apps/commands.h"
#include "apps/fields_cli.h"
#include "f2c/io/image.h"

namespace f2c::app {

namespace {

// The selected frames and what a script needs to read them itself (bench/run_benchmarks.sh
// hands them to a peer): one JSON object on stdout.
nlohmann::json CameraJson(const CameraIntrinsics& k) {
  return {{"fx", k.fx}, {"fy", k.fy}, {"cx", k.cx}, {"cy", k.cy}, {"width", k.width}, {"height", k.height}};
}

int PrintJson(const RgbdSequence& seq) {
  nlohmann::json frames = nlohmann::json::array();
  for (const RgbdFrame& f : seq.frames) {
    nlohmann::json frame = {
        {"timestamp", f.timestamp}, {"color", f.color_path.string()}, {"depth", f.depth_path.string()}};
    // Images inside a recording: where they lie in it.
    if (f.color_embedded) frame["color_bytes"] = {f.color_embedded->offset, f.color_embedded->size};
    if (f.depth_embedded) frame["depth_bytes"] = {f.depth_embedded->offset, f.depth_embedded->size};
    frames.push_back(frame);
  }
  nlohmann::json j = {{"input", seq.root.string()},
                      {"layout", LayoutName(seq.layout)},
                      {"depth_meters_per_unit", seq.depth_scale},
                      {"depth_encoding", seq.depth_encoding == DepthEncoding::kSun3dBitRotated ? "sun3d" : "plain"},
                      {"ground_truth", seq.ground_truth ? seq.ground_truth_source.string() : ""},
                      {"frames", frames}};
  if (!seq.streams.empty()) j["streams"] = seq.streams;
  if (seq.intrinsics) {
    j["intrinsics"] = CameraJson(*seq.intrinsics);
    j["intrinsics"]["distortion"] = seq.intrinsics->distortion;
    j["intrinsics"]["source"] = seq.intrinsics_source;
  } else {
    j["intrinsics"] = nullptr;
  }
  if (seq.color_camera) {
    const Eigen::Matrix4d m = seq.color_camera->color_from_depth.matrix();
    std::vector<double> rows;  // row-major, as the .sens and .log files hold matrices
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) rows.push_back(m(r, c));
    }
    j["color_camera"] = CameraJson(seq.color_camera->intrinsics);
    j["color_camera"]["color_from_depth"] = rows;
  }
  std::printf("%s\n", j.dump(2).c_str());
  return 0;
}

}  // namespace

int RunInfo(const InfoArgs& args) {
  const RgbdSequence seq = ReadSequence(args.input, args.io);
  if (args.json) return PrintJson(seq);
  std::printf("input        %s\n", args.input.c_str());
  std::printf("layout       %s\n", LayoutName(seq.layout).c_str());
  std::printf("frames       %zu (%.3f .. %.3f s)\n", seq.frames.size(), seq.frames.front().timestamp,
              seq.frames.back().timestamp);
  for (const std::string& stream : seq.streams) std::printf("stream       %s\n", stream.c_str());
  if (seq.intrinsics) {
    const CameraIntrinsics& k = *seq.intrinsics;
    std::printf("intrinsics   fx %.3f fy %.3f cx %.3f cy %.3f (%s)\n", k.fx, k.fy, k.cx, k.cy,
                seq.intrinsics_source.c_str());
    if (k.HasDistortion()) {
      std::printf("distortion   k1 %g k2 %g p1 %g p2 %g k3 %g (frames are resampled to the pinhole model)\n",
                  k.distortion[0], k.distortion[1], k.distortion[2], k.distortion[3], k.distortion[4]);
    }
    if (seq.color_camera) {
      const CameraIntrinsics& c = seq.color_camera->intrinsics;
      const Rigid3d& e = seq.color_camera->color_from_depth;
      std::printf(
          "depth camera %dx%d; colour camera %dx%d, fx %.3f fy %.3f cx %.3f cy %.3f, %.1f mm and %.2f deg "
          "from the depth camera (colour is resampled into the depth camera)\n",
          k.width, k.height, c.width, c.height, c.fx, c.fy, c.cx, c.cy, 1000 * e.translation().norm(),
          Eigen::AngleAxisd(e.linear()).angle() * 180 / M_PI);
    }
  } else {
    std::printf(
        "intrinsics   none in the folder: pass --intrinsics (tum-fr1, tum-fr2, tum-fr3, "
        "primesense, or fx,fy,cx,cy[,k1,k2,p1,p2[,k3]])\n");
  }
  std::printf("depth        %s, %.6g m per unit, invalid values %s\n",
              seq.depth_encoding == DepthEncoding::kSun3dBitRotated ? "SUN3D bit-rotated" : "plain 16-bit",
              seq.depth_scale, fmt::format("{}", fmt::join(seq.invalid_depth_values, ", ")).c_str());
  // Depth range measured on the first frame.
  const cv::Mat depth = LoadDepthMeters(seq, seq.frames.front());
  double lo = 1e9, hi = 0;
  int valid = 0;
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      const float z = depth.at<float>(v, u);
      if (z > 0) {
        lo = std::min<double>(lo, z);
        hi = std::max<double>(hi, z);
        ++valid;
      }
    }
  }
  std::printf("depth range  %.3f .. %.3f m in frame 0 (%.1f%% of pixels valid)\n", valid ? lo : 0.0, hi,
              100.0 * valid / depth.total());
  if (seq.ground_truth) {
    std::printf("ground truth %zu poses (%s)\n", seq.ground_truth->size(), seq.ground_truth_source.string().c_str());
  } else {
    std::printf("ground truth none\n");
  }
  return 0;
}

Subcommand AddInfoCommand(CLI::App* app) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app->add_subcommand("info",
                                      "what a dataset folder holds: layout, frames, "
                                      "intrinsics, depth range, ground truth");
  cmd->add_option("INPUT", args->input, "dataset folder, .conf, or a recording (.sens, ROS 1 or 2 bag)")->required();
  AddFieldFlags(cmd, &args->io);
  cmd->add_flag("--json", args->json,
                "print JSON instead: layout, intrinsics, depth scale, ground truth and every selected frame's time "
                "stamp and files");
  return {cmd, [args] { return RunInfo(*args); }};
}

}  // namespace f2c::app
