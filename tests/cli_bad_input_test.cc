// The CLI on bad input (docs/cli.md, "Bad input: what you see"): exit codes 1 and 2, one-line
// messages naming the file or flag, and nothing written.

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <thread>
#include <vector>
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
using namespace cli_test;  // the runner and inputs both CLI test files share

TEST(Cli, BadUsageExitsTwo) {
  EXPECT_EQ(RunCli("").code, 2);
  EXPECT_EQ(RunCli("frobnicate").code, 2);
  EXPECT_EQ(RunCli("register /tmp").code, 2);                        // -o missing
  EXPECT_EQ(RunCli("register /tmp -o /tmp/x --every two").code, 2);  // not a number
}

// A number out of its range is bad input (exit 1), named by its flag, before any work or
// output folder.
TEST(Cli, OutOfRangeOptionsAreOneLineNamingTheFlag) {
  const fs::path out = testing::FreshTempDir("cli_range") / "x";
  Result r = RunCli("register /tmp -o " + out.string() + " --every 0");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: --every: must be >= 1, got 0\n");
  r = RunCli("register /tmp -o " + out.string() + " --voxel-size 2");
  EXPECT_EQ(r.output, "error: --voxel-size: must be in [0.001, 0.5], got 2\n");
  r = RunCli("register /tmp -o " + out.string() + " --ransac-threshold -1");
  EXPECT_EQ(r.output, "error: --ransac-threshold: must be > 0, got -1\n");
  r = RunCli("register /tmp -o " + out.string() + " --track-window 8");
  EXPECT_EQ(r.output, "error: --track-window: must be odd, got 8\n");
  r = RunCli("register /tmp -o " + out.string() + " --feature-step 0");
  EXPECT_EQ(r.output, "error: --feature-step: must be >= 1, got 0\n");
  r = RunCli("register /tmp -o " + out.string() + " --loss tukey");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: --loss: unknown value 'tukey' (none, huber, cauchy)\n");
  r = RunCli("evaluate --estimate /tmp/a --ground-truth /tmp/b --drift-min-seconds -1");
  EXPECT_EQ(r.output, "error: --drift-min-seconds: must be >= 0, got -1\n");
  r = RunCli("evaluate --estimate /tmp/a --ground-truth /tmp/b --drift-threshold -0.5");
  EXPECT_EQ(r.output, "error: --drift-threshold: must be >= 0, got -0.5\n");
  EXPECT_FALSE(fs::exists(out));
}

