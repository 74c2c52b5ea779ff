#include "f2c/util/progress.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace f2c {

Progress::Progress(std::string label, long total, bool quiet)
    : label_(std::move(label)), total_(total), quiet_(quiet || total <= 0) {
  terminal_ = isatty(fileno(stderr)) && std::getenv("CI") == nullptr;
}

Progress::~Progress() { Finish(); }

void Progress::Advance(long n) {
  const long done = done_.fetch_add(n) + n;
  if (quiet_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
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
  if (quiet_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  Draw(done_.load(), true);
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
    std::fprintf(stderr, "\r%s [%s] %ld/%ld  %.1f/s  %s   ", label_.c_str(), bar.c_str(), done,
                 total_, rate,
                 final_line ? fmt::format("{:.1f} s", elapsed).c_str()
                            : fmt::format("ETA {:.0f} s", eta).c_str());
    if (final_line) std::fputc('\n', stderr);
    std::fflush(stderr);
  } else {
    spdlog::info("{}: {}/{} ({:.1f}/s, {:.1f} s)", label_, done, total_, rate, elapsed);
  }
}

}  // namespace f2c
