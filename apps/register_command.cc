// fine2coarse register: a dataset folder to camera poses.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>
#include <set>
#include <sstream>
#include <vector>

#include "apps/commands.h"
#include "apps/fields_cli.h"
#include "apps/help_format.h"
#include "f2c/pipeline/outputs.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"
#include "f2c/util/timer.h"

namespace f2c::app {
namespace fs = std::filesystem;

namespace {

// What the command line says in words that RegisterArgs holds as stages to run.
struct RegisterFlags {
  bool no_cache = false, no_features = false, no_mesh = false, no_report = false;
  std::string stop_after = "refine";
  Preset preset = Preset::kDefault;
};

// What `register --help` lists: the input and its frames, what to write, how to run. Every
// other option is in --help-all.
const std::vector<HelpSection> kEverydayOptions = {
    {"Input", {"output", "intrinsics", "every", "first", "last", "sequence", "min-depth", "max-depth"}},
    {"Output", {"voxel-size", "no-mesh", "no-report", "save-iterations", "no-cache", "write-config"}},
    {"Registration", {"preset", "stop-after", "initial-trajectory", "structure", "self-check", "seed"}},
    {"Running", {"threads", "quiet", "help"}},
};

}  // namespace

int RunRegister(const RegisterArgs& args) {
  Timer total;
  const fs::path out = args.output;
  // The input first (a bad one leaves no output folder behind), then the start the
  // refinement is given, then the output folder: all fail in seconds, before minutes of work.
  RgbdSequence seq = ReadSequence(args.input, args.io);
  const double read_s = total.Seconds();
  RegisterOptions options = args.options;
  if (!args.initial_trajectory.empty()) {
    options.initial_poses = PosesFor(seq, args.initial_trajectory, args.io);
    options.initial_name = args.initial_trajectory;
  }
  if (!args.write_config.empty()) {  // only for a run that can start: options and input checked
    RequireIntrinsics(seq);
    WriteFileAtomic(args.write_config, args.config_text);
    spdlog::info("options written to {}", args.write_config);
  }
  const OutputFolder output_folder(out);  // a run stopped by an error leaves no empty folders
  spdlog::info("{}: {} layout, {} frames", args.input, LayoutName(seq.layout), seq.frames.size());
  if (args.use_cache) options.cache_dir = out / "cache";
  RegisterResult result = Register(std::move(seq), options);
  result.read_s = read_s;
  result.total_s = total.Seconds();
  OutputOptions outputs;
  outputs.report = args.write_report;
  outputs.iterations = args.save_iterations;
  outputs.input = fs::absolute(args.input).string();
  outputs.io = args.io;
  const std::vector<std::string> names = WriteOutputs(out, result, options, outputs);
  std::string written;
  for (size_t i = 1; i < names.size(); ++i) written += ", " + names[i];
  std::printf("wrote %s (TUM; %s)%s, run.json\n", (out / names.front()).string().c_str(),
              result.refine ? "refined" : "T0", written.c_str());
  const size_t frames = result.sequence.frames.size();
  std::printf("%zu frames in %.1f s (%.1f frames/s)\n", frames, total.Seconds(), frames / total.Seconds());
  return 0;
}

Subcommand AddRegisterCommand(CLI::App* app) {
  auto args = std::make_shared<RegisterArgs>();
  CLI::App* cmd = app->add_subcommand(
      "register",
      "align the frames (keyframe odometry: tracking, SIFT + 3D RANSAC, ICP fallback) into T0, refine "
      "it fine-to-coarse, fuse a mesh and write OUTDIR/trajectory.txt (TUM), trajectory.log, "
      "trajectory.conf, trajectory_t0.txt, mesh.ply, odometry.json, run.json");
  cmd->add_option(
         "INPUT", args->input,
         "dataset folder (TUM, 7-Scenes/3DMatch, Redwood/Open3D, SUN3D), .conf, or a recording (.sens, ROS 1 or 2 bag)")
      ->required();
  cmd->add_option("-o,--output", args->output, "output folder")->required();
  AddFieldFlags(cmd, &args->io);
  AddFieldFlags(cmd, &args->options.odometry);  // odometry/odometry.h
  AddFieldFlags(cmd, &args->options.features);
  auto flags = std::make_shared<RegisterFlags>();
  cmd->add_option("--stop-after", flags->stop_after,
                  "odometry: T0 is the result (no refinement, no mesh); refine: the fine-to-coarse refinement, "
                  "then the mesh")
      ->check(CLI::IsMember({"odometry", "refine"}))
      ->capture_default_str();
  cmd->add_option_function<std::string>(
         "--preset", [flags](const std::string& text) { flags->preset = FromName<Preset>(text, "--preset"); },
         "fast: a 2 cm mesh, 3 polish iterations, no self-check (faster, a little less accurate); default; paper: "
         "the paper's algorithm only (no SIFT loops, E_V, polish iterations, information-weighted E_L or "
         "self-check). Options given beside it win")
      ->default_str("default");
  AddFieldFlags(cmd, &args->options.refine);  // refine/refine.h
  auto write_config = std::make_shared<std::string>();
  cmd->add_option("--write-config", *write_config,
                  "write this run's options (all of them) to FILE as TOML, for --config")
      ->group("Output");
  cmd->add_option("--initial-trajectory", args->initial_trajectory,
                  "refine from these poses instead of T0: a trajectory (TUM by time stamp, .log by frame id, .conf by "
                  "image name), or a dataset folder's ground truth")
      ->type_name("FILE")
      ->group("Refinement: windows (paper 4.2)");
  cmd->add_flag("--save-iterations", args->save_iterations,
                "write each refinement iteration's trajectory to OUTDIR/iterations/");
  AddFieldFlags(cmd, &args->options.fusion);
  cmd->add_flag("--no-mesh", flags->no_mesh, "do not fuse the frames into OUTDIR/mesh.ply");
  cmd->add_flag("--no-report", flags->no_report, "do not write OUTDIR/report.html");
  cmd->add_flag("--no-features", flags->no_features, "skip the feature extraction, and so the refinement (T0 only)");
  cmd->add_flag("--no-cache", flags->no_cache, "ignore and do not write OUTDIR/cache");
  cmd->add_option("--threads", args->options.threads,
                  "worker threads (0: all cores, at most 1024; results are the same for any)")
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->options.quiet, "no progress output");

