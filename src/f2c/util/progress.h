#pragma once
// Progress of long work. On a terminal: one redrawn bar on stderr with rate and ETA. Not on
// a terminal (CI, a pipe, a log file): a plain log line at every 10%, so logs stay readable.
// Thread-safe: workers call Advance() from any thread.

#include <atomic>
#include <functional>
#include <mutex>
#include <string>

#include "f2c/util/timer.h"

namespace f2c {

// Told of every stage's progress (its label, units done, units in all) besides the bar, for
// embedders that draw their own (the Python module). Called at most ten times a second per
// stage and once at its end, from whichever thread advanced it, under the stage's lock.
using ProgressListener = std::function<void(const std::string& stage, long done, long total)>;

// While one lives, the Progress objects its thread constructs report to `listener` (also
// when quiet). Scopes nest; the innermost wins.
class ScopedProgressListener {
 public:
  explicit ScopedProgressListener(ProgressListener listener);
  ~ScopedProgressListener();
  ScopedProgressListener(const ScopedProgressListener&) = delete;
  ScopedProgressListener& operator=(const ScopedProgressListener&) = delete;

 private:
  ProgressListener previous_;
};

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

  void Tell(long done, bool final_call);  // the listener, under mutex_

  std::string label_;
  long total_;
  bool quiet_;
  ProgressListener listener_;
  double last_told_ = -1.0;
  bool terminal_;
  std::atomic<long> done_{0};
  std::mutex mutex_;
  int last_decile_ = 0;
  double last_draw_ = -1.0;
  bool finished_ = false;
  Timer timer_;
};

}  // namespace f2c
