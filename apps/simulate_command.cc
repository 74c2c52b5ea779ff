// fine2coarse simulate and demo: synthetic multi-room scans with exact ground truth, and the
// no-download demo that simulates, registers and evaluates one.

#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>

#include "apps/commands.h"
#include "apps/fields_cli.h"
#include "f2c/sim/simulate.h"
#include "f2c/util/timer.h"

namespace f2c::app {
namespace fs = std::filesystem;

int RunSimulate(const SimulateArgs& args) {
  sim::SimulateOptions options = args.options;
  if (args.exact) {  // no noise, holes or blur; the distortion is a flag of its own
    options.sensor = sim::SensorOptions::Exact();
    options.sensor.radial_distortion = args.options.sensor.radial_distortion;
  }
  Timer timer;
  const Trajectory poses = sim::Simulate(args.output, options, args.quiet, args.overwrite);
  double path = 0;
  for (size_t i = 1; i < poses.size(); ++i) {
    path += (poses.world_from_camera[i].translation() - poses.world_from_camera[i - 1].translation()).norm();
  }
  std::printf(
      "wrote %s: %d frames of '%s' (%.1f m of camera path) in %.1f s, TUM layout with "
      "camera-intrinsics.txt, groundtruth.txt, correspondences.txt\n",
      args.output.c_str(), options.walk.frames, options.scene.c_str(), path, timer.Seconds());
  return 0;
}

int RunDemo(const DemoArgs& args) {
  // The demo evaluates its poses, and a rigid alignment needs three.
  if (args.frames < 3 || args.frames > 100000) {
    ThrowInputError("--frames", fmt::format("must be in [3, 100000], got {}", args.frames));
  }
  Timer timer;
  const fs::path root = args.output;
  std::printf("fine2coarse demo: simulating an apartment scan, registering it, fusing a mesh, evaluating it\n");
  SimulateArgs sim_args;
  sim_args.output = (root / "scan").string();
  sim_args.options.scene = "apartment";
  sim_args.options.walk.frames = args.frames;
  sim_args.options.seed = args.seed;
  sim_args.overwrite = true;  // the demo's own folder: a second demo replaces the first
  RunSimulate(sim_args);
  RegisterArgs reg;
  reg.input = sim_args.output;
  reg.output = (root / "registration").string();
  RunRegister(reg);
  EvaluateArgs eval;
  eval.ground_truth = sim_args.output;
  std::printf("\nT0, the odometry alone:\n");
  eval.estimate = (fs::path(reg.output) / "trajectory_t0.txt").string();
  RunEvaluate(eval);
  std::printf("\nrefined fine-to-coarse:\n");
  eval.estimate = (fs::path(reg.output) / "trajectory.txt").string();
  RunEvaluate(eval);
  std::printf(
      "\nscan (TUM layout, ground truth): %s\nposes (TUM, .log, .conf), mesh.ply, run.json: %s\n"
      "demo took %.1f s\n",
      sim_args.output.c_str(), reg.output.c_str(), timer.Seconds());
  return 0;
}

Subcommand AddSimulateCommand(CLI::App* app) {
  auto args = std::make_shared<SimulateArgs>();
  CLI::App* cmd =
      app->add_subcommand("simulate", "render a synthetic multi-room RGB-D scan with exact ground truth (TUM layout)");
  cmd->add_option("-o,--output", args->output, "output folder")->required();
  AddFieldFlags(cmd, &args->options);  // sim/simulate.h
  cmd->add_flag("--exact", args->exact, "no sensor noise, holes or blur");
  cmd->add_flag("--overwrite", args->overwrite,
                "replace the simulated scan in a folder that holds one (without it, a folder that is not empty is "
                "an error)");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress output");

  return {cmd, [args] {
            if (args->quiet) spdlog::set_level(spdlog::level::warn);
            return RunSimulate(*args);
          }};
}

Subcommand AddDemoCommand(CLI::App* app) {
  auto args = std::make_shared<DemoArgs>();
  CLI::App* cmd =
      app->add_subcommand("demo", "no download needed: simulate an apartment scan, register it, evaluate it");
  cmd->add_option("-o,--output", args->output, "output folder")->capture_default_str();
  cmd->add_option("--frames", args->frames, "frames to simulate (3 to 100,000)")->capture_default_str();
  cmd->add_option_function<std::string>(
         "--seed", [seed = &args->seed](const std::string& text) { *seed = ParseUnsigned<uint64_t>(text, "--seed"); },
         "seed")
      ->default_str(std::to_string(args->seed));
  return {cmd, [args] { return RunDemo(*args); }};
}

}  // namespace f2c::app
