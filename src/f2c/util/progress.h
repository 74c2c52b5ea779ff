#pragma once
// Progress of long work. On a terminal: one redrawn bar on stderr with rate and ETA. Not on
// a terminal (CI, a pipe, a log file): a plain log line at every 10%, so logs stay readable.
// Thread-safe: workers call Advance() from any thread.

#include <atomic>
#include <mutex>
#include <string>

#include "f2c/util/timer.h"

namespace f2c {

class Progress {
 public:
  // `quiet` suppresses all output (tests, --quiet).
  Progress(std::string label, long total, bool quiet = false);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void Advance(long n = 1);
  // Prints the final state once; called by the destructor if not before.
  void Finish();

 private:
  void Draw(long done, bool final_line);

  std::string label_;
  long total_;
  bool quiet_;
  bool terminal_;
  std::atomic<long> done_{0};
  std::mutex mutex_;
  int last_decile_ = 0;
  double last_draw_ = -1.0;
  bool finished_ = false;
  Timer timer_;
};

}  // namespace f2c
