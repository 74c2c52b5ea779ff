#include "f2c/refine/keyframes.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <tbb/parallel_for.h>

#include <cstring>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "f2c/io/image.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {

void KeyframeOptions::Check() const { CheckFields(*this); }

Keyframe MakeKeyframe(int frame, const SiftFeatures& sift, int max_keypoints) {
  Keyframe k;
  k.frame = frame;
  const int n = static_cast<int>(sift.size());
  const int take = std::min(n, max_keypoints);
  k.descriptors.create(take, 128, CV_8U);
  for (int j = 0; j < take; ++j) {
    const int i = static_cast<int>(static_cast<int64_t>(j) * n / take);
    k.points.push_back(sift.points_in_camera[i].cast<float>());
    sift.descriptors.row(i).convertTo(k.descriptors.row(j), CV_8U);
  }
  return k;
}

void ReferToDepthMoments(const std::vector<std::optional<Rigid3d>>& depth_from_color,
                         std::vector<Keyframe>* keyframes) {
  for (Keyframe& keyframe : *keyframes) {
    if (keyframe.frame >= static_cast<int>(depth_from_color.size()) || !depth_from_color[keyframe.frame]) continue;
    const Eigen::Isometry3f motion = depth_from_color[keyframe.frame]->cast<float>();
    for (Eigen::Vector3f& p : keyframe.points) p = motion * p;
  }
}

