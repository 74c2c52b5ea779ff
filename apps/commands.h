#pragma once
// The subcommands of the fine2coarse CLI, one file each (apps/<name>_command.cc). Each adds
// its options to the CLI and returns the function that runs it once the command line is
// parsed; that returns the process exit code. Bad input propagates as InputError, which
// main() turns into one line and exit 1.

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "f2c/eval/trajectory_error.h"
#include "f2c/features/depth_features.h"
#include "f2c/fusion/fuse.h"
#include "f2c/io/sequence.h"
#include "f2c/odometry/odometry.h"
#include "f2c/pipeline/register.h"
#include "f2c/refine/refine.h"
#include "f2c/sim/simulate.h"

namespace f2c::app {

struct Subcommand {
  CLI::App* cli = nullptr;
  std::function<int()> run;
};
Subcommand AddRegisterCommand(CLI::App* app);
Subcommand AddFeaturesCommand(CLI::App* app);
Subcommand AddEvaluateCommand(CLI::App* app);
Subcommand AddSimulateCommand(CLI::App* app);
Subcommand AddDemoCommand(CLI::App* app);
Subcommand AddInfoCommand(CLI::App* app);
Subcommand AddFuseCommand(CLI::App* app);

// The subcommands' arguments and bodies (the demo runs simulate, register and evaluate).

struct RegisterArgs {
  std::string input;
  std::string output;
  IoOptions io;
  RegisterOptions options;  // the stages' options (pipeline/register.h)
  // The refinement starts from these poses instead of T0 (--initial-trajectory; empty: T0).
  std::string initial_trajectory;
  bool save_iterations = false;  // OUTDIR/iterations/iteration_NN.txt
  bool write_report = true;      // OUTDIR/report.html (--no-report: off)
  bool use_cache = true;         // OUTDIR/cache (--no-cache: off)
  // --write-config: this file gets `config_text` once the input has been read and checked.
  std::string write_config;
  std::string config_text;
};
int RunRegister(const RegisterArgs& args);

struct FeaturesArgs {
  std::string input;
  std::string output;
  IoOptions io;
  FeatureOptions features;
  bool images = false;  // OUTDIR/images/NNNNNN.png: proxies and features drawn per frame
  bool ply = false;     // OUTDIR/ply/NNNNNN.ply: feature points per frame, camera coordinates
  bool quiet = false;
};
int RunFeatures(const FeaturesArgs& args);

struct EvaluateArgs {
  std::string estimate;
  std::string ground_truth;
  bool json = false;
  EvaluationOptions evaluation;  // --max-time-difference, --drift-min-seconds
  // Ground-truth correspondences (the authors' format); empty: the dataset folder's
  // correspondences.txt when there is one.
  std::string correspondences;
  std::string mesh;               // a mesh fused with the estimate's poses, to measure
  std::string true_surfaces;      // PLY of the true surfaces; default: the folder's scene.ply
  std::string report;             // an HTML page with the plots, when set
  std::string name = "estimate";  // the estimate's name in the report
  std::vector<std::string> also;  // NAME=FILE: further trajectories drawn in the report
  IoOptions io;                   // frame selection (frame ids of .log/.conf estimates) and intrinsics
};
int RunEvaluate(const EvaluateArgs& args);

struct SimulateArgs {
  std::string output;
  sim::SimulateOptions options;  // --scene, --frames, --seed, --correspondences, --depth-distortion
  bool exact = false;            // no sensor noise
  bool quiet = false;
  bool overwrite = false;  // replace the scan in a folder that holds one
};
int RunSimulate(const SimulateArgs& args);

struct DemoArgs {
  std::string output = "fine2coarse-demo";
  int frames = 900;  // 30 s of walking through several rooms and back; about a minute all told
  uint64_t seed = 0;
};
int RunDemo(const DemoArgs& args);

struct FuseArgs {
  std::string input;
  std::string trajectory;
  std::string output;  // the .ply
  IoOptions io;
  FusionOptions fusion;
  bool pictures = false;  // <mesh>_top.png and <mesh>_view.png beside the mesh
  bool json = false;
  bool quiet = false;
};
int RunFuse(const FuseArgs& args);

struct InfoArgs {
  std::string input;
  IoOptions io;
  bool json = false;  // the frame list and facts as JSON
};
int RunInfo(const InfoArgs& args);

}  // namespace f2c::app
