#include "f2c/refine/windows.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "f2c/util/error.h"

namespace f2c {

void WindowOptions::Check() const { CheckFields(*this); }

WindowSchedule::WindowSchedule(const WindowOptions& options, std::vector<double> path) : options_(options) {
  options.Check();
  const int n = static_cast<int>(path.size());
  F2C_CHECK(n >= 1, "a schedule needs frames");
  if (options.mode == WindowMode::kPath) {
    position_ = std::move(path);
    for (int k = 1; k < n; ++k) F2C_CHECK(position_[k] >= position_[k - 1], "path must not decrease");
  } else {
    position_.resize(n);
    for (int k = 0; k < n; ++k) position_[k] = k;
  }
  int growth = 0;
  while (!Full(growth)) ++growth;
  iterations_ = growth + 1 + options.extra_iterations + options.polish_iterations;
  // The ablation: as many iterations, each with the whole scan in one window.
  whole_scan_only_ = !options.fine_to_coarse;
}

double WindowSchedule::Length(int iteration) const {
  if (whole_scan_only_) iteration = 60;
  const double doubling = std::ldexp(1.0, std::min(iteration, 60));
  if (options_.mode == WindowMode::kFrames) {
    return std::min(options_.initial_frames * doubling, std::max<double>(frames(), options_.initial_frames));
  }
  const double cap = std::max(options_.path_cap * position_.back(), options_.initial_path);
  return std::min(options_.initial_path * doubling, cap);
}

bool WindowSchedule::Full(int iteration) const { return position_.back() < Length(iteration); }

int WindowSchedule::LastWindow(int iteration) const {
  const double length = Length(iteration);
  const double half = length / 2;
  const double total = position_.back();
  int last = total < length ? 0 : static_cast<int>(std::floor((total - length) / half)) + 1;
  while (last * half + length <= total) ++last;
  while (last > 0 && (last - 1) * half + length > total) --last;
  return last;
}

std::vector<Window> WindowSchedule::Windows(int iteration) const {
  const double length = Length(iteration);
  const double half = length / 2;
  std::vector<Window> windows;
  for (int j = 0; j <= LastWindow(iteration); ++j) {
    Window w;
    w.begin = static_cast<int>(std::lower_bound(position_.begin(), position_.end(), j * half) - position_.begin());
    w.end =
        static_cast<int>(std::lower_bound(position_.begin(), position_.end(), j * half + length) - position_.begin());
    if (w.end > w.begin) windows.push_back(w);
  }
  return windows;
}

int WindowSchedule::ShareEnd(int iteration, int a) const {
  const double length = Length(iteration);
  const double half = length / 2;
  // The window that starts last at or before frame a reaches farthest.
  const int j = std::min(static_cast<int>(std::floor(position_[a] / half)), LastWindow(iteration));
  return static_cast<int>(std::lower_bound(position_.begin(), position_.end(), j * half + length) - position_.begin());
}

bool WindowSchedule::Share(int iteration, int a, int b) const {
  if (a > b) std::swap(a, b);
  return b < ShareEnd(iteration, a);
}

int WindowSchedule::FirstShared(int a, int b) const {
  for (int i = 0; i < iterations_; ++i) {
    if (Share(i, a, b)) return i;
  }
  return iterations_;
}

}  // namespace f2c