// Words an enumeration does not know, negative or partial whole numbers for seeds, a thread
// count no machine has and a demo too short to evaluate: one line naming the flag, exit 1,
// before any output.
TEST(Cli, UnknownWordsNegativeSeedsAndAbsurdCountsAreOneLine) {
  const fs::path out = testing::FreshTempDir("cli_words") / "x";
  const std::string seeds = "error: --seed: must be a whole number from 0 to 18446744073709551615, got ";
  const std::pair<std::string, std::string> rows[] = {
      {"register /tmp -o " + out.string() + " --local-spans keyframe",
       "error: --local-spans: unknown value 'keyframe' (frames, keyframes)\n"},
      {"register /tmp -o " + out.string() + " --seed -1", seeds + "'-1'\n"},
      {"register /tmp -o " + out.string() + " --refine-seed 1x",
       "error: --refine-seed: must be a whole number from 0 to 18446744073709551615, got '1x'\n"},
      {"register /tmp -o " + out.string() + " --threads 100000",
       "error: --threads: must be in [0, 1024], got 100000\n"},
      {"simulate -o " + out.string() + " --seed -1", seeds + "'-1'\n"},
      {"demo -o " + out.string() + " --seed -5", seeds + "'-5'\n"},
      {"demo -o " + out.string() + " --frames 2", "error: --frames: must be in [3, 100000], got 2\n"},
  };
  for (const auto& [args, message] : rows) {
    const Result r = RunCli(args);
    EXPECT_EQ(r.code, 1) << args;
    EXPECT_EQ(r.output, message) << args;
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(Cli, MissingInputExitsOneWithOneLine) {
  const Result r = RunCli("info /no/such/folder");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: /no/such/folder: no such file or folder\n");
}

TEST(Cli, UnwritableOutputFolderFailsBeforeWork) {
  const fs::path dir = SyntheticTum("cli_unwritable", 2);
  const fs::path blocker = testing::FreshTempDir("cli_blocker") / "file";
  WriteFileAtomic(blocker, "x");
  const Result r = RunCli(dir.string() + " --intrinsics primesense -o " + (blocker / "out").string() + " -q");
  // register is the subcommand; put it first.
  const Result r2 =
      RunCli("register " + dir.string() + " --intrinsics primesense -o " + (blocker / "out").string() + " -q");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r2.code, 1);
  EXPECT_EQ(r2.output.rfind("error: " + (blocker / "out").string() + ": cannot create output folder", 0), 0u)
      << r2.output;
}

TEST(Cli, BadRefinementOptionFailsBeforeAnyWork) {
  const fs::path dir = SyntheticTum("cli_refine_bad", 2);
  const fs::path out = testing::FreshTempDir("cli_refine_bad_out") / "run";
  const Result r =
      RunCli("register " + dir.string() + " --intrinsics primesense -q --window-frames 1 -o " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: --window-frames: must be >= 2, got 1\n");
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(RunCli("register " + dir.string() + " --intrinsics primesense -q --windows time -o " + out.string()).output,
            "error: --windows: unknown value 'time' (frames, path)\n");
  EXPECT_EQ(
      RunCli("register " + dir.string() + " --intrinsics primesense -q --thresholds time -o " + out.string()).output,
      "error: --thresholds: unknown value 'time' (age, path)\n");
}

// A start trajectory that ends before the last frame is refused before any work, naming the
// frame.
// simulate onto a folder that holds a scan: refused (it would mix the old frames with the
// new), or replaced whole with --overwrite, other files left as they were.
TEST(Cli, SimulateOntoAScanRefusesOrReplacesIt) {
  const fs::path dir = testing::FreshTempDir("cli_sim_twice") / "scan";
  ASSERT_EQ(RunCli("simulate -o " + dir.string() + " --frames 6 -q --scene two-rooms").code, 0);
  WriteFileAtomic(dir / "notes.txt", "mine");
  const Result again = RunCli("simulate -o " + dir.string() + " --frames 4 -q --scene two-rooms --seed 1");
  EXPECT_EQ(again.code, 1);
  EXPECT_EQ(again.output, "error: " + dir.string() +
                              ": is not empty: give a new or empty folder, or --overwrite to replace the scan in it\n");
  EXPECT_EQ(ReadTumTrajectory(dir / "groundtruth.txt").size(), 6u);
  const Result replaced =
      RunCli("simulate -o " + dir.string() + " --frames 4 -q --scene two-rooms --seed 1 --overwrite");
  ASSERT_EQ(replaced.code, 0) << replaced.output;
  EXPECT_EQ(ReadTumTrajectory(dir / "groundtruth.txt").size(), 4u);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "rgb"), fs::directory_iterator()), 4);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "depth"), fs::directory_iterator()), 4);
  EXPECT_EQ(ReadFileToString(dir / "notes.txt"), "mine");
}

