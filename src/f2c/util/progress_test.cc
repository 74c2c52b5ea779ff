#include "f2c/util/progress.h"

#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <cstdlib>
#include <regex>
#include <sstream>
#include <tuple>

#include "f2c/testing/log_capture.h"

namespace f2c {
namespace {

// Progress logs a line per 10% when stderr is not a terminal (as under ctest and CI); CI=1
// makes it do so when the test runs on a terminal too.
class LogCapture : public testing::LogCapture {
 public:
  LogCapture() { setenv("CI", "1", 1); }
};

TEST(Progress, LogsEveryTenthAndTheEndOnce) {
  LogCapture capture;
  {
    Progress progress("work", 50);
    for (int i = 0; i < 50; ++i) progress.Advance();
  }  // the destructor prints the final line
  const std::vector<std::string> lines = capture.Lines();
  ASSERT_EQ(lines.size(), 10u);
  for (int i = 0; i < 9; ++i) {
    EXPECT_TRUE(std::regex_match(lines[i], std::regex("work: " + std::to_string(5 * (i + 1)) + "/50 \\(.*/s, .* s\\)")))
        << lines[i];
  }
  EXPECT_TRUE(std::regex_match(lines[9], std::regex("work: 50/50 \\(.*")));
}

TEST(Progress, FromManyThreadsEachTenthOnce) {
  LogCapture capture;
  Progress progress("parallel", 1000);
  tbb::parallel_for(0, 1000, [&](int) { progress.Advance(); });
  progress.Finish();
  progress.Finish();  // twice: printed once
  const std::vector<std::string> lines = capture.Lines();
  ASSERT_EQ(lines.size(), 10u);
  EXPECT_TRUE(std::regex_match(lines.back(), std::regex("parallel: 1000/1000 \\(.*")));
}

TEST(Progress, QuietOrEmptyPrintsNothing) {
  LogCapture capture;
  {
    Progress quiet("quiet", 10, true);
    for (int i = 0; i < 10; ++i) quiet.Advance();
    Progress empty("empty", 0);
  }
  EXPECT_TRUE(capture.Lines().empty());
}

TEST(Progress, ListenerHearsTheStartAndTheEndEvenWhenQuiet) {
  LogCapture capture;
  std::vector<std::tuple<std::string, long, long>> heard;
  {
    ScopedProgressListener listener(
        [&](const std::string& stage, long done, long total) { heard.emplace_back(stage, done, total); });
    Progress progress("stage", 1000, /*quiet=*/true);
    tbb::parallel_for(0, 1000, [&](int) { progress.Advance(); });
    progress.Finish();
    progress.Finish();
  }
  Progress after("unheard", 5, /*quiet=*/true);  // the scope has ended
  after.Advance(5);
  ASSERT_GE(heard.size(), 2u);
  EXPECT_EQ(heard.front(), std::make_tuple(std::string("stage"), 0L, 1000L));
  EXPECT_EQ(heard.back(), std::make_tuple(std::string("stage"), 1000L, 1000L));
  // At most ten a second besides the first and the last: the loop takes well under a second.
  EXPECT_LE(heard.size(), 4u);
  for (size_t i = 1; i < heard.size(); ++i) EXPECT_LE(std::get<1>(heard[i - 1]), std::get<1>(heard[i]));
  EXPECT_EQ(capture.Lines().size(), 0u);  // quiet: no line of its own
}

}  // namespace
}  // namespace f2c
