// TUM RGB-D layout: rgb.txt and depth.txt list `timestamp filename`; groundtruth.txt holds
// `timestamp tx ty tz qx qy qz qw` at 100 Hz. Depth PNGs hold metres * 5000.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "f2c/io/readers.h"
#include "f2c/util/error.h"
#include "f2c/util/text.h"

namespace f2c::internal {
namespace fs = std::filesystem;

namespace {

struct StampedFile {
  double timestamp;
  fs::path path;
};

// The list in time order: a list out of order is sorted (with one warning: frames read in
// line order would make odometry jump, and the trajectory written would not be in time order,
// which our own evaluate and fuse refuse); a time stamp listed twice is an error (which image
// is that moment?).
std::vector<StampedFile> ReadFileList(const fs::path& list, const fs::path& dir) {
  std::vector<StampedFile> files;
  std::vector<int> lines;
  for (const TextLine& line : ReadDataLines(list)) {
    const auto tokens = SplitWhitespace(line.text);
    double t = 0;
    if (tokens.size() != 2 || !ParseDouble(tokens[0], &t)) {
      ThrowInputError(list, line.number, "expected 'timestamp filename'");
    }
    files.push_back({t, dir / tokens[1]});
    lines.push_back(line.number);
  }
  if (files.empty()) ThrowInputError(list, "lists no image");
  std::vector<size_t> order(files.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return files[a].timestamp < files[b].timestamp; });
  for (size_t k = 1; k < order.size(); ++k) {
    if (files[order[k]].timestamp == files[order[k - 1]].timestamp) {
      const size_t later = std::max(order[k], order[k - 1]), earlier = std::min(order[k], order[k - 1]);
      ThrowInputError(list, lines[later],
                      fmt::format("time stamp {:.6f} listed again (line {})", files[later].timestamp, lines[earlier]));
    }
  }
  if (!std::is_sorted(order.begin(), order.end())) {
    spdlog::warn("{}: images listed out of time order; read in time order", list.string());
    std::vector<StampedFile> sorted;
    for (size_t i : order) sorted.push_back(files[i]);
    files = std::move(sorted);
  }
  return files;
}

}  // namespace

std::vector<std::pair<size_t, size_t>> AssociateTimestamps(const std::vector<double>& a, const std::vector<double>& b,
                                                           double max_difference) {
  // Candidate pairs within the window; b sorted so each a needs one binary search.
  std::vector<size_t> b_order(b.size());
  for (size_t i = 0; i < b.size(); ++i) b_order[i] = i;
  std::sort(b_order.begin(), b_order.end(), [&](size_t x, size_t y) { return b[x] < b[y]; });
  std::vector<double> b_sorted(b.size());
  for (size_t i = 0; i < b.size(); ++i) b_sorted[i] = b[b_order[i]];
  struct Candidate {
    double difference;
    size_t ia, ib;
  };
  std::vector<Candidate> candidates;
  for (size_t ia = 0; ia < a.size(); ++ia) {
    auto it = std::lower_bound(b_sorted.begin(), b_sorted.end(), a[ia] - max_difference);
    for (; it != b_sorted.end() && *it <= a[ia] + max_difference; ++it) {
      const size_t ib = b_order[it - b_sorted.begin()];
      candidates.push_back({std::abs(a[ia] - b[ib]), ia, ib});
    }
  }
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const Candidate& x, const Candidate& y) { return x.difference < y.difference; });
  std::vector<bool> used_a(a.size(), false), used_b(b.size(), false);
  std::vector<std::pair<size_t, size_t>> matches;
  for (const Candidate& c : candidates) {
    if (used_a[c.ia] || used_b[c.ib]) continue;
    used_a[c.ia] = used_b[c.ib] = true;
    matches.emplace_back(c.ia, c.ib);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

void StampFrame(double color_stamp, double depth_stamp, FrameStamp stamp, RgbdFrame& frame) {
  frame.timestamp = stamp == FrameStamp::kDepth ? depth_stamp : color_stamp;
  frame.color_time = color_stamp - frame.timestamp;
}

void SortFramesByTime(std::vector<RgbdFrame>& frames) {
  std::stable_sort(frames.begin(), frames.end(),
                   [](const RgbdFrame& a, const RgbdFrame& b) { return a.timestamp < b.timestamp; });
}

RgbdSequence ReadTum(const fs::path& dir, const IoOptions& options) {
  const auto colors = ReadFileList(dir / "rgb.txt", dir);
  const auto depths = ReadFileList(dir / "depth.txt", dir);
  std::vector<double> tc, td;
  for (const auto& f : colors) tc.push_back(f.timestamp);
  for (const auto& f : depths) td.push_back(f.timestamp);
  RgbdSequence seq;
  seq.depth_scale = 1.0 / 5000.0;
  for (const auto& [ic, id] : AssociateTimestamps(tc, td, options.max_time_difference)) {
    RgbdFrame frame;
    StampFrame(colors[ic].timestamp, depths[id].timestamp, options.stamp, frame);
    frame.color_path = colors[ic].path;
    frame.depth_path = depths[id].path;
    frame.name = frame.depth_path.filename().string();
    seq.frames.push_back(frame);
  }
  SortFramesByTime(seq.frames);
  if (seq.frames.empty()) {
    ThrowInputError(dir / "depth.txt", fmt::format("no depth image within {} s of a colour image in rgb.txt",
                                                   options.max_time_difference));
  }
  if (seq.frames.size() < colors.size()) {
    spdlog::warn("{}: {} of {} colour images have no depth image within {} s (depth.txt): left out",
                 (dir / "rgb.txt").string(), colors.size() - seq.frames.size(), colors.size(),
                 options.max_time_difference);
  }
  // TUM folders carry no intrinsics; ours (the simulator's) add camera-intrinsics.txt.
  if (fs::exists(dir / "camera-intrinsics.txt")) {
    seq.intrinsics = ReadIntrinsicsMatrixFile(dir / "camera-intrinsics.txt");
    seq.intrinsics_source = (dir / "camera-intrinsics.txt").string();
  }
  if (fs::exists(dir / "groundtruth.txt")) {
    seq.ground_truth = ReadTumTrajectory(dir / "groundtruth.txt");
    seq.ground_truth_source = dir / "groundtruth.txt";
  }
  return seq;
}

}  // namespace f2c::internal