TEST(Cli, InitialTrajectoryWithoutAFrameFailsBeforeAnyWork) {
  const fs::path dir = SyntheticTum("cli_initial_bad", 3);
  Trajectory truth = ReadTumTrajectory(dir / "groundtruth.txt");
  Trajectory two;
  for (size_t i : {0, 1}) two.Add(truth.timestamps[i], truth.world_from_camera[i]);
  const fs::path start = testing::FreshTempDir("cli_initial_bad_start") / "start.txt";
  WriteTumTrajectory(start, two);
  const fs::path out = testing::FreshTempDir("cli_initial_bad_out") / "run";
  const Result r = RunCli("register " + dir.string() + " --intrinsics primesense -q --initial-trajectory " +
                          start.string() + " -o " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, fmt::format("error: {}: no pose within 1 ms of frame 2 (time stamp {:.6f} s), nor two within "
                                  "0.25 s around it\n",
                                  start.string(), truth.timestamps[2] + 0.001));  // frame 2's depth's stamp
  EXPECT_FALSE(fs::exists(out));
  // Poses no hand-held camera could have followed (the truth in millimetres): refused before
  // any work, not bent by the refinement into a wrong result.
  Trajectory millimetres = truth;
  for (Rigid3d& pose : millimetres.world_from_camera) pose.translation() *= 1000;
  const fs::path mm = start.parent_path() / "mm.txt";
  WriteTumTrajectory(mm, millimetres);
  const Result fast = RunCli("register " + dir.string() + " --intrinsics primesense -q --initial-trajectory " +
                             mm.string() + " -o " + out.string());
  EXPECT_EQ(fast.code, 1);
  const double step =
      (millimetres.world_from_camera[1].translation() - millimetres.world_from_camera[0].translation()).norm();
  EXPECT_EQ(fast.output, fmt::format("error: {}: the poses of frames 0 and 1 lie {:.3g} m apart, {:.3g} s apart in "
                                     "time: faster than 10 m/s, not a hand-held camera's path (poses in metres?)\n",
                                     mm.string(), step, truth.timestamps[1] - truth.timestamps[0]));
  EXPECT_FALSE(fs::exists(out));
  // A dataset folder as the start needs a ground truth.
  const fs::path bare = SyntheticTum("cli_initial_bare", 3);
  fs::remove(bare / "groundtruth.txt");
  const Result none = RunCli("register " + dir.string() + " --intrinsics primesense -q --initial-trajectory " +
                             bare.string() + " -o " + out.string());
  EXPECT_EQ(none.code, 1);
  EXPECT_EQ(none.output, "error: " + bare.string() + ": dataset has no ground-truth trajectory\n");
  EXPECT_FALSE(fs::exists(out));
  // Without the refinement nothing would start from it: refused, not ignored.
  const Result odometry = RunCli("register " + dir.string() + " --intrinsics primesense -q --stop-after odometry " +
                                 "--initial-trajectory " + dir.string() + " -o " + out.string());
  EXPECT_EQ(odometry.code, 1);
  EXPECT_EQ(odometry.output,
            "error: --initial-trajectory: only the refinement starts from it, and --stop-after odometry skips the "
            "refinement\n");
  EXPECT_EQ(
      RunCli("register " + dir.string() + " --intrinsics primesense -q --no-features --initial-trajectory " +
             dir.string() + " -o " + out.string())
          .output,
      "error: --initial-trajectory: only the refinement starts from it, and --no-features skips the refinement\n");
  EXPECT_FALSE(fs::exists(out));
}

