#include "f2c/odometry/pair_cache.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <nlohmann/json.hpp>

#include "f2c/odometry/odometry.h"
#include "f2c/util/error.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

constexpr int kCacheVersion = 1;

nlohmann::json PairToJson(const PairAlignment& p) {
  std::vector<double> m(16);
  for (int i = 0; i < 16; ++i) m[i] = p.prev_from_curr.matrix()(i / 4, i % 4);
  return {{"frame", p.frame},
          {"prev_from_curr", m},
          {"method", static_cast<int>(p.method)},
          {"keypoints_prev", p.keypoints_prev},
          {"keypoints_curr", p.keypoints_curr},
          {"matches", p.matches},
          {"inliers", p.inliers},
          {"inlier_rmse", p.inlier_rmse},
          {"fitness", p.fitness},
          {"overlap_rmse", p.overlap_rmse}};
}

PairAlignment PairFromJson(const nlohmann::json& j) {
  PairAlignment p;
  p.frame = j.at("frame").get<int>();
  const auto m = j.at("prev_from_curr").get<std::vector<double>>();
  if (m.size() != 16) throw std::runtime_error("matrix size");
  for (int i = 0; i < 16; ++i) p.prev_from_curr.matrix()(i / 4, i % 4) = m[i];
  p.method = static_cast<AlignmentMethod>(j.at("method").get<int>());
  p.keypoints_prev = j.at("keypoints_prev").get<int>();
  p.keypoints_curr = j.at("keypoints_curr").get<int>();
  p.matches = j.at("matches").get<int>();
  p.inliers = j.at("inliers").get<int>();
  p.inlier_rmse = j.at("inlier_rmse").get<double>();
  p.fitness = j.at("fitness").get<double>();
  p.overlap_rmse = j.at("overlap_rmse").get<double>();
  return p;
}

}  // namespace

std::string CacheContext(const RgbdSequence& seq, const std::string& options_json) {
  std::string context = options_json;
  if (seq.intrinsics) {
    const CameraIntrinsics& k = *seq.intrinsics;
    context += fmt::format("|K {:.17g} {:.17g} {:.17g} {:.17g} {} {}", k.fx, k.fy, k.cx, k.cy,
                           k.width, k.height);
  }
  context += fmt::format("|depth {:.17g} {} {}", seq.depth_scale, static_cast<int>(seq.depth_encoding),
                         fmt::join(seq.invalid_depth_values, ","));
  return context;
}

PairCache::PairCache(std::filesystem::path path, std::string context)
    : path_(std::move(path)), context_hash_(Fnv1a64(context)) {
  if (!enabled() || !std::filesystem::exists(path_)) return;
  try {
    const auto j = nlohmann::json::parse(ReadFileToString(path_));
    if (j.at("version").get<int>() != kCacheVersion) {
      spdlog::warn("{}: cache of another version; recomputing", path_.string());
      return;
    }
    for (const auto& [key, value] : j.at("pairs").items()) entries_[key] = value.dump();
  } catch (const std::exception& e) {
    spdlog::warn("{}: unreadable cache ({}); recomputing", path_.string(), e.what());
    entries_.clear();
  }
}

std::string PairCache::Key(uint64_t prev_frame_hash, uint64_t curr_frame_hash) const {
  return HexString(context_hash_ ^ (prev_frame_hash * 0x9E3779B97F4A7C15ULL)) +
         HexString(curr_frame_hash);
}

bool PairCache::Lookup(const std::string& key, PairAlignment* pair) const {
  const auto it = entries_.find(key);
  if (it == entries_.end()) return false;
  try {
    *pair = PairFromJson(nlohmann::json::parse(it->second));
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

void PairCache::Store(const std::string& key, const PairAlignment& pair) {
  if (!enabled()) return;
  entries_[key] = PairToJson(pair).dump();
  dirty_ = true;
}

void PairCache::Save() {
  if (!enabled() || !dirty_) return;
  nlohmann::json pairs = nlohmann::json::object();
  for (const auto& [key, value] : entries_) pairs[key] = nlohmann::json::parse(value);
  const nlohmann::json j = {{"version", kCacheVersion}, {"pairs", pairs}};
  std::filesystem::create_directories(path_.parent_path());
  WriteFileAtomic(path_, j.dump());
  dirty_ = false;
}

}  // namespace f2c
