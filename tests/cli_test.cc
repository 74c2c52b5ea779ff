// Runs the fine2coarse binary as a user would and checks exit codes, messages and outputs.
// Bad input: cli_bad_input_test.cc.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "f2c/features/feature_set.h"
#include "f2c/io/conf.h"
#include "f2c/io/correspondences.h"
#include "f2c/io/ply.h"
#include "f2c/io/trajectory.h"
#include "f2c/testing/sens_writer.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"
#include "f2c/util/text.h"
#include "tests/cli_helpers.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;
using namespace cli_test;  // the runner and inputs both CLI test files share

TEST(Cli, HelpOnEverySubcommand) {
  for (const char* cmd : {"", "register ", "features ", "fuse ", "evaluate ", "info ", "simulate ", "demo "}) {
    const Result r = RunCli(std::string(cmd) + "--help");
    EXPECT_EQ(r.code, 0) << cmd;
    EXPECT_NE(r.output.find("Usage"), std::string::npos) << r.output;
  }
}

TEST(Cli, RegisterThenEvaluateOnASyntheticSequence) {
  const fs::path dir = SyntheticTum("cli_register", 5);
  const fs::path out = testing::FreshTempDir("cli_register_out");
  const Result r = RunCli("register " + dir.string() + " --intrinsics 525,525,319.5,239.5 -q -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  for (const char* file :
       {"trajectory.txt", "trajectory.log", "trajectory.conf", "odometry.json", "run.json", "mesh.ply"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
  for (const auto& e : fs::directory_iterator(out)) {
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << "left a temporary file";
  }
  // report.html: every section, the plots inline.
  const std::string report = ReadFileToString(out / "report.html");
  for (const char* s : {"<h2>Run</h2>", "<h2>Trajectories</h2>", "<h2>Errors</h2>", "<h2>Mesh</h2>", ">T0</text>",
                        ">final</text>", ">ground truth</text>"}) {
    EXPECT_NE(report.find(s), std::string::npos) << s;
  }
  const Trajectory t = ReadTumTrajectory(out / "trajectory.txt");
  ASSERT_EQ(t.size(), 5u);
  EXPECT_NEAR(t.world_from_camera[4].translation().x(), 0.12, 0.01);  // 4 steps of 3 cm
  const Result e =
      RunCli("evaluate --json --estimate " + (out / "trajectory.txt").string() + " --ground-truth " + dir.string());
  ASSERT_EQ(e.code, 0) << e.output;
  EXPECT_NE(e.output.find("\"ate_m\""), std::string::npos);
  // 5 frames span 0.13 s: no pair is 1 s apart, and so no RPE per second: n/a and null, never
  // a 0 that reads as perfect.
  const nlohmann::json stats = nlohmann::json::parse(e.output);
  EXPECT_EQ(stats["rpe_per_second"]["translation_m"]["count"], 0);
  EXPECT_TRUE(stats["rpe_per_second"]["translation_m"]["rmse"].is_null());
  const Result table =
      RunCli("evaluate --estimate " + (out / "trajectory.txt").string() + " --ground-truth " + dir.string());
  EXPECT_NE(table.output.find(
                "RPE/s translation        m          n/a       n/a       n/a       n/a       n/a       n/a      0"),
            std::string::npos)
      << table.output;
  // The .log estimate carries frame ids; with the dataset as ground truth it evaluates too.
  const Result log =
      RunCli("evaluate --estimate " + (out / "trajectory.log").string() + " --ground-truth " + dir.string());
  EXPECT_EQ(log.code, 0) << log.output;
  EXPECT_NE(log.output.find("5 of 5 poses associated"), std::string::npos) << log.output;
  // The .conf's scan lines name their frames: in reverse order they are the same estimate.
  std::vector<std::string> header, scans;
  for (const TextLine& line : ReadDataLines(out / "trajectory.conf")) {
    (line.text.rfind("scan ", 0) == 0 ? scans : header).push_back(line.text);
  }
  ASSERT_EQ(scans.size(), 5u);
  std::string reversed;
  for (const std::string& line : header) reversed += line + "\n";
  for (auto it = scans.rbegin(); it != scans.rend(); ++it) reversed += *it + "\n";
  WriteFileAtomic(out / "reversed.conf", reversed);
  auto ate = [&](const fs::path& estimate) {
    const Result r = RunCli("evaluate --json --estimate " + estimate.string() + " --ground-truth " + dir.string());
    EXPECT_EQ(r.code, 0) << r.output;
    return nlohmann::json::parse(r.output)["ate_m"]["rmse"].get<double>();
  };
  EXPECT_NEAR(ate(out / "reversed.conf"), ate(out / "trajectory.txt"), 1e-6);
  // The page for the .log estimate (frame ids placed in time), with T0 beside it.
  const Result page_run = RunCli("evaluate --estimate " + (out / "trajectory.log").string() + " --ground-truth " +
                                 dir.string() + " --name final --also T0=" + (out / "trajectory_t0.txt").string() +
                                 " --report " + (out / "eval.html").string());
  ASSERT_EQ(page_run.code, 0) << page_run.output;
  const std::string page = ReadFileToString(out / "eval.html");
  for (const char* s :
       {"<h2>Errors</h2>", "<h2>Top-down slice of the registered points</h2>", ">final</text>", ">T0</text>"}) {
    EXPECT_NE(page.find(s), std::string::npos) << s;
  }
  EXPECT_EQ(page.find(">no data</text>"), std::string::npos);  // every plot drawn, the .log's errors too
  const Result bad = RunCli("evaluate --estimate " + (out / "trajectory.txt").string() + " --ground-truth " +
                            dir.string() + " --also T0 --report " + (out / "bad.html").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_EQ(bad.output, "error: --also: 'T0' is not NAME=FILE\n");
  EXPECT_FALSE(fs::exists(out / "bad.html"));
}

// Keyframe odometry (the default) aligns most frames to a keyframe, but every input frame
// still gets exactly one pose in each output, the same in all three; odometry.json says
// which keyframe each frame was aligned to and how much E_L trusts it.
// A ScanNet .sens recording whose colour comes from a camera of its own (800x600, 2.5 cm
// beside the depth camera) aligns as the folder of the same frames does, and `info` says
// what it found.
TEST(Cli, RegisterASensRecordingAsTheFolderOfItsFrames) {
  const int n = 8;
  const fs::path folder = SyntheticTum("cli_sens_folder", n);
  const Trajectory truth = ReadTumTrajectory(folder / "groundtruth.txt");
  const fs::path dir = testing::FreshTempDir("cli_sens");
  testing::SensOptions o;
  o.color = {600.0, 605.0, 405.0, 297.0, 800, 600};
  o.color_from_depth.translation() = Eigen::Vector3d(-0.025, 0, 0);
  testing::WriteSyntheticSens(dir / "scan.sens", testing::SyntheticScene(), truth.world_from_camera, o);
  const Result info = RunCli("info " + (dir / "scan.sens").string());
  ASSERT_EQ(info.code, 0) << info.output;
  EXPECT_NE(info.output.find("layout       sens"), std::string::npos) << info.output;
  EXPECT_NE(
      info.output.find("colour camera 800x600, fx 600.000 fy 605.000 cx 405.000 cy 297.000, 25.0 mm and 0.00 deg"),
      std::string::npos)
      << info.output;
  auto ate = [&](const std::string& input, const std::string& extra, const fs::path& out) {
    // T0 alone: the odometry is where colour and depth meet; the refinement adds nothing here.
    const Result r = RunCli("register " + input + " -q --no-report --stop-after odometry -o " + out.string() + extra);
    EXPECT_EQ(r.code, 0) << r.output;
    const Result e =
        RunCli("evaluate --json --estimate " + (out / "trajectory.txt").string() + " --ground-truth " + input);
    EXPECT_EQ(e.code, 0) << e.output;
    return nlohmann::json::parse(e.output)["ate_m"]["rmse"].get<double>();
  };
  const double from_folder = ate(folder.string(), " --intrinsics 525,525,319.5,239.5", dir / "folder_out");
  const double from_sens = ate((dir / "scan.sens").string(), "", dir / "sens_out");
  EXPECT_LT(std::abs(from_sens - from_folder), 0.001) << from_sens << " " << from_folder;
  EXPECT_LT(from_sens, 0.005);
}

TEST(Cli, KeyframeOdometryGivesEveryFrameOnePoseInEveryOutput) {
  const fs::path dir = SyntheticTum("cli_keyframes", 12);
  const fs::path out = testing::FreshTempDir("cli_keyframes_out");
  const Result r =
      RunCli("register " + dir.string() + " --intrinsics primesense -q --stop-after odometry -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const Trajectory tum = ReadTumTrajectory(out / "trajectory.txt");
  const Trajectory log = ReadLogTrajectory(out / "trajectory.log");
  const ConfFile conf = ReadConf(out / "trajectory.conf");
  ASSERT_EQ(tum.size(), 12u);
  ASSERT_EQ(log.size(), 12u);
  ASSERT_EQ(conf.trajectory.size(), 12u);
  for (size_t k = 0; k < 12; ++k) {
    // The synthetic scan starts at 1000 s; a frame carries its depth image's stamp, 1 ms later.
    EXPECT_NEAR(tum.timestamps[k], 1000.001 + k / 30.0, 1e-5);
    EXPECT_EQ(log.timestamps[k], static_cast<double>(k));
    EXPECT_LT((tum.world_from_camera[k].matrix() - log.world_from_camera[k].matrix()).norm(), 1e-5) << k;
    EXPECT_LT((tum.world_from_camera[k].matrix() - conf.trajectory.world_from_camera[k].matrix()).norm(), 1e-5) << k;
    EXPECT_NEAR(tum.world_from_camera[k].translation().x(), 0.03 * k, 0.01) << k;
  }
  const nlohmann::json pairs = nlohmann::json::parse(ReadFileToString(out / "odometry.json"));
  ASSERT_EQ(pairs.size(), 11u);
  int tracked = 0, keyframes = 1;
  for (size_t i = 0; i < pairs.size(); ++i) {
    EXPECT_EQ(pairs[i]["frame"].get<int>(), static_cast<int>(i) + 1);
    EXPECT_LT(pairs[i]["reference"].get<int>(), pairs[i]["frame"].get<int>());
    EXPECT_GT(pairs[i]["confidence"].get<double>(), 0.5);
    tracked += pairs[i]["method"] == "track";
    keyframes += pairs[i]["keyframe"].get<bool>();
  }
  EXPECT_GE(tracked, 8);
  EXPECT_LT(keyframes, 6);  // 3 cm and 1.15 degrees per frame: a keyframe about every 4th frame
  const nlohmann::json run = nlohmann::json::parse(ReadFileToString(out / "run.json"));
  EXPECT_EQ(run["statistics"]["odometry"]["keyframes"].get<int>(), keyframes);
  EXPECT_EQ(run["stages"]["odometry"]["sift_frames"].get<int>(), keyframes);

  const fs::path off = testing::FreshTempDir("cli_keyframes_off");
  ASSERT_EQ(RunCli("register " + dir.string() +
                   " --intrinsics primesense -q --stop-after odometry --keyframes off -o " + off.string())
                .code,
            0);
  const nlohmann::json chain = nlohmann::json::parse(ReadFileToString(off / "odometry.json"));
  for (const auto& pair : chain) {
    EXPECT_EQ(pair["reference"].get<int>(), pair["frame"].get<int>() - 1);
    EXPECT_EQ(pair["method"], "sift");
  }
  EXPECT_EQ(ReadTumTrajectory(off / "trajectory.txt").size(), 12u);
}

// The refinement runs by default: T0 beside the refined trajectory, per-iteration summaries in
// run.json, each iteration's poses on request; --stop-after odometry makes T0 the result.
TEST(Cli, RegisterRefinesAndKeepsT0) {
  const fs::path dir = SyntheticTum("cli_refine", 12);
  const fs::path out = testing::FreshTempDir("cli_refine_out");
  const std::string base = "register " + dir.string() + " --intrinsics primesense -q --window-frames 4 ";
  const Result r = RunCli(base + "--save-iterations -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("(TUM; refined)"), std::string::npos) << r.output;
  const Trajectory t0 = ReadTumTrajectory(out / "trajectory_t0.txt");
  const Trajectory refined = ReadTumTrajectory(out / "trajectory.txt");
  ASSERT_EQ(refined.size(), 12u);
  // The synthetic walk moves 3 cm per frame: the refined poses keep it.
  EXPECT_NEAR(refined.world_from_camera[11].translation().x(), 0.33, 0.01);
  const std::string run = ReadFileToString(out / "run.json");
  EXPECT_NE(run.find("\"result\": \"refined\""), std::string::npos);
  EXPECT_NE(run.find("\"candidate_pairs\""), std::string::npos);
  // l_0 = 4 over 12 frames: 4, 8, 16 (full), then 2 extra and 6 polish iterations.
  for (int i = 1; i <= 11; ++i)
    EXPECT_TRUE(fs::exists(out / "iterations" / fmt::format("iteration_{:02d}.txt", i))) << i;
  EXPECT_FALSE(fs::exists(out / "iterations" / "iteration_12.txt"));

  const fs::path odo = testing::FreshTempDir("cli_refine_odometry");
  ASSERT_EQ(RunCli(base + "--stop-after odometry -o " + odo.string()).code, 0);
  EXPECT_FALSE(fs::exists(odo / "mesh.ply"));  // T0 only: no mesh
  EXPECT_EQ(ReadFileToString(odo / "trajectory.txt"), ReadFileToString(odo / "trajectory_t0.txt"));
  EXPECT_EQ(ReadFileToString(odo / "trajectory_t0.txt"), ReadFileToString(out / "trajectory_t0.txt"));
}

// --initial-trajectory: the refinement starts from the given poses, not T0. The whole truth
// moved by 1 m: the free gauge keeps frame 0 where the start put it, and the others stay
// with it, so the result is the moved truth, not T0's frame.
TEST(Cli, RegisterRefinesFromAGivenTrajectory) {
  const fs::path dir = SyntheticTum("cli_initial", 12);
  const Trajectory truth = ReadTumTrajectory(dir / "groundtruth.txt");
  Trajectory moved = truth;
  for (Rigid3d& pose : moved.world_from_camera) pose.translation() += Eigen::Vector3d(1, 0, 0);
  const fs::path start = testing::FreshTempDir("cli_initial_start") / "start.txt";
  WriteTumTrajectory(start, moved);
  const fs::path out = testing::FreshTempDir("cli_initial_out");
  const Result r = RunCli("register " + dir.string() + " --intrinsics primesense -q --window-frames 4 --no-mesh " +
                          "--no-report --initial-trajectory " + start.string() + " -o " + out.string());
  ASSERT_EQ(r.code, 0) << r.output;
  const Trajectory refined = ReadTumTrajectory(out / "trajectory.txt");
  ASSERT_EQ(refined.size(), 12u);
  EXPECT_LT((refined.world_from_camera[0].translation() - moved.world_from_camera[0].translation()).norm(), 1e-6);
  for (size_t i = 0; i < refined.size(); ++i) {
    EXPECT_LT((refined.world_from_camera[i].translation() - moved.world_from_camera[i].translation()).norm(), 0.01)
        << i;
  }
  EXPECT_NE(ReadFileToString(out / "run.json").find("\"initial\": \"" + start.string() + "\""), std::string::npos);
}

// fuse: a dataset and any trajectory file to a mesh on the scene's surfaces; register fuses
// its final poses into OUTDIR/mesh.ply unless --no-mesh.
TEST(Cli, FuseWritesTheRoomsSurfacesAndRegisterFusesItsPoses) {
  const fs::path dir = SyntheticTum("cli_fuse", 6);
  const fs::path out = testing::FreshTempDir("cli_fuse_out");
  const std::string base = "fuse " + dir.string() + " --intrinsics primesense -q --trajectory ";
  const Result r = RunCli(base + (dir / "groundtruth.txt").string() + " -o " + (out / "gt.ply").string());
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("6 frames fused"), std::string::npos) << r.output;
  const PlyPoints mesh = ReadPly(out / "gt.ply");
  ASSERT_GT(mesh.faces.size(), 10000u);
  ASSERT_EQ(mesh.colors.size(), mesh.positions.size());
  std::vector<double> d;
  for (const Eigen::Vector3f& p : mesh.positions)
    d.push_back(testing::SurfaceDistance(testing::SyntheticScene(), p.cast<double>()));
  std::nth_element(d.begin(), d.begin() + d.size() * 9 / 10, d.end());
  EXPECT_LT(d[d.size() * 9 / 10], 0.01);

  EXPECT_EQ(RunCli(base + (dir / "groundtruth.txt").string() + " -o " + (out / "m.obj").string()).output,
            "error: " + (out / "m.obj").string() + ": the mesh is written as PLY: give a .ply file\n");
  WriteFileAtomic(out / "late.txt", "100.0 0 0 0 0 0 0 1\n");
  EXPECT_EQ(RunCli(base + (out / "late.txt").string() + " -o " + (out / "late.ply").string()).output,
            "error: " + (out / "late.txt").string() + ": no pose matches a frame of " + dir.string() +
                " (time stamps 0.02 s apart at most)\n");
  EXPECT_FALSE(fs::exists(out / "late.ply"));

  const std::string reg = "register " + dir.string() + " --intrinsics primesense -q --voxel-size 0.02 ";
  ASSERT_EQ(RunCli(reg + "-o " + (out / "reg").string()).code, 0);
  const PlyPoints registered = ReadPly(out / "reg" / "mesh.ply");
  EXPECT_GT(registered.faces.size(), 1000u);
  const nlohmann::json run = nlohmann::json::parse(ReadFileToString(out / "reg" / "run.json"));
  EXPECT_EQ(run["stages"]["fusion"]["triangles"].get<size_t>(), registered.faces.size());
  EXPECT_EQ(run["options"]["fusion"]["tsdf"]["voxel_size"].get<double>(), 0.02);
  ASSERT_EQ(RunCli(reg + "--no-mesh -o " + (out / "none").string()).code, 0);
  EXPECT_FALSE(fs::exists(out / "none" / "mesh.ply"));
}

// simulate writes the true surfaces; evaluate --mesh measures a mesh against them, in the
// ground truth's frame: a mesh from the true poses lies on them, one from poses off by 5 cm
// does not.
TEST(Cli, EvaluateMeshAgainstTheSimulatedSurfaces) {
  const fs::path dir = testing::FreshTempDir("cli_mesh_eval");
  ASSERT_EQ(RunCli("simulate --scene two-rooms --frames 12 --exact -q -o " + (dir / "scan").string()).code, 0);
  ASSERT_TRUE(fs::exists(dir / "scan" / "scene.ply"));
  const std::string gt = (dir / "scan" / "groundtruth.txt").string();
  ASSERT_EQ(RunCli("fuse " + (dir / "scan").string() + " --trajectory " + gt + " --voxel-size 0.02 -q -o " +
                   (dir / "gt.ply").string())
                .code,
            0);
  const Result exact = RunCli("evaluate --json --estimate " + gt + " --ground-truth " + (dir / "scan").string() +
                              " --mesh " + (dir / "gt.ply").string());
  ASSERT_EQ(exact.code, 0) << exact.output;
  const nlohmann::json e = nlohmann::json::parse(exact.output);
  EXPECT_LT(e["mesh"]["accuracy_p90_m"].get<double>(), 0.01);
  EXPECT_GT(e["mesh"]["completeness"].get<double>(), 0.05);  // 12 frames see part of two rooms (0.07)

  // Every pose 5 cm off, alternately to either side (so that ATE's alignment, which moves
  // the mesh into the truth's frame, stays about the identity): doubled walls.
  const Trajectory truth = ReadTumTrajectory(gt);
  Trajectory off = truth;
  for (size_t i = 0; i < off.size(); ++i) {
    off.world_from_camera[i].translation() += (i % 2 ? 0.05 : -0.05) * Eigen::Vector3d::UnitX();
  }
  WriteTumTrajectory(dir / "off.txt", off);
  ASSERT_EQ(RunCli("fuse " + (dir / "scan").string() + " --trajectory " + (dir / "off.txt").string() +
                   " --voxel-size 0.02 -q -o " + (dir / "off.ply").string())
                .code,
            0);
  const Result wrong = RunCli("evaluate --json --estimate " + (dir / "off.txt").string() + " --ground-truth " +
                              (dir / "scan").string() + " --mesh " + (dir / "off.ply").string());
  ASSERT_EQ(wrong.code, 0) << wrong.output;
  const nlohmann::json w = nlohmann::json::parse(wrong.output);
  EXPECT_GT(w["mesh"]["accuracy_p90_m"].get<double>(), 2 * e["mesh"]["accuracy_p90_m"].get<double>());
  EXPECT_LT(w["mesh"]["completeness"].get<double>(), e["mesh"]["completeness"].get<double>());

  // True surfaces without triangles (a point set): one line naming that file.
  PlyPoints points;
  points.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  WritePly(dir / "points.ply", points);
  EXPECT_EQ(RunCli("evaluate --estimate " + gt + " --ground-truth " + gt + " --mesh " + (dir / "gt.ply").string() +
                   " --true-surfaces " + (dir / "points.ply").string())
                .output,
            "error: " + (dir / "points.ply").string() + ": has no triangles: the true surfaces must be a PLY mesh\n");
  // Without true surfaces: one line naming the mesh.
  EXPECT_EQ(
      RunCli("evaluate --estimate " + gt + " --ground-truth " + gt + " --mesh " + (dir / "gt.ply").string()).output,
      "error: " + (dir / "gt.ply").string() +
          ": --mesh needs the true surfaces: --true-surfaces FILE, or "
          "--ground-truth as a simulated folder (with scene.ply)\n");
}

// Any run's options can be written and re-run: the same poses come back.
TEST(Cli, WriteConfigThenConfigReproducesTheRun) {
  const fs::path dir = SyntheticTum("cli_config", 8);
  const fs::path out = testing::FreshTempDir("cli_config_out");
  const fs::path config = out / "run.toml";
  ASSERT_EQ(RunCli("register " + dir.string() +
                   " --intrinsics primesense -q --window-frames 2 --no-sift-loops --no-mesh --no-report "
                   "--loss huber --write-config " +
                   config.string() + " -o " + (out / "a").string())
                .code,
            0);
  const std::string text = ReadFileToString(config);
  EXPECT_NE(text.find("register.window-frames=2"), std::string::npos) << text;
  EXPECT_NE(text.find("register.sift-loops=false"), std::string::npos);
  EXPECT_NE(text.find("register.loss=\"huber\""), std::string::npos);
  // Register's options alone: read with another subcommand, the file changes nothing there.
  EXPECT_EQ(text.find("evaluate."), std::string::npos);
  const Result evaluated = RunCli("--config " + config.string() + " evaluate --estimate " +
                                  (out / "a" / "trajectory.txt").string() + " --ground-truth " + dir.string());
  EXPECT_EQ(evaluated.code, 0) << evaluated.output;
  // Written only for a run that can start: not for an input that cannot be read.
  const Result missing = RunCli("register " + (out / "nothing").string() + " -q --write-config " +
                                (out / "never.toml").string() + " -o " + (out / "c").string());
  EXPECT_EQ(missing.code, 1);
  EXPECT_FALSE(fs::exists(out / "never.toml"));
  // Re-run from the file into another folder.
  std::string edited = text;
  const std::string from = "register.output=\"" + (out / "a").string() + "\"";
  ASSERT_NE(edited.find(from), std::string::npos);
  edited.replace(edited.find(from), from.size(), "register.output=\"" + (out / "b").string() + "\"");
  WriteFileAtomic(out / "b.toml", edited);
  const Result r = RunCli("--config " + (out / "b.toml").string() + " register");
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_EQ(ReadFileToString(out / "a" / "trajectory.txt"), ReadFileToString(out / "b" / "trajectory.txt"));
  // A misspelt key is an error, not a hint.
  WriteFileAtomic(out / "bad.toml", "register.windw-frames=4\n");
  EXPECT_EQ(RunCli("--config " + (out / "bad.toml").string() + " register " + dir.string() + " -o /tmp/x").code, 2);
}

// The structural model is on by default (and --structure says so): each iteration's summary
// in run.json lists the hierarchy (every child linked, parents from the synthetic room's
// walls and floor) and the terms E_P and E_H; --no-structure has none of them.
TEST(Cli, StructureAddsTheHierarchyAndItsTermsToEachIteration) {
  const fs::path dir = SyntheticTum("cli_structure", 12);
  const fs::path out = testing::FreshTempDir("cli_structure_out");
  const std::string base =
      "register " + dir.string() + " --intrinsics primesense -q --window-frames 4 --no-mesh --no-report ";
  ASSERT_EQ(RunCli(base + "-o " + (out / "on").string()).code, 0);
  // The later runs differ only in the refinement: they start from the first run's caches (a
  // cached run gives the computing run's poses bit for bit).
  for (const char* run : {"explicit", "off", "noisy", "late"}) {
    fs::create_directories(out / run);
    fs::copy(out / "on" / "cache", out / run / "cache", fs::copy_options::recursive);
  }
  ASSERT_EQ(RunCli(base + "--structure -o " + (out / "explicit").string()).code, 0);
  ASSERT_EQ(RunCli(base + "--no-structure -o " + (out / "off").string()).code, 0);
  EXPECT_EQ(ReadFileToString(out / "on" / "trajectory.txt"), ReadFileToString(out / "explicit" / "trajectory.txt"));
  const nlohmann::json on = nlohmann::json::parse(ReadFileToString(out / "on" / "run.json"));
  const nlohmann::json off = nlohmann::json::parse(ReadFileToString(out / "off" / "run.json"));
  const nlohmann::json& last = on["stages"]["refine"]["iterations"].back();
  EXPECT_GT(last["hierarchy"]["children"].get<int>(), 0) << last.dump(2);
  EXPECT_EQ(last["hierarchy"]["links"].get<int>(), last["hierarchy"]["children"].get<int>());  // one window
  EXPECT_GT(last["hierarchy"]["parents"].get<int>(), 0);
  EXPECT_TRUE(last["solve"]["cost_after"].contains("E_P"));
  EXPECT_TRUE(last["solve"]["cost_after"].contains("E_H"));
  // E_H's weight follows the children's normal spread, measured once at the start in windows
  // of l_0 frames: times min(1, (reference / spread)^2), here with a reference below the
  // spread. The measurement does not depend on the schedule: the same spread when the
  // structure starts later or every window holds the whole scan.
  ASSERT_EQ(RunCli(base + "--structure --coplanarity-noise-reference 0.001 -o " + (out / "noisy").string()).code, 0);
  const nlohmann::json noisy = nlohmann::json::parse(ReadFileToString(out / "noisy" / "run.json"));
  const nlohmann::json& refine = noisy["stages"]["refine"];
  const double spread = refine["initial_child_normal_spread_deg"].get<double>();
  ASSERT_GT(spread, 0.001);
  const double factor = std::pow(0.001 / spread, 2);
  EXPECT_NEAR(refine["coplanarity_noise_factor"].get<double>(), factor, 1e-12 * factor);
  for (const nlohmann::json& it : refine["iterations"]) {
    EXPECT_NEAR(it["coplanarity_noise_factor"].get<double>(), factor, 1e-12 * factor);
    EXPECT_NEAR(it["weights"]["E_H"].get<double>(), 1000 * factor, 1e-9 * factor);
  }
  EXPECT_NEAR(
      on["stages"]["refine"]["coplanarity_noise_factor"].get<double>(),
      std::min(1.0, std::pow(0.25 / on["stages"]["refine"]["initial_child_normal_spread_deg"].get<double>(), 2)),
      1e-12);
  ASSERT_EQ(RunCli(base + "--structure --structure-from 2 --no-fine-to-coarse -o " + (out / "late").string()).code, 0);
  const nlohmann::json late = nlohmann::json::parse(ReadFileToString(out / "late" / "run.json"));
  EXPECT_EQ(late["stages"]["refine"]["initial_child_normal_spread_deg"].get<double>(),
            on["stages"]["refine"]["initial_child_normal_spread_deg"].get<double>());
  const nlohmann::json& plain = off["stages"]["refine"]["iterations"].back();
  EXPECT_EQ(plain["hierarchy"]["children"].get<int>(), 0);
  EXPECT_FALSE(plain["solve"]["cost_after"].contains("E_P"));
  EXPECT_EQ(RunCli(base + "--weight-schedule linear -o " + (out / "bad").string()).output,
            "error: --weight-schedule: unknown value 'linear' (constant, authors)\n");
  EXPECT_EQ(RunCli(base + "--structure --coplanar-angle 95 -o " + (out / "bad").string()).output,
            "error: --coplanar-angle: must be in (0, 90), got 95\n");
  EXPECT_FALSE(fs::exists(out / "bad"));
}

TEST(Cli, FeaturesWritesTheCacheImagesAndPointSetsAndReusesTheCache) {
  const fs::path dir = SyntheticTum("cli_features", 3);
  const fs::path out = testing::FreshTempDir("cli_features_out");
  const std::string command =
      "features " + dir.string() + " --intrinsics primesense -q --images --ply -o " + out.string();
  const Result r = RunCli(command);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("3 frames computed, 0 from cache"), std::string::npos) << r.output;
  uint64_t context = 0;
  const std::vector<FeatureCacheEntry> cache = ReadFeatureCache(out / "features.f2cf", &context);
  ASSERT_EQ(cache.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const std::string name = "00000" + std::to_string(i);
    EXPECT_TRUE(fs::exists(out / "images" / (name + ".png"))) << name;
    // The point set holds the frame's features, in the cache's order.
    const PlyPoints ply = ReadPly(out / "ply" / (name + ".ply"));
    ASSERT_EQ(ply.positions.size(), cache[i].features.features.size());
    EXPECT_EQ(ply.positions.front(), cache[i].features.features.front().position);
  }
  EXPECT_TRUE(fs::exists(out / "features.json"));
  const Result again = RunCli(command);
  EXPECT_NE(again.output.find("0 frames computed, 3 from cache"), std::string::npos) << again.output;
  // register extracts them too, into its own cache.
  const fs::path reg = testing::FreshTempDir("cli_features_register");
  ASSERT_EQ(RunCli("register " + dir.string() + " --intrinsics primesense -q -o " + reg.string()).code, 0);
  // From the depth images the odometry decoded: the same bytes as the features command's.
  EXPECT_EQ(ReadFileToString(reg / "cache" / "features.f2cf"), ReadFileToString(out / "features.f2cf"));

  // A corrupt depth image: one line naming it, exit 1, and no new cache (the old one stays).
  const fs::path victim = *fs::directory_iterator(dir / "depth");
  WriteFileAtomic(victim, "garbage");
  const fs::path fresh = testing::FreshTempDir("cli_features_corrupt");
  const Result corrupt = RunCli("features " + dir.string() + " --intrinsics primesense -q -o " + fresh.string());
  EXPECT_EQ(corrupt.code, 1);
  EXPECT_EQ(corrupt.output, "error: " + victim.string() + ": cannot decode image (corrupt or not an image)\n");
  EXPECT_FALSE(fs::exists(fresh / "features.f2cf"));

  const Result no_k = RunCli("features " + dir.string() + " -q -o " + out.string());
  EXPECT_EQ(no_k.code, 1);
  EXPECT_EQ(no_k.output, "error: " + dir.string() +
                             ": no intrinsics: pass --intrinsics (a preset: tum-fr1, tum-fr2, tum-fr3, primesense; "
                             "or fx,fy,cx,cy)\n");
}

TEST(Cli, SimulateWritesAReadableScanAndDemoEvaluatesIt) {
  const fs::path dir = testing::FreshTempDir("cli_sim");
  const Result sim = RunCli("simulate --scene two-rooms --frames 4 --seed 3 -q -o " + (dir / "scan").string());
  ASSERT_EQ(sim.code, 0) << sim.output;
  const Result info = RunCli("info " + (dir / "scan").string());
  EXPECT_NE(info.output.find("frames       4 "), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("fx 525.000"), std::string::npos) << info.output;
  EXPECT_NE(info.output.find("ground truth 4 poses"), std::string::npos) << info.output;
  const Result bad = RunCli("simulate --scene castle --frames 4 -o " + (dir / "x").string());
  EXPECT_EQ(bad.code, 1);
  EXPECT_EQ(
      bad.output,
      "error: --scene: unknown scene 'castle' (expected two-rooms, apartment, apartment-square, corridor or object)\n");
  const Result demo = RunCli("demo --frames 12 -o " + (dir / "demo").string());
  ASSERT_EQ(demo.code, 0) << demo.output;
  EXPECT_NE(demo.output.find("12 of 12 poses associated"), std::string::npos) << demo.output;
  // The scan's ground-truth correspondences are evaluated too (the authors' metric).
  EXPECT_NE(demo.output.find("\ncorrespondences          m "), std::string::npos) << demo.output;
  EXPECT_TRUE(fs::exists(dir / "demo" / "registration" / "trajectory.txt"));
  EXPECT_TRUE(fs::exists(dir / "demo" / "registration" / "mesh.ply"));
  // The simulated scan's correspondences: their errors by frame distance (the paper's Fig. 9)
  // and their histogram, in the report.
  const std::string report = ReadFileToString(dir / "demo" / "registration" / "report.html");
  EXPECT_NE(report.find("Fig. 9"), std::string::npos);
  EXPECT_NE(report.find(">Correspondence errors</text>"), std::string::npos);
  // Correspondences name frames, so they need the dataset folder, not a trajectory file.
  const fs::path scan = dir / "demo" / "scan";
  const Result no_frames =
      RunCli("evaluate --estimate " + (dir / "demo" / "registration" / "trajectory.txt").string() + " --ground-truth " +
             (scan / "groundtruth.txt").string() + " --correspondences " + (scan / "correspondences.txt").string());
  EXPECT_EQ(no_frames.code, 1);
  EXPECT_EQ(no_frames.output, "error: " + (scan / "correspondences.txt").string() +
                                  ": correspondences name frames: give --ground-truth as the dataset folder\n");
  // A prefix (--last) is measured on the correspondences inside it: the truth's own poses
  // put each pair's points together, and every pair within frames 0..5 counts.
  const Result prefix = RunCli("evaluate --json --last 5 --estimate " + (scan / "groundtruth.txt").string() +
                               " --ground-truth " + scan.string());
  ASSERT_EQ(prefix.code, 0) << prefix.output;
  const nlohmann::json p = nlohmann::json::parse(prefix.output);
  int inside = 0, all = 0;
  for (const Correspondence& c : ReadCorrespondences(scan / "correspondences.txt")) {
    ++all;
    inside += c.frame_a <= 5 && c.frame_b <= 5;
  }
  ASSERT_GT(inside, 0);
  ASSERT_LT(inside, all);
  EXPECT_EQ(p["correspondences"]["distance_m"]["count"].get<int>(), inside);
  EXPECT_LT(p["correspondences"]["distance_m"]["rmse"].get<double>(), 1e-4);
}

TEST(Cli, InfoOnRealData) {
  if (!fs::exists(Data("7scenes_redkitchen_15hz"))) GTEST_SKIP() << "../shared/data absent";
  const Result r = RunCli("info " + Data("7scenes_redkitchen_15hz").string());
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.output.find("layout       7scenes"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("frames       500"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("fx 585.000"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("ground truth 500 poses"), std::string::npos) << r.output;
}

TEST(Cli, EvaluateGroundTruthAgainstItselfIsZero) {
  if (!fs::exists(Data("tum_fr1_desk_9"))) GTEST_SKIP() << "../shared/data absent";
  const fs::path gt = Data("tum_fr1_desk_9") / "groundtruth.txt";
  const Result r = RunCli("evaluate --estimate " + gt.string() + " --ground-truth " + gt.string());
  EXPECT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find("ATE                      m       0.0000"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("rotation drift >=5 s     deg     0.0000"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace f2c