  cmd->formatter(std::make_shared<EverydayHelp>(kEverydayOptions));

  return {cmd, [app, cmd, args, flags, write_config] {
            ApplyPreset(flags->preset, &args->options, [cmd](const std::string& flag) { return cmd->count(flag) > 0; });
            RegisterOptions& options = args->options;
            options.extract_features = !flags->no_features;
            options.refine_poses = flags->stop_after == "refine";
            options.fuse_mesh = !flags->no_mesh && flags->stop_after != "odometry";
            options.keep_iterations = args->save_iterations;
            args->write_report = !flags->no_report;
            args->use_cache = !flags->no_cache;
            // Every stage's options, once, before the input is read or minutes of odometry run.
            options.CheckStart(!args->initial_trajectory.empty());
            args->io.Check();
            options.Check();
            if (!write_config->empty()) {
              // Every register option with its value (defaults too), so the file reproduces the
              // run; but the preset's own values are left to the preset (written, they would count
              // as given, and the preset would not set them when the file is read). The other
              // subcommands' defaults stay out: the file is this run's, and read with another
              // subcommand it changes nothing there.
              std::set<std::string> left_to_preset = {"write-config"};
              for (const PresetSetting& s : PresetSettings(flags->preset)) {
                const CLI::Option* opt = cmd->get_option(s.flag);
                if (opt->count() == 0) left_to_preset.insert(opt->get_single_name());
              }
              std::string text;
              std::istringstream lines(app->config_to_str(true, false));
              for (std::string line; std::getline(lines, line);) {
                if (line.rfind("register.", 0) != 0) continue;
                const std::string key = line.substr(9, line.find('=') - 9);  // "register.polish-iterations=6"
                if (!left_to_preset.count(key)) text += line + "\n";
              }
              args->write_config = *write_config;
              args->config_text = text;
            }
            if (options.quiet) spdlog::set_level(spdlog::level::warn);
            return RunRegister(*args);
          }};
}

}  // namespace f2c::app
