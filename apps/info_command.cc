// fine2coarse info: what a dataset folder holds.

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cstdio>
#include <memory>

#include "apps/commands.h"
#include "apps/common.h"
#include "f2c/io/image.h"

namespace f2c::app {

int RunInfo(const InfoArgs& args) {
  const RgbdSequence seq = ReadSequence(args.input, args.io);
  std::printf("input        %s\n", args.input.c_str());
  std::printf("layout       %s\n", LayoutName(seq.layout).c_str());
  std::printf("frames       %zu (%.3f .. %.3f s)\n", seq.frames.size(), seq.frames.front().timestamp,
              seq.frames.back().timestamp);
  if (seq.intrinsics) {
    const CameraIntrinsics& k = *seq.intrinsics;
    std::printf("intrinsics   fx %.3f fy %.3f cx %.3f cy %.3f (%s)\n", k.fx, k.fy, k.cx, k.cy,
                seq.intrinsics_source.c_str());
  } else {
    std::printf("intrinsics   none in the folder: pass --intrinsics (tum-fr1, tum-fr2, tum-fr3, "
                "primesense, or fx,fy,cx,cy)\n");
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
  CLI::App* cmd = app->add_subcommand("info", "what a dataset folder holds: layout, frames, "
                                                  "intrinsics, depth range, ground truth");
  cmd->add_option("INPUT", args->input, "dataset folder or .conf")->required();
  AddFrameSelection(cmd, &args->io);
  return {cmd, [args] { return RunInfo(*args); }};
}

}  // namespace f2c::app
