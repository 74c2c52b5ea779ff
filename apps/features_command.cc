// fine2coarse features: planar proxies and plane/edge features of every frame.

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <cstdio>
#include <memory>

#include "apps/commands.h"
#include "f2c/io/image_write.h"
#include "f2c/pipeline/outputs.h"
#include "apps/feature_views.h"
#include "apps/fields_cli.h"
#include "f2c/features/feature_set.h"
#include "f2c/io/image.h"
#include "f2c/io/ply.h"
#include "f2c/util/error.h"
#include "f2c/util/fields_json.h"
#include "f2c/util/file.h"

namespace f2c::app {
namespace fs = std::filesystem;
using nlohmann::json;

int RunFeatures(const FeaturesArgs& args) {
  args.features.Check();  // before any file is read
  const fs::path out = args.output;
  const RgbdSequence seq = ReadSequence(args.input, args.io);  // a bad input leaves no output folder
  const OutputFolder output_folder(out);                       // a run stopped by an error leaves no empty folders
  spdlog::info("{}: {} layout, {} frames", args.input, LayoutName(seq.layout), seq.frames.size());
  FeatureRun run;
  run.quiet = args.quiet;
  run.cache_file = out / "features.f2cf";  // the output, reused by the next run with the same inputs
  FeatureTimings timings;
  const FeatureSet set = ExtractFeatures(seq, args.features, run, &timings);
  const int n = static_cast<int>(seq.frames.size());
  if (args.images || args.ply) {
    if (args.images) fs::create_directories(out / "images");
    if (args.ply) fs::create_directories(out / "ply");
    const CameraIntrinsics& k = *seq.intrinsics;
    tbb::parallel_for(0, n, [&](int i) {
      const std::string name = fmt::format("{:06d}", i);
      if (args.ply) WritePly(out / "ply" / (name + ".ply"), FeaturesToPly(set.frames[i]));
      if (args.images) {
        // The picture needs the grid and labels, which the cache does not keep: recompute.
        FeatureDebug debug;
        const FrameFeatures f = ExtractFrameFeatures(LoadDepthMeters(seq, seq.frames[i]), k, args.features, &debug);
        const fs::path path = out / "images" / (name + ".png");
        WritePngFile(path, DrawFeatures(f, debug, k));
      }
    });
  }
  const json stats = FeatureStatistics(set);
  const json report = {{"input", fs::absolute(args.input).string()},
                       {"layout", LayoutName(seq.layout)},
                       {"frames", n},
                       {"versions", Versions()},
                       {"options", {{"io", FieldsToJson(args.io)}, {"features", FieldsToJson(args.features)}}},
                       {"timings", ToJson(timings, n)},
                       {"statistics", stats}};
  WriteFileAtomic(out / "features.json", report.dump(2) + "\n");
  std::printf("wrote %s (%d frames)%s%s, features.json\n", run.cache_file.string().c_str(), n,
              args.images ? ", images/" : "", args.ply ? ", ply/" : "");
  std::printf("per frame:");
  for (const auto& [type, count] : stats["per_frame"].items())
    std::printf(" %s %.1f", type.c_str(), count.get<double>());
  std::printf("\n%d frames computed, %d from cache; extraction %.2f ms per frame per core\n", timings.frames_computed,
              timings.frames_cached,
              timings.frames_computed ? 1000.0 * timings.extract / timings.frames_computed : 0.0);
  return 0;
}

Subcommand AddFeaturesCommand(CLI::App* app) {
  auto args = std::make_shared<FeaturesArgs>();
  CLI::App* cmd = app->add_subcommand("features",
                                      "extract planar proxies and plane/edge features of every frame into "
                                      "OUTDIR/features.f2cf (reused when inputs and options match) and features.json");
  cmd->add_option("INPUT", args->input, "dataset folder, .conf, or a recording (.sens, ROS 1 or 2 bag)")->required();
  cmd->add_option("-o,--output", args->output, "output folder")->required();
  AddFieldFlags(cmd, &args->io);
  AddFieldFlags(cmd, &args->features);
  cmd->add_flag("--images", args->images, "also draw each frame's proxies and features to OUTDIR/images/");
  cmd->add_flag("--ply", args->ply, "also write each frame's features as points to OUTDIR/ply/");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress output");

  return {cmd, [args] {
            if (args->quiet) spdlog::set_level(spdlog::level::warn);
            return RunFeatures(*args);
          }};
}

}  // namespace f2c::app
