#include "f2c/util/temp_files.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace f2c {
namespace {
namespace fs = std::filesystem;

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("f2c_temp_files_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void Touch(const fs::path& p) { std::ofstream(p) << "x"; }

// A child process that has a temporary file registered is stopped by `signal_number`: the
// file is gone and the child died of that signal (the exit status still says so).
void ExpectRemovedOnSignal(int signal_number) {
  const fs::path dir = FreshDir("signal_" + std::to_string(signal_number));
  const fs::path tmp = TemporaryName(dir / "cache.f2cf");
  const fs::path kept = dir / "kept.txt";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    InstallTemporaryFileCleanup();
    Touch(kept);
    const TemporaryFileName name(tmp);
    Touch(tmp);
    ::raise(signal_number);
    ::_exit(0);  // not reached: the signal's default action ends the process
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "status " << status;
  EXPECT_EQ(WTERMSIG(status), signal_number);
  EXPECT_TRUE(fs::exists(kept));
  EXPECT_FALSE(fs::exists(tmp)) << tmp;
}

TEST(TemporaryFileName, SigintSigtermSighupAndSigpipeRemoveIt) {
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) ExpectRemovedOnSignal(s);
}

// Once the name is released (the file renamed into place), a signal leaves the file alone.
TEST(TemporaryFileName, AReleasedNameIsNotRemoved) {
  const fs::path dir = FreshDir("released");
  const fs::path file = TemporaryName(dir / "out.txt");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    InstallTemporaryFileCleanup();
    { const TemporaryFileName name(file); }
    Touch(file);
    ::raise(SIGTERM);
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status));
  EXPECT_TRUE(fs::exists(file));
}

// Temporaries of processes that are gone (a run killed by SIGKILL) are removed, in
// subfolders too; this process's own, and files that only look alike, stay.
TEST(RemoveStaleTemporaries, RemovesOnlyThoseOfDeadProcesses) {
  const fs::path dir = FreshDir("stale");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // reaped: its pid names no process now
  fs::create_directories(dir / "cache");
  const std::string dead = std::to_string(child), alive = std::to_string(::getpid());
  for (const std::string& name :
       {"cache/features.f2cf.tmp." + dead, "run.json.tmp." + dead + ".3", "cache/features.f2cf.tmp." + alive,
        std::string("notes.tmp.txt"), "a.tmp." + dead + ".x", std::string("trajectory.txt")}) {
    Touch(dir / name);
  }
  EXPECT_EQ(RemoveStaleTemporaries(dir), 2);
  EXPECT_FALSE(fs::exists(dir / "cache" / ("features.f2cf.tmp." + dead)));
  EXPECT_FALSE(fs::exists(dir / ("run.json.tmp." + dead + ".3")));
  EXPECT_TRUE(fs::exists(dir / "cache" / ("features.f2cf.tmp." + alive)));
  EXPECT_TRUE(fs::exists(dir / "notes.tmp.txt"));
  EXPECT_TRUE(fs::exists(dir / ("a.tmp." + dead + ".x")));
  EXPECT_TRUE(fs::exists(dir / "trajectory.txt"));
  EXPECT_EQ(RemoveStaleTemporaries(dir / "absent"), 0);
}

}  // namespace
}  // namespace f2c
