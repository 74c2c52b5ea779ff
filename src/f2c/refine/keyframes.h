#pragma once
// SIFT of keyframes (the odometry's, or every interval-th frame), kept for the loop-pair matcher
// (refine/sift_loops.h): compact (at most max_keypoints points, descriptors as bytes: OpenCV's
// SIFT values are whole numbers in 0..255, so nothing is lost) and cached on disk, so a re-run
// with other refinement options does not decode images again.
//
// Cache format (little-endian), version 1:
//   "F2CKEYS\0"  u32 version  u64 context hash  u32 keyframes
//   per keyframe: u64 key  u32 frame  u32 points  points 3f each  descriptors 128 u8 each
// A keyframe's key hashes its colour and depth files' bytes with the context (SIFT options,
// intrinsics, max_keypoints).

#include <Eigen/Core>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <opencv2/core.hpp>
#include <vector>

#include "f2c/io/sequence.h"
#include "f2c/matching/sift.h"
#include "f2c/util/fields.h"

namespace f2c {

struct KeyframeOptions {
  // Every interval-th frame is a keyframe (frame 0 first); 0: the odometry's keyframes (every
  // 5th frame when the odometry has none, --keyframes off).
  int interval = 0;
  int max_keypoints = 300;  // an even subsample when SIFT found more

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: SIFT loops and bridges (beyond the paper)");
    F2C_FIELD(v, interval, "--keyframe-interval", AtLeast(0),
              "every N-th frame keeps its SIFT for re-matching (0: the odometry's keyframes; every 5th without them)");
    F2C_FIELD(v, max_keypoints, "--keyframe-keypoints", AtLeast(3), "SIFT points kept per keyframe");
  }
  void Check() const;
};

struct Keyframe {
  int frame = -1;
  std::vector<Eigen::Vector3f> points;  // camera coordinates, metres
  cv::Mat descriptors;                  // CV_8U, 128 per row
};

// The keyframe of `frame` from its SIFT (an even subsample of max_keypoints).
Keyframe MakeKeyframe(int frame, const SiftFeatures& sift, int max_keypoints);

// Keyframes' points, measured from colour, moved to their depth's moment
// (Odometry::depth_from_color, indexed by frame; empty: nothing to move).
void ReferToDepthMoments(const std::vector<std::optional<Rigid3d>>& depth_from_color, std::vector<Keyframe>* keyframes);

class KeyframeStore {
 public:
  // `cache_file` (empty: no cache) holds keyframes computed before. `interval` > 0 keeps only
  // every interval-th frame offered; 0 keeps every frame offered.
  KeyframeStore(const RgbdSequence& sequence, const KeyframeOptions& options, const SiftOptions& sift,
                std::filesystem::path cache_file, int interval);
  // Keeps a keyframe's SIFT computed elsewhere (the odometry); any thread.
  void Offer(int frame, const SiftFeatures& sift);
  // The keyframes `frames` (ascending): those offered, then those in the cache, and the rest
  // decoded and described (in parallel). Writes the cache; returns them in frame order.
  std::vector<Keyframe> Finish(const std::vector<int>& frames);
  int computed() const { return computed_; }  // decoded again by Finish()
  int cached() const { return cached_; }

 private:
  const RgbdSequence& seq_;
  KeyframeOptions options_;
  SiftOptions sift_;
  std::filesystem::path cache_file_;
  uint64_t context_ = 0;
  int interval_ = 0;
  std::mutex mutex_;
  std::map<int, Keyframe> offered_;
  int computed_ = 0, cached_ = 0;
};

// The keyframe cache's entries by key, when it was written for `context` (another context:
// none). A missing file gives none; a damaged entry is left out (one warning for the file).
std::map<uint64_t, Keyframe> ReadKeyframeCache(const std::filesystem::path& path, uint64_t context);

// The loop matcher's keyframes: every interval-th frame, or (interval 0) frame 0 and each
// frame the odometry started a keyframe at; every 5th frame when it started none.
std::vector<int> LoopKeyframes(int frames, const KeyframeOptions& options, const std::vector<int>& odometry_keyframes);

}  // namespace f2c
