#include "f2c/util/temp_files.h"

#include <fmt/format.h>
#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace f2c {
namespace fs = std::filesystem;
namespace {

// A signal handler may only call async-signal-safe functions (unlink, raise, signal) and
// read lock-free atomics, so the names live in fixed slots, each with its state: free,
// being written (the handler skips it), or live.
constexpr int kSlots = 64;
constexpr size_t kMaxPath = 4096;
enum SlotState : int { kFree = 0, kWriting = 1, kLive = 2 };
std::array<std::atomic<int>, kSlots> g_state{};
char g_paths[kSlots][kMaxPath];

void RemoveAndReraise(int signal_number) {
  for (int i = 0; i < kSlots; ++i) {
    if (g_state[i].load() == kLive) ::unlink(g_paths[i]);
  }
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

// True when `name` ends in ".tmp.<pid>" or ".tmp.<pid>.<n>"; *pid receives the pid.
bool ParseTemporaryName(const std::string& name, long* pid) {
  const size_t at = name.rfind(".tmp.");
  if (at == std::string::npos || at == 0) return false;
  const std::string rest = name.substr(at + 5);
  const size_t dot = rest.find('.');
  const std::string pid_text = rest.substr(0, dot);
  const std::string counter = dot == std::string::npos ? "" : rest.substr(dot + 1);
  auto digits = [](const std::string& s) {
    return !s.empty() && s.size() < 12 && s.find_first_not_of("0123456789") == std::string::npos;
  };
  if (!digits(pid_text) || (dot != std::string::npos && !digits(counter))) return false;
  *pid = std::strtol(pid_text.c_str(), nullptr, 10);
  return *pid > 0;
}

bool ProcessIsGone(long pid) { return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH; }

}  // namespace

TemporaryFileName::TemporaryFileName(const fs::path& path) : path_(path.string()) {
  if (path_.size() >= kMaxPath) return;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (!g_state[i].compare_exchange_strong(expected, kWriting)) continue;
    std::memcpy(g_paths[i], path_.c_str(), path_.size() + 1);
    g_state[i].store(kLive);
    slot_ = i;
    return;
  }
}

TemporaryFileName::~TemporaryFileName() {
  if (slot_ < 0) return;
  g_state[slot_].store(kWriting);
  g_paths[slot_][0] = '\0';
  g_state[slot_].store(kFree);
}

std::string TemporaryName(const fs::path& path) {
  return path.string() + fmt::format(".tmp.{}", static_cast<long>(::getpid()));
}

void InstallTemporaryFileCleanup() {
  struct sigaction action = {};
  action.sa_handler = RemoveAndReraise;
  sigemptyset(&action.sa_mask);
  for (int s : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) ::sigaction(s, &action, nullptr);
}

int RemoveStaleTemporaries(const fs::path& dir) {
  std::error_code ec;
  std::vector<fs::path> stale;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator();
       it.increment(ec)) {
    std::error_code type_ec;
    long pid = 0;
    if (it->is_regular_file(type_ec) && ParseTemporaryName(it->path().filename().string(), &pid) &&
        pid != static_cast<long>(::getpid()) && ProcessIsGone(pid)) {
      stale.push_back(it->path());
    }
  }
  int removed = 0;
  for (const fs::path& p : stale) removed += fs::remove(p, ec) ? 1 : 0;
  return removed;
}

}  // namespace f2c
