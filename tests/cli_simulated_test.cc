// Simulated scans through the command line: simulate, register and evaluate, with the
// truth the simulator knows.

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "f2c/io/trajectory.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"
#include "tests/cli_helpers.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;
using namespace cli_test;

// An object scan (simulate --scene object): the camera circles a table of curved and
// cluttered objects, walls out of the sensor's reach. The refinement makes T0 better, by
// the trajectory and by the ground-truth correspondences, and its self-check agrees.
TEST(Cli, RegisterRefinesASimulatedObjectScan) {
  const fs::path dir = testing::FreshTempDir("cli_object");
  // 70 frames (measured: ATE 0.0076 -> 0.0038 m, correspondence RMSE 0.0078 -> 0.0046 m).
  ASSERT_EQ(RunCli("simulate --scene object --frames 70 --seed 2 -q -o " + (dir / "scan").string()).code, 0);
  const Result r = RunCli("register " + (dir / "scan").string() + " -q --no-mesh -o " + (dir / "out").string());
  ASSERT_EQ(r.code, 0) << r.output;
  // The self-check's record: every iteration's, the run's (which kept the result), the report's line.
  const nlohmann::json refine = nlohmann::json::parse(ReadFileToString(dir / "out" / "run.json"))["stages"]["refine"];
  for (const nlohmann::json& it : refine["iterations"]) {
    EXPECT_GT(it["self_check"]["before"]["points"].get<int>(), 1000);
    EXPECT_EQ(it["self_check"]["undone"].get<bool>(), false);
  }
  EXPECT_EQ(refine["self_check_undone_iterations"].get<int>(), 0);
  EXPECT_LT(refine["self_check"]["after"]["rms_m"].get<double>(),
            refine["self_check"]["before"]["rms_m"].get<double>());
  EXPECT_FALSE(refine["self_check"]["undone"].get<bool>());
  EXPECT_NE(ReadFileToString(dir / "out" / "report.html").find("0 iterations undone"), std::string::npos);
  auto measure = [&](const std::string& name) {
    const Result e = RunCli(
        "evaluate --json --estimate " + (dir / "out" / name).string() + " --ground-truth " + (dir / "scan").string(),
        " 2>/dev/null");
    EXPECT_EQ(e.code, 0);
    const nlohmann::json j = nlohmann::json::parse(e.output);
    return std::pair(j["ate_m"]["rmse"].get<double>(), j["correspondences"]["distance_m"]["rmse"].get<double>());
  };
  const auto [t0_ate, t0_corr] = measure("trajectory_t0.txt");
  const auto [ate, corr] = measure("trajectory.txt");
  EXPECT_LT(ate, 0.7 * t0_ate);
  EXPECT_LT(corr, 0.7 * t0_corr);
}

// Colour taken up to 15 ms before or after depth (simulate --color-offset, as TUM's
// unsynchronised Kinect streams): frames carry their depth's stamps, and referring what colour
// measured to the depth's moment (--sync-color on, the default) lowers the refined ATE
// (measured on 90-frame apartment walks: seed 0 0.0041 -> 0.0020 m, seed 1 0.0047 -> 0.0031).
TEST(Cli, ColourTakenAtAnotherMomentIsReferredToTheDepths) {
  const fs::path dir = testing::FreshTempDir("cli_moments");
  const fs::path scan = dir / "scan";
  ASSERT_EQ(RunCli("simulate --scene apartment --frames 60 --seed 0 --color-offset 15 -q -o " + scan.string()).code, 0);
  const auto stamps = [](const fs::path& list) {
    std::vector<double> out;
    std::istringstream in(ReadFileToString(list));
    for (std::string line; std::getline(in, line);) {
      if (!line.empty() && line[0] != '#') out.push_back(std::stod(line));
    }
    return out;
  };
  const std::vector<double> color = stamps(scan / "rgb.txt"), depth = stamps(scan / "depth.txt");
  ASSERT_EQ(color.size(), 60u);
  ASSERT_EQ(depth.size(), 60u);
  double widest = 0;
  for (size_t i = 0; i < color.size(); ++i) widest = std::max(widest, std::abs(color[i] - depth[i]));
  EXPECT_LE(widest, 0.015 + 1e-6);
  EXPECT_GT(widest, 0.010);
  const auto ate = [&](const std::string& sync) {
    const fs::path out = dir / ("out_" + sync);
    const Result r =
        RunCli("register " + scan.string() + " -q --no-mesh --no-report --sync-color " + sync + " -o " + out.string());
    EXPECT_EQ(r.code, 0) << r.output;
    EXPECT_EQ(ReadTumTrajectory(out / "trajectory.txt").timestamps, depth);  // the depth's moments
    const Result e =
        RunCli("evaluate --json --estimate " + (out / "trajectory.txt").string() + " --ground-truth " + scan.string(),
               " 2>/dev/null");
    EXPECT_EQ(e.code, 0);
    return nlohmann::json::parse(e.output)["ate_m"]["rmse"].get<double>();
  };
  const double synced = ate("on"), unsynced = ate("off");
  EXPECT_LT(synced, 0.8 * unsynced);
}

}  // namespace
}  // namespace f2c
