// SIFT ratio-test matching time per frame pair: OpenCV's BFMatcher (knnMatch, k = 2, what
// MatchSiftRatio used before) against MatchSiftRatio (one matrix product per block of
// queries, matching/sift.h), on real keypoints: frames k and k + 5 of each sequence, at the
// odometry's default SIFT options, one thread. Also checks that both give the same matches.
//   ./build/bench/sift_match_bench [pairs per sequence] [repeats] [data dir]

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bench_data.h"
#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/matching/sift.h"
#include "f2c/util/timer.h"

namespace {

std::vector<f2c::SiftMatch> OpenCvRatio(const f2c::SiftFeatures& query, const f2c::SiftFeatures& train, double ratio) {
  cv::BFMatcher matcher(cv::NORM_L2);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(query.descriptors, train.descriptors, knn, 2);
  std::vector<f2c::SiftMatch> out;
  for (const auto& m : knn) {
    if (m.size() == 2 && m[0].distance < ratio * m[1].distance) out.push_back({m[0].queryIdx, m[0].trainIdx});
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace f2c;
  cv::setNumThreads(1);
  const int pairs = argc > 1 ? std::max(1, std::stoi(argv[1])) : 20;
  const int repeats = argc > 2 ? std::max(1, std::stoi(argv[2])) : 5;
  const std::filesystem::path data = argc > 3 ? argv[3] : "../shared/data";
  std::printf(
      "| sequence | pairs | keypoints per frame | OpenCV BFMatcher (ms/pair) | MatchSiftRatio (ms/pair) | same matches "
      "|\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (const char* name : {"tum_fr1_xyz_15hz", "7scenes_redkitchen_15hz"}) {
    const std::optional<RgbdSequence> opened = bench::OpenSequence(data, name);
    if (!opened) continue;
    const RgbdSequence& seq = *opened;
    const SiftOptions options;
    std::vector<std::pair<SiftFeatures, SiftFeatures>> frames;
    const int step = std::max<int>(1, (static_cast<int>(seq.frames.size()) - 6) / pairs);
    double keypoints = 0;
    for (int k = 0; k + 5 < static_cast<int>(seq.frames.size()) && static_cast<int>(frames.size()) < pairs; k += step) {
      auto extract = [&](int i) {
        const cv::Mat depth = LoadDepthMeters(seq, seq.frames[i]);
        return ExtractSiftWithDepth(LoadGray(seq, seq.frames[i], depth.size()), depth, *seq.intrinsics, options);
      };
      frames.emplace_back(extract(k + 5), extract(k));
      keypoints += frames.back().first.size() + frames.back().second.size();
    }
    bool same = true;
    double opencv_s = 0, ours_s = 0;
    for (int r = 0; r < repeats; ++r) {
      for (const auto& [query, train] : frames) {
        Timer a;
        const std::vector<SiftMatch> x = OpenCvRatio(query, train, 0.8);
        opencv_s += a.Seconds();
        Timer b;
        const std::vector<SiftMatch> y = MatchSiftRatio(query, train, 0.8, 0.8, 0);
        ours_s += b.Seconds();
        same = same && x.size() == y.size() &&
               std::equal(x.begin(), x.end(), y.begin(), [](const SiftMatch& p, const SiftMatch& q) {
                 return p.query == q.query && p.train == q.train;
               });
      }
    }
    const double n = static_cast<double>(frames.size()) * repeats;
    std::printf("| %s | %zu | %.0f | %.2f | %.2f | %s |\n", name, frames.size(), keypoints / (2.0 * frames.size()),
                1000 * opencv_s / n, 1000 * ours_s / n, same ? "yes" : "no");
  }
  return 0;
}
