#pragma once
// The fine-to-coarse window schedule (paper §3, §4.2; DESIGN.md §2). Constraints are only
// detected among frames that share a window. In iteration i the windows hold l_i consecutive
// frames and overlap their neighbours by l_i / 2; l_{i+1} = 2 l_i, until one window holds the
// whole scan; then `extra_iterations` more at that size.
//
// The authors' released code measures windows in camera path length instead (3 m, doubling,
// capped at twice the scan's path): WindowMode::kPath. Both are the same construction over a
// "position" of each frame along the scan: its index, or the camera path walked up to it.
// Window j of iteration i covers the frames whose position lies in [j h, j h + L) with
// L = the window length and h = L / 2; the last window is the first that reaches the scan's
// end, and may be partial.

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "f2c/util/fields.h"

namespace f2c {

enum class WindowMode { kFrames, kPath };
F2C_ENUM_NAMES(WindowMode, {{WindowMode::kFrames, "frames"}, {WindowMode::kPath, "path"}})

struct WindowOptions {
  WindowMode mode = WindowMode::kFrames;
  // l_0, frames (4, 16 and 32 measured level or worse on the real sequences and walks).
  int initial_frames = 8;
  // Path mode: the first window's length (metres) and the cap, as a multiple of the path.
  double initial_path = 3.0;
  double path_cap = 2.0;
  // Iterations at full size after the first window that holds the whole scan (the paper: "a
  // few more"; iteration counts are in run.json).
  int extra_iterations = 2;
  // Beyond the paper: iterations after those, still at full size, in which the
  // correspondences use the tighter polish thresholds (refine/correspondences.h). Measured:
  // the paper's final 0.15 m admits closest points on neighbouring surfaces.
  int polish_iterations = 6;
  // Beyond the paper: while the last iteration still moved the poses by more than
  // polish_tolerance (metres, RMS over the poses), up to max_added_polish more polish
  // iterations follow. A loop that SIFT closes only in the first full window moves a part of
  // the scan by decimetres; measured, six polish iterations then left it 4 cm from where it
  // settles. The RMS change of a settled scan is a few millimetres (the
  // correspondences are re-sampled every iteration), so 1 cm ends the added iterations.
  double polish_tolerance = 0.01;
  int max_added_polish = 10;
  // false: the paper's ablation (--no-fine-to-coarse): every iteration has one window that
  // holds the whole scan, as many iterations as the fine-to-coarse schedule would run.
  bool fine_to_coarse = true;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: windows (paper 4.2)");
    F2C_FIELD(v, mode, "--windows", {},
              "frames: l_0 consecutive frames, doubling (the paper); path: by camera path (the authors' code)");
    F2C_FIELD(v, initial_frames, "--window-frames", AtLeast(2), "l_0, frames in the first windows");
    F2C_FIELD(v, initial_path, "--window-path", Positive(), "path windows: the first windows' length (m)");
    F2C_FIELD(v, path_cap, "--window-path-cap", AtLeast(1), "path windows: longest window, times the scan's path");
    F2C_FIELD(v, extra_iterations, "--extra-iterations", AtLeast(0),
              "iterations after one window holds the whole scan");
    F2C_FIELD(v, polish_iterations, "--polish-iterations", AtLeast(0),
              "then this many more with the polish thresholds (beyond the paper; 0: the paper's schedule only)");
    F2C_FIELD(v, polish_tolerance, "--polish-tolerance", Positive(),
              "more polish iterations while the last moved the poses more than this (m, RMS)");
    F2C_FIELD(v, max_added_polish, "--max-added-polish", AtLeast(0), "...at most this many (0: the fixed schedule)");
    F2C_FIELD(v, fine_to_coarse, "!--no-fine-to-coarse", {},
              "the paper's ablation: every iteration has one window holding the whole scan (as many iterations)");
  }
  void Check() const;  // InputError naming the option when out of range
};

struct Window {
  int begin = 0;  // first frame
  int end = 0;    // one past the last frame
};

class WindowSchedule {
 public:
  // `path` is each frame's camera path from the first frame (metres, non-decreasing); only
  // path mode reads it, but it must have one entry per frame.
  WindowSchedule(const WindowOptions& options, std::vector<double> path);

  int frames() const { return static_cast<int>(position_.size()); }
  WindowMode mode() const { return options_.mode; }
  int iterations() const { return iterations_; }
  // Window length of iteration i: frames, or metres in path mode.
  double Length(int iteration) const;
  // Whether iteration i's windows are a single one holding every frame.
  bool Full(int iteration) const;
  // Whether iteration i is one of the polish iterations at the end.
  bool Polishing(int iteration) const { return iteration >= iterations_ - options_.polish_iterations; }
  std::vector<Window> Windows(int iteration) const;
  // Whether frames a and b share a window in iteration i.
  bool Share(int iteration, int a, int b) const;
  // The first iteration in which a and b share a window (iterations() if none).
  int FirstShared(int a, int b) const;
  // One past the last frame that shares a window with frame a in iteration i (frames a..end-1
  // after a all do, since windows are intervals).
  int ShareEnd(int iteration, int a) const;

 private:
  bool whole_scan_only_ = false;
  int LastWindow(int iteration) const;  // index of the window that reaches the end
  WindowOptions options_;
  std::vector<double> position_;  // frame index, or path
  int iterations_ = 0;
};

}  // namespace f2c