TEST(Cli, CorruptFrameExitsOneNamingTheFile) {
  const fs::path dir = SyntheticTum("cli_corrupt", 3);
  const fs::path victim = *fs::directory_iterator(dir / "depth");
  WriteFileAtomic(victim, "garbage");
  const fs::path out = testing::FreshTempDir("cli_corrupt_out");
  const Result r = RunCli("register " + dir.string() + " --intrinsics primesense -q --no-cache -o " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: " + victim.string() + ": cannot decode image (corrupt or not an image)\n");
  // The folder was there before the run: it stays, as empty as it was.
  EXPECT_TRUE(fs::is_empty(out));
}

// Inputs that once ended in exit 3 ("internal error") or in OpenCV's words: each is one line
// naming the file, exit 1, and no output folder left behind.
TEST(Cli, FilesystemAndOversizedImagesAreOneLineErrors) {
  const fs::path dir = SyntheticTum("cli_fs", 3);
  // A listed image that is a symlink loop.
  const fs::path victim = *fs::directory_iterator(dir / "depth");
  fs::remove(victim);
  fs::create_symlink(victim, victim);
  const fs::path out = testing::FreshTempDir("cli_fs_out") / "run";
  Result r = RunCli("register " + dir.string() + " --intrinsics primesense -q -o " + out.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: " + victim.string() + ": Too many levels of symbolic links\n");
  EXPECT_FALSE(fs::exists(out));
  // The first depth image's header claims 100000 x 100000 pixels and the intrinsics carry no
  // size, so the reader looks at it first.
  const fs::path big = testing::FreshTempDir("cli_fs_big");
  testing::WriteTumSequence(big, testing::SyntheticScene(), testing::TestIntrinsics(),
                            {Rigid3d::Identity(), Rigid3d::Identity()});
  std::vector<fs::path> depths;
  for (const auto& e : fs::directory_iterator(big / "depth")) depths.push_back(e.path());
  std::sort(depths.begin(), depths.end());
  std::string header = "\x89PNG\r\n\x1a\n";
  auto put32 = [](std::string* s, uint32_t v) {
    for (int shift = 24; shift >= 0; shift -= 8) s->push_back(static_cast<char>((v >> shift) & 0xff));
  };
  std::string ihdr = "IHDR";
  put32(&ihdr, 100000), put32(&ihdr, 100000);
  ihdr += std::string("\x10\0\0\0\0", 5);
  put32(&header, 13);
  header += ihdr;
  put32(&header, static_cast<uint32_t>(Crc32ForTest(ihdr)));
  WriteFileAtomic(depths.front(), header + std::string("\0\0\0\0IEND\xae\x42\x60\x82", 12));
  r = RunCli("info " + big.string() + " --intrinsics 525,525,319.5,239.5");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: " + depths.front().string() +
                          ": PNG of 100000 x 100000 pixels: over the 32-megapixel limit for RGB-D frames\n");
  // The same from a 20-byte PGM header that OpenCV's decoder reads (30000 x 30000): refused
  // by OpenCV's own limit, which we set to ours (without it OpenCV allocated 2.7 GB and then
  // said "Unexpected end of input stream").
  WriteFileAtomic(depths.front(), "P5\n30000 30000\n255\nabc");
  r = RunCli("info " + big.string() + " --intrinsics 525,525,319.5,239.5");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: " + depths.front().string() +
                          ": corrupt image: its header claims over the 32-megapixel limit for RGB-D frames\n");
  // The output folder's cache is a file.
  const fs::path good = SyntheticTum("cli_fs_good", 3);
  const fs::path blocked = testing::FreshTempDir("cli_fs_blocked");
  WriteFileAtomic(blocked / "cache", "not a folder");
  r = RunCli("register " + good.string() + " --intrinsics primesense -q --stop-after odometry -o " + blocked.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: " + (blocked / "cache").string() + ": Not a directory\n");
}

TEST(Cli, FailedWritesToStdoutAndAbsurdOptionsAreErrors) {
  // Results on stdout that cannot be written (a full disk) are not a success.
  const fs::path dir = SyntheticTum("cli_stdout", 2);
  Result r = RunCli("info " + dir.string() + " --intrinsics primesense --json", " 2>&1 > /dev/full");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: stdout: No space left on device\n");
  // --help and --version too: to a full disk, or to a closed stdout.
  for (const char* args : {"--version", "register --help", "register --help-all"}) {
    r = RunCli(args, " 2>&1 > /dev/full");
    EXPECT_EQ(r.code, 1) << args;
    EXPECT_EQ(r.output, "error: stdout: No space left on device\n") << args;
  }
  r = RunCli("--version", " 2>&1 >&-");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: stdout: Bad file descriptor\n");
  r = RunCli("simulate --frames 2000000000 -o " + (testing::FreshTempDir("cli_absurd") / "s").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: --frames: must be in [1, 100000], got 2000000000\n");
  r = RunCli("simulate --frames 3 --depth-distortion nan -o " + (testing::FreshTempDir("cli_absurd") / "s").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: --depth-distortion: must be in [-1, 1], got nan\n");
  r = RunCli("simulate --frames 3 --color-offset 20 -o " + (testing::FreshTempDir("cli_absurd") / "s").string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: --color-offset: must be below half a frame interval (16.7 ms at 30 frames/s), got 20\n");
  r = RunCli("register " + dir.string() + " --intrinsics primesense -q -o ''");
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: (empty path): cannot create output folder: Invalid argument\n");
}

// A damaged entry in the pair cache is recomputed, with one warning, to the same poses.
// A cached pair moved by 5 cm (a hand edit, or a bit flip in a digit) fails its checksum: it
// is recomputed with one warning naming the file, and the poses are those of the first run.
// Without the checksum the moved pair was trusted and moved the trajectory.
TEST(Cli, ADamagedCachedPairIsRecomputed) {
  const fs::path dir = SyntheticTum("cli_cache_damage", 4);
  const fs::path out = testing::FreshTempDir("cli_cache_damage_out");
  const std::string cmd =
      "register " + dir.string() + " --intrinsics primesense -q --stop-after odometry -o " + out.string();
  ASSERT_EQ(RunCli(cmd).code, 0);
  const std::string before = ReadFileToString(out / "trajectory.txt");
  const fs::path file = out / "cache" / "odometry_pairs.json";
  nlohmann::json cache = nlohmann::json::parse(ReadFileToString(file));
  ASSERT_FALSE(cache["pairs"].empty());
  nlohmann::json& x = cache["pairs"].begin().value()["pair"]["prev_from_curr"][3];
  x = x.get<double>() + 0.05;
  WriteFileAtomic(file, cache.dump());
  const Result r = RunCli(cmd);
  ASSERT_EQ(r.code, 0) << r.output;
  EXPECT_NE(r.output.find(file.string() + ": 1 cached pair fails its checksum (edited or damaged); recomputing"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(ReadFileToString(out / "trajectory.txt"), before);
}

// The documented commands on damaged copies of real data (TUM fr1/desk, its 9 frames): each
// damage gives the documented one-line error, exit 1, from every command that reads what was
// damaged, and no output folder.
TEST(Cli, DamagedCopiesOfRealDataGiveTheDocumentedErrors) {
  if (!fs::exists(Data("tum_fr1_desk_9"))) GTEST_SKIP() << "../shared/data absent";
  const fs::path root = testing::FreshTempDir("cli_damaged");
  int copies = 0;
  auto copy = [&] {
    const fs::path dir = root / ("copy" + std::to_string(copies++));
    fs::copy(Data("tum_fr1_desk_9"), dir, fs::copy_options::recursive);
    return dir;
  };
  auto nth = [](const fs::path& folder, int n) {
    std::vector<fs::path> files{fs::directory_iterator(folder), fs::directory_iterator()};
    std::sort(files.begin(), files.end());
    return files.at(n);
  };
  const std::string k = " --intrinsics tum-fr1 -q ";
  // Nothing is left behind, not even an empty folder (an image found corrupt while decoding
  // stops a run after it made its output folder).
  auto expect = [&](const std::string& command, const std::string& message) {
    const fs::path out = root / ("out" + std::to_string(copies));
    const bool mesh = command.rfind("fuse", 0) == 0;
    const Result r = RunCli(command + " -o " + (mesh ? out / "mesh.ply" : out).string());
    EXPECT_EQ(r.code, 1) << command;
    EXPECT_EQ(r.output, "error: " + message + "\n") << command;
    EXPECT_FALSE(fs::exists(out)) << command << " left " << out;
  };
  const fs::path gt = Data("tum_fr1_desk_9") / "groundtruth.txt";

  // A colour JPEG cut short: read by register and fuse (features reads depth only).
  fs::path dir = copy();
  fs::path image = nth(dir / "rgb", 2);
  fs::resize_file(image, 5000);
  expect("register " + dir.string() + k, image.string() + ": corrupt JPEG: Premature end of JPEG file");
  expect("fuse " + dir.string() + k + "--trajectory " + gt.string(),
         image.string() + ": corrupt JPEG: Premature end of JPEG file");

  // A depth PNG of zero bytes: every command that reads depth.
  dir = copy();
  image = nth(dir / "depth", 1);
  fs::resize_file(image, 0);
  for (const std::string& command : {"register " + dir.string() + k, "features " + dir.string() + k,
                                     "fuse " + dir.string() + k + "--trajectory " + gt.string()}) {
    expect(command, image.string() + ": cannot decode image (corrupt or not an image)");
  }

  // A listed colour image missing: found when the folder is read, before any work.
  dir = copy();
  image = nth(dir / "rgb", 3);
  fs::remove(image);
  for (const std::string& command : {"register " + dir.string() + k, "features " + dir.string() + k,
                                     "fuse " + dir.string() + k + "--trajectory " + gt.string()}) {
    expect(command, image.string() + ": missing frame image (listed in the dataset)");
  }
  EXPECT_EQ(RunCli("info " + dir.string() + " --intrinsics tum-fr1").output,
            "error: " + image.string() + ": missing frame image (listed in the dataset)\n");

  // A listed image that is a symlink loop: the system's words, naming it.
  dir = copy();
  image = nth(dir / "rgb", 4);
  fs::remove(image);
  fs::create_symlink(image, image);
  expect("register " + dir.string() + k, image.string() + ": Too many levels of symbolic links");

  // A ground-truth line with a NaN: evaluate names the line.
  dir = copy();
  {
    std::string text = ReadFileToString(dir / "groundtruth.txt");
    std::istringstream lines(text);
    std::string out, line;
    for (int n = 1; std::getline(lines, line); ++n) out += (n == 5 ? "1305031453.4 nan 0 0 0 0 0 1" : line) + "\n";
    WriteFileAtomic(dir / "groundtruth.txt", out);
  }
  const Result r = RunCli("evaluate --estimate " + gt.string() + " --ground-truth " + dir.string());
  EXPECT_EQ(r.code, 1);
  EXPECT_EQ(r.output, "error: " + (dir / "groundtruth.txt").string() +
                          ":5: 'nan' is not a finite number; expected 'timestamp tx ty tz qx qy qz qw'\n");
}

// Names under `dir` (recursively) that are a run's temporary files.
std::vector<std::string> Temporaries(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    if (it->path().filename().string().find(".tmp.") != std::string::npos) found.push_back(it->path().string());
  }
  return found;
}

// Ctrl-C or kill while register streams its feature cache: the process ends by that signal,
// its temporary files are gone, and no trajectory.txt is left without the rest. A run killed
// where no handler runs (SIGKILL) leaves its temporary file; the next run removes it.
TEST(Cli, AStoppedRunLeavesNoTemporaryFile) {
  const fs::path scan = SyntheticTum("cli_signal_scan", 16);
  const fs::path base = testing::FreshTempDir("cli_signal");
  for (int signal_number : {SIGINT, SIGTERM, SIGKILL}) {
    const fs::path out = base / std::to_string(signal_number);
    const std::vector<std::string> args = {F2C_CLI_PATH, "register", scan.string(),  "-o",
                                           out.string(), "-q",       "--intrinsics", "525,525,319.5,239.5"};
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      std::vector<char*> argv;
      for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::freopen("/dev/null", "w", stderr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    // Stopped as soon as its feature cache is being written (the run's first seconds).
    bool seen = false;
    for (int wait_ms = 0; wait_ms < 120000 && !seen; wait_ms += 5) {
      seen = !Temporaries(out).empty();
      if (!seen) ::usleep(5000);
    }
    ::kill(child, signal_number);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(seen) << "no temporary file appeared under " << out;
    ASSERT_TRUE(WIFSIGNALED(status)) << "the run finished before the signal: status " << status;
    EXPECT_EQ(WTERMSIG(status), signal_number);
    EXPECT_FALSE(fs::exists(out / "trajectory.txt"));
    if (signal_number == SIGKILL) {
      EXPECT_FALSE(Temporaries(out).empty());  // no handler ran
      const Result again = RunCli("register " + scan.string() + " -o " + out.string() +
                                  " -q --stop-after odometry --no-report --intrinsics 525,525,319.5,239.5");
      EXPECT_EQ(again.code, 0) << again.output;
      EXPECT_TRUE(fs::exists(out / "trajectory.txt"));
    }
    EXPECT_EQ(Temporaries(out), std::vector<std::string>()) << "signal " << signal_number;
  }
}

// What is not a regular file is written through, never replaced: a FIFO given to
// --write-config hands its reader the options, and stays a FIFO; a cache that is a FIFO is
// an error naming it, before any work.
TEST(Cli, FifosAreWrittenThroughAndACacheFifoIsAnError) {
  const fs::path scan = SyntheticTum("cli_fifo_scan", 3);
  const fs::path dir = testing::FreshTempDir("cli_fifo");
  const fs::path fifo = dir / "config.fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string config;
  std::thread reader([&] { config = ReadFileToString(fifo); });
  const Result written =
      RunCli("register " + scan.string() + " -o " + (dir / "out").string() +
             " --stop-after odometry --no-report --intrinsics 525,525,319.5,239.5 --write-config " + fifo.string());
  reader.join();
  EXPECT_EQ(written.code, 0) << written.output;
  EXPECT_TRUE(fs::is_fifo(fifo));
  EXPECT_NE(config.find("register.voxel-size="), std::string::npos) << config;
  fs::create_directories(dir / "cached" / "cache");
  ASSERT_EQ(::mkfifo((dir / "cached" / "cache" / "features.f2cf").c_str(), 0600), 0);
  const Result cached =
      RunCli("register " + scan.string() + " -o " + (dir / "cached").string() + " -q --intrinsics 525,525,319.5,239.5");
  EXPECT_EQ(cached.code, 1);
  EXPECT_EQ(cached.output, "error: " + (dir / "cached" / "cache" / "features.f2cf").string() +
                               ": cache is not a regular file (a device, FIFO or socket)\n");
}

}  // namespace
}  // namespace f2c
