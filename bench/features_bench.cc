// Feature extraction time per frame on one core, warm: every frame of each sequence in
// ../shared/data is decoded first, then ExtractFrameFeatures runs over all frames on this
// thread alone, `passes` times; the first pass (cold: first-touch allocations) is reported
// apart from the mean of the others. Counts are means per frame.
//   ./build/bench/features_bench [passes] [data dir]

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bench_data.h"
#include "f2c/features/depth_features.h"
#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/util/timer.h"

int main(int argc, char** argv) {
  using namespace f2c;
  const int passes = argc > 1 ? std::max(2, std::stoi(argv[1])) : 3;
  const std::filesystem::path data = argc > 2 ? argv[2] : "../shared/data";
  std::printf(
      "| sequence | frames | proxies | features | ms/frame, 1 core, cold pass | ms/frame, 1 core, warm (mean of %d "
      "passes) |\n",
      passes - 1);
  std::printf("|---|---|---|---|---|---|\n");
  for (const char* name : {"tum_fr1_xyz_15hz", "7scenes_redkitchen_15hz", "tum_fr1_desk_9", "sun3d_mit76_studyroom_5",
                           "open3d_testdata_rgbd"}) {
    const std::optional<RgbdSequence> opened = bench::OpenSequence(data, name);
    if (!opened) continue;
    const RgbdSequence& seq = *opened;
    std::vector<cv::Mat> depths;
    for (const RgbdFrame& f : seq.frames) depths.push_back(LoadDepthMeters(seq, f));
    const FeatureOptions options;
    double cold = 0, warm = 0;
    long proxies = 0, features = 0;
    for (int pass = 0; pass < passes; ++pass) {
      Timer timer;
      for (const cv::Mat& depth : depths) {
        const FrameFeatures f = ExtractFrameFeatures(depth, *seq.intrinsics, options);
        if (pass == 0) proxies += static_cast<long>(f.proxies.size()), features += static_cast<long>(f.features.size());
      }
      (pass == 0 ? cold : warm) += timer.Seconds();
    }
    const double n = static_cast<double>(depths.size());
    std::printf("| %s | %zu | %.1f | %.0f | %.1f | %.1f |\n", name, depths.size(), proxies / n, features / n,
                1000 * cold / n, 1000 * warm / (n * (passes - 1)));
  }
  return 0;
}