namespace {

constexpr char kMagic[8] = {'F', '2', 'C', 'K', 'E', 'Y', 'S', '\0'};
// 2: each entry followed by its checksum (XXH3 of the entry's bytes).
constexpr uint32_t kVersion = 2;

template <typename T>
void Put(std::string* out, const T& v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

}  // namespace

std::map<uint64_t, Keyframe> ReadKeyframeCache(const std::filesystem::path& path, uint64_t context) {
  std::map<uint64_t, Keyframe> out;
  if (path.empty() || !std::filesystem::exists(path)) return out;
  std::string bytes;
  try {
    bytes = ReadFileToString(path);
  } catch (const InputError&) {
    return out;
  }
  size_t at = 0;
  auto need = [&](size_t n) { return bytes.size() - at >= n; };
  auto get = [&](auto* v) {
    std::memcpy(v, bytes.data() + at, sizeof(*v));
    at += sizeof(*v);
  };
  if (!need(8 + 4 + 8 + 4) || std::memcmp(bytes.data(), kMagic, 8) != 0) {
    spdlog::warn("{}: not a keyframe cache; recomputing", path.string());
    return out;
  }
  at = 8;
  uint32_t version, count;
  uint64_t file_context;
  get(&version);
  get(&file_context);
  get(&count);
  if (version != kVersion || file_context != context) return out;  // other options: recompute
  int damaged = 0;
  bool cut = false;
  for (uint32_t e = 0; e < count; ++e) {
    const size_t start = at;
    uint64_t key;
    uint32_t frame, points;
    if (!need(16)) {
      cut = true;
      break;
    }
    get(&key);
    get(&frame);
    get(&points);
    if (!need(static_cast<size_t>(points) * (12 + 128) + 8)) {
      cut = true;
      break;
    }
    Keyframe k;
    k.frame = static_cast<int>(frame);
    k.points.resize(points);
    k.descriptors.create(static_cast<int>(points), 128, CV_8U);
    if (points > 0) {  // memcpy into an empty vector's null data is undefined, even of 0 bytes
      std::memcpy(static_cast<void*>(k.points.data()), bytes.data() + at, points * 12);
      std::memcpy(k.descriptors.data, bytes.data() + at + points * 12, points * 128);
    }
    at += points * (12 + 128);
    const uint64_t sum = HashBytes(std::string_view(bytes).substr(start, at - start));
    uint64_t stored;
    get(&stored);
    if (stored != sum) {
      ++damaged;
      continue;
    }
    out[key] = std::move(k);
  }
  if (damaged > 0 || cut) {
    spdlog::warn("{}: keyframe cache {}; recomputing those keyframes", path.string(), CacheDamage(damaged, cut));
  }
  return out;
}

KeyframeStore::KeyframeStore(const RgbdSequence& sequence, const KeyframeOptions& options, const SiftOptions& sift,
                             std::filesystem::path cache_file, int interval)
    : seq_(sequence), options_(options), sift_(sift), cache_file_(std::move(cache_file)), interval_(interval) {
  options.Check();
  RequireIntrinsics(sequence);
  const nlohmann::json context = {{"max_keypoints", options.max_keypoints},
                                  {"sift",
                                   {{"max_features", sift.max_features},
                                    {"octave_layers", sift.octave_layers},
                                    {"contrast_threshold", sift.contrast_threshold},
                                    {"edge_threshold", sift.edge_threshold},
                                    {"sigma", sift.sigma},
                                    {"downscale", sift.downscale},
                                    {"min_depth", sift.min_depth},
                                    {"max_depth", sift.max_depth},
                                    {"max_depth_spread", sift.max_depth_spread}}}};
  context_ = Fnv1a64(CacheContext(sequence, context.dump()));
  if (!cache_file_.empty()) CheckCacheFile(cache_file_);
}

void KeyframeStore::Offer(int frame, const SiftFeatures& sift) {
  if (interval_ > 0 && frame % interval_ != 0) return;
  Keyframe keyframe = MakeKeyframe(frame, sift, options_.max_keypoints);
  std::lock_guard<std::mutex> lock(mutex_);
  offered_.emplace(frame, std::move(keyframe));
}

std::vector<Keyframe> KeyframeStore::Finish(const std::vector<int>& frames) {
  const int n = static_cast<int>(frames.size());
  std::vector<Keyframe> keyframes(n);
  std::vector<uint64_t> keys(n);
  if (!cache_file_.empty()) {
    tbb::parallel_for(
        0, n, [&](int i) { keys[i] = HashFrameFiles(seq_.frames[frames[i]]) ^ (context_ * 0x9E3779B97F4A7C15ULL); });
  }
  std::map<uint64_t, Keyframe> cache = ReadKeyframeCache(cache_file_, context_);
  std::vector<int> missing;
  for (int i = 0; i < n; ++i) {
    F2C_CHECK(
        frames[i] >= 0 && frames[i] < static_cast<int>(seq_.frames.size()) && (i == 0 || frames[i] > frames[i - 1]),
        "keyframes ascending and in the sequence");
    if (auto it = offered_.find(frames[i]); it != offered_.end()) {
      keyframes[i] = std::move(it->second);
    } else if (auto hit = cache.find(keys[i]); !cache_file_.empty() && hit != cache.end()) {
      keyframes[i] = std::move(hit->second);
      keyframes[i].frame = frames[i];
      ++cached_;
    } else {
      missing.push_back(i);
    }
  }
  offered_.clear();
  tbb::parallel_for(0, static_cast<int>(missing.size()), [&](int m) {
    const int i = missing[m];
    const RgbdFrame& frame = seq_.frames[frames[i]];
    const cv::Mat depth = LoadDepthMeters(seq_, frame);
    const cv::Mat gray = LoadGray(seq_, frame, depth.size());  // as the odometry decodes it
    keyframes[i] =
        MakeKeyframe(frames[i], ExtractSiftWithDepth(gray, depth, *seq_.intrinsics, sift_), options_.max_keypoints);
  });
  computed_ = static_cast<int>(missing.size());
  if (!cache_file_.empty() && cached_ < n) {
    std::string out(kMagic, 8);
    Put(&out, kVersion);
    Put(&out, context_);
    Put(&out, static_cast<uint32_t>(n));
    for (int i = 0; i < n; ++i) {
      const Keyframe& k = keyframes[i];
      const size_t start = out.size();
      Put(&out, keys[i]);
      Put(&out, static_cast<uint32_t>(k.frame));
      Put(&out, static_cast<uint32_t>(k.points.size()));
      out.append(reinterpret_cast<const char*>(k.points.data()), k.points.size() * 12);
      out.append(reinterpret_cast<const char*>(k.descriptors.data), k.points.size() * 128);
      Put(&out, HashBytes(std::string_view(out).substr(start)));
    }
    std::filesystem::create_directories(cache_file_.parent_path().empty() ? "." : cache_file_.parent_path());
    WriteFileAtomic(cache_file_, out);
  }
  return keyframes;
}

std::vector<int> LoopKeyframes(int frames, const KeyframeOptions& options, const std::vector<int>& odometry_keyframes) {
  std::vector<int> out;
  if (options.interval == 0 && !odometry_keyframes.empty()) {
    out = odometry_keyframes;
    if (out.front() != 0) out.insert(out.begin(), 0);
    return out;
  }
  const int interval = options.interval > 0 ? options.interval : 5;
  for (int f = 0; f < frames; f += interval) out.push_back(f);
  return out;
}

}  // namespace f2c
