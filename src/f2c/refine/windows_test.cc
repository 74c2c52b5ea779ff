#include "f2c/refine/windows.h"

#include <gtest/gtest.h>

#include "f2c/util/error.h"

namespace f2c {
namespace {

std::vector<double> Straight(int n, double step) {
  std::vector<double> path(n);
  for (int k = 0; k < n; ++k) path[k] = k * step;
  return path;
}

std::vector<std::pair<int, int>> Ranges(const std::vector<Window>& windows) {
  std::vector<std::pair<int, int>> out;
  for (const Window& w : windows) out.push_back({w.begin, w.end});
  return out;
}

TEST(WindowSchedule, FramesDoubleWithHalfOverlapAndAPartialLastWindow) {
  WindowOptions options;
  options.polish_iterations = 0;
  options.initial_frames = 4;
  options.extra_iterations = 2;
  const WindowSchedule s(options, Straight(11, 0.1));
  // l = 4, 8, 16: 16 >= 11 frames holds all at iteration 2; then 2 more.
  EXPECT_EQ(s.iterations(), 5);
  using R = std::vector<std::pair<int, int>>;
  EXPECT_EQ(Ranges(s.Windows(0)), (R{{0, 4}, {2, 6}, {4, 8}, {6, 10}, {8, 11}}));
  EXPECT_EQ(Ranges(s.Windows(1)), (R{{0, 8}, {4, 11}}));
  EXPECT_EQ(Ranges(s.Windows(2)), (R{{0, 11}}));
  EXPECT_EQ(Ranges(s.Windows(4)), (R{{0, 11}}));
  EXPECT_FALSE(s.Full(1));
  EXPECT_TRUE(s.Full(2));
  EXPECT_DOUBLE_EQ(s.Length(1), 8);
}

TEST(WindowSchedule, LastWindowEndsExactlyAtTheScan) {
  WindowOptions options;
  options.polish_iterations = 0;
  options.initial_frames = 4;
  const WindowSchedule s(options, Straight(10, 0.1));
  using R = std::vector<std::pair<int, int>>;
  EXPECT_EQ(Ranges(s.Windows(0)), (R{{0, 4}, {2, 6}, {4, 8}, {6, 10}}));
}

TEST(WindowSchedule, SharingAgreesWithTheWindowsAndStartsWhenTheyGrow) {
  WindowOptions options;
  options.polish_iterations = 0;
  options.initial_frames = 4;
  const WindowSchedule s(options, Straight(37, 0.1));
  for (int i = 0; i < s.iterations(); ++i) {
    const std::vector<Window> windows = s.Windows(i);
    for (int a = 0; a < 37; ++a) {
      for (int b = a; b < 37; ++b) {
        bool together = false;
        for (const Window& w : windows) together = together || (a >= w.begin && b < w.end);
        ASSERT_EQ(s.Share(i, a, b), together) << i << " " << a << " " << b;
        ASSERT_EQ(s.Share(i, b, a), together);
      }
    }
  }
  EXPECT_EQ(s.FirstShared(0, 3), 0);
  EXPECT_EQ(s.FirstShared(2, 5), 0);  // window [2, 6)
  EXPECT_EQ(s.FirstShared(1, 4), 1);  // no window of 4 holds both
  EXPECT_EQ(s.FirstShared(1, 6), 1);  // l = 8: window [0, 8)
  EXPECT_EQ(s.FirstShared(3, 4), 0);
  EXPECT_EQ(s.FirstShared(0, 36), 4);  // l = 64
  EXPECT_EQ(s.ShareEnd(0, 5), 8);      // window [4, 8)
}

TEST(WindowSchedule, PathWindowsFollowTheCameraPathAndAreCapped) {
  WindowOptions options;
  options.polish_iterations = 0;
  options.mode = WindowMode::kPath;
  options.initial_path = 3.0;
  options.extra_iterations = 1;
  // 0.25 m per frame up to frame 20 (5 m), then a pause: frames 21-30 at 5 m.
  std::vector<double> path(31);
  for (int k = 0; k < 31; ++k) path[k] = 0.25 * std::min(k, 20);
  const WindowSchedule s(options, path);
  // L = 3, 6 (> 5 m: full), then one more.
  EXPECT_EQ(s.iterations(), 3);
  using R = std::vector<std::pair<int, int>>;
  // [0, 3 m) frames 0-11, [1.5, 4.5) frames 6-17, [3, 6) frames 12-30.
  EXPECT_EQ(Ranges(s.Windows(0)), (R{{0, 12}, {6, 18}, {12, 31}}));
  EXPECT_EQ(Ranges(s.Windows(1)), (R{{0, 31}}));
  // Capped at twice the path: 5 m scan, iteration 5 would be 96 m.
  EXPECT_DOUBLE_EQ(s.Length(5), 10.0);
}

TEST(WindowSchedule, ShortScanIsOneWindowFromTheStart) {
  WindowOptions options;
  options.polish_iterations = 0;
  options.initial_frames = 8;
  options.extra_iterations = 0;
  const WindowSchedule s(options, Straight(5, 0.1));
  EXPECT_EQ(s.iterations(), 1);
  using R = std::vector<std::pair<int, int>>;
  EXPECT_EQ(Ranges(s.Windows(0)), (R{{0, 5}}));
}

TEST(WindowSchedule, PolishIterationsComeLastAtFullSize) {
  WindowOptions options;
  options.initial_frames = 4;
  options.extra_iterations = 1;
  options.polish_iterations = 3;
  const WindowSchedule s(options, Straight(11, 0.1));
  // l = 4, 8, 16 (full), 1 extra, 3 polish.
  ASSERT_EQ(s.iterations(), 7);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(s.Polishing(i), i >= 4) << i;
  EXPECT_TRUE(s.Full(6));
}

// The paper's ablation: as many iterations as the fine-to-coarse schedule, each with one
// window holding the whole scan, so every pair shares a window from the first iteration.
TEST(WindowSchedule, NoFineToCoarseIsTheWholeScanInEveryIteration) {
  WindowOptions options;
  options.initial_frames = 4;
  const WindowSchedule growing(options, Straight(40, 0.1));
  options.fine_to_coarse = false;
  const WindowSchedule whole(options, Straight(40, 0.1));
  EXPECT_EQ(whole.iterations(), growing.iterations());
  EXPECT_GT(growing.Windows(0).size(), 1u);
  for (int i = 0; i < whole.iterations(); ++i) {
    EXPECT_TRUE(whole.Full(i));
    ASSERT_EQ(Ranges(whole.Windows(i)), (std::vector<std::pair<int, int>>{{0, 40}})) << i;
  }
  EXPECT_EQ(whole.FirstShared(0, 39), 0);
  EXPECT_GT(growing.FirstShared(0, 39), 0);
}

TEST(WindowOptions, BadValuesNameTheOption) {
  WindowOptions options;
  options.polish_iterations = 0;
  options.initial_frames = 1;
  try {
    options.Check();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--window-frames: must be >= 2, got 1");
  }
  try {
    FromName<WindowMode>("time", "--windows");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "--windows: unknown value 'time' (frames, path)");
  }
}

}  // namespace
}  // namespace f2c
