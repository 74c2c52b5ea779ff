#pragma once
// SIFT of every interval-th frame (keyframes), kept for the loop-pair matcher
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
#include <nlohmann/json_fwd.hpp>
#include <opencv2/core.hpp>
#include <vector>

#include "f2c/io/sequence.h"
#include "f2c/matching/sift.h"

namespace f2c {

struct KeyframeOptions {
  int interval = 5;         // every interval-th frame is a keyframe (frame 0 first)
  int max_keypoints = 300;  // an even subsample when SIFT found more

  void Check() const;
};

struct Keyframe {
  int frame = -1;
  std::vector<Eigen::Vector3f> points;  // camera coordinates, metres
  cv::Mat descriptors;                  // CV_8U, 128 per row
};

// The keyframe of `frame` from its SIFT (an even subsample of max_keypoints).
Keyframe MakeKeyframe(int frame, const SiftFeatures& sift, int max_keypoints);

class KeyframeStore {
 public:
  // Reads `cache_file` (empty: no cache) for keyframes already computed.
  KeyframeStore(const RgbdSequence& sequence, const KeyframeOptions& options, const SiftOptions& sift,
                std::filesystem::path cache_file);
  bool IsKeyframe(int frame) const { return frame % options_.interval == 0; }
  // Keeps a keyframe's SIFT computed elsewhere (the odometry); any thread, distinct frames.
  void Offer(int frame, const SiftFeatures& sift);
  // Decodes and describes the keyframes still missing (in parallel), writes the cache, and
  // returns them all in frame order.
  std::vector<Keyframe> Finish();
  int computed() const { return computed_; }  // decoded again by Finish()
  int cached() const { return cached_; }

 private:
  const RgbdSequence& seq_;
  KeyframeOptions options_;
  SiftOptions sift_;
  std::filesystem::path cache_file_;
  uint64_t context_ = 0;
  std::vector<int> frames_;           // keyframes
  std::vector<uint64_t> keys_;        // per keyframe
  std::vector<Keyframe> keyframes_;   // per keyframe; frame -1 while missing
  int computed_ = 0, cached_ = 0;
};

nlohmann::json ToJson(const KeyframeOptions& options);

}  // namespace f2c
