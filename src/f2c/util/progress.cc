#include "f2c/util/progress.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <utility>

namespace f2c {
namespace {

thread_local ProgressListener current_listener;

}  // namespace

ScopedProgressListener::ScopedProgressListener(ProgressListener listener)
    : previous_(std::exchange(current_listener, std::move(listener))) {}

ScopedProgressListener::~ScopedProgressListener() { current_listener = std::move(previous_); }

Progress::Progress(std::string label, long total, bool quiet)
    : label_(std::move(label)), total_(total), quiet_(quiet || total <= 0), listener_(current_listener) {
  terminal_ = isatty(fileno(stderr)) && std::getenv("CI") == nullptr;
  if (listener_ && total_ > 0) {
    std::lock_guard<std::mutex> lock(mutex_);
    Tell(0, false);
  }
}

Progress::~Progress() { Finish(); }

void Progress::Tell(long done, bool final_call) {
  if (!listener_ || total_ <= 0) return;
  const double now = timer_.Seconds();
  if (!final_call && done < total_ && now - last_told_ < 0.1 && last_told_ >= 0) return;
  last_told_ = now;
  listener_(label_, done, total_);
}

void Progress::Advance(long n) {
  const long done = done_.fetch_add(n) + n;
  if (quiet_ && !listener_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  Tell(done_.load(), false);  // read under the lock, so the listener hears counts that never go back
  if (quiet_) return;
  if (terminal_) {
    const double now = timer_.Seconds();
    if (now - last_draw_ < 0.1 && done < total_) return;  // redraw at most 10 times a second
    last_draw_ = now;
    Draw(done, false);
  } else {
    const int decile = static_cast<int>(10 * done / total_);
    if (decile > last_decile_ && done < total_) {
      last_decile_ = decile;
      Draw(done, false);
    }
  }
}

void Progress::Finish() {
  if (quiet_ && !listener_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  Tell(done_.load(), true);
  if (!quiet_) Draw(done_.load(), true);
}

void Progress::Draw(long done, bool final_line) {
  const double elapsed = timer_.Seconds();
  const double rate = elapsed > 0 ? done / elapsed : 0.0;
  const double eta = rate > 0 ? (total_ - done) / rate : 0.0;
  if (terminal_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(kWidth * done / std::max(total_, 1L));
    std::string bar(filled, '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r%s [%s] %ld/%ld  %.1f/s  %s   ", label_.c_str(), bar.c_str(), done, total_, rate,
                 final_line ? fmt::format("{:.1f} s", elapsed).c_str() : fmt::format("ETA {:.0f} s", eta).c_str());
    if (final_line) std::fputc('\n', stderr);
    std::fflush(stderr);
  } else {
    spdlog::info("{}: {}/{} ({:.1f}/s, {:.1f} s)", label_, done, total_, rate, elapsed);
  }
}

}  // namespace f2c
