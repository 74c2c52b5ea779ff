// What register reads back from OUTDIR/cache: the feature cache (binary), the keyframe cache
// (binary) and the pair cache (JSON). Each entry carries a checksum, so random bytes mostly
// stop there; each reader is therefore also fed the bytes as an entry whose checksum is
// right, which reaches the parsers behind it. A damaged feature cache read whole is an
// InputError; damaged keyframe and pair entries are left out (recomputed), so no reader may
// throw anything else.
#include <cstring>
#include <nlohmann/json.hpp>

#include "f2c/features/feature_set.h"
#include "f2c/odometry/odometry.h"
#include "f2c/odometry/pair_cache.h"
#include "f2c/refine/keyframes.h"
#include "f2c/util/file.h"
#include "tests/fuzz/fuzz_common.h"

namespace {

template <typename T>
void Put(std::string* out, const T& v) {
  out->append(reinterpret_cast<const char*>(&v), sizeof(T));
}

// A cache file: magic, version, context, a count of 1, then `entry` and its checksum.
std::string OneEntryFile(const char (&magic)[9], uint32_t version, std::string_view entry) {
  std::string file(magic, 8);
  Put(&file, version);
  Put(&file, uint64_t{7});  // context
  Put(&file, uint32_t{1});
  file += entry;
  Put(&file, f2c::HashBytes(entry));
  return file;
}

void Features(std::string_view bytes) {
  uint64_t context = 0;
  const auto raw = f2c::fuzz::WriteInput("features.f2cf", bytes);
  f2c::fuzz::Expect([&] { f2c::ReadFeatureCache(raw, &context); });
  const auto framed = f2c::fuzz::WriteInput("framed.f2cf", OneEntryFile("F2CFEAT\0", 4, bytes));
  f2c::fuzz::Expect([&] { f2c::ReadFeatureCache(framed, &context); });
}

void Keyframes(std::string_view bytes) {
  uint64_t context = 0;  // the file's own, so that its entries are read
  if (bytes.size() >= 20) std::memcpy(&context, bytes.data() + 12, sizeof(context));
  const auto raw = f2c::fuzz::WriteInput("keyframes.f2ck", bytes);
  f2c::fuzz::Expect([&] { f2c::ReadKeyframeCache(raw, context); });
  const auto framed = f2c::fuzz::WriteInput("framed.f2ck", OneEntryFile("F2CKEYS\0", 2, bytes));
  f2c::fuzz::Expect([&] { f2c::ReadKeyframeCache(framed, 7); });
}

void Pairs(std::string_view bytes) {
  const auto raw = f2c::fuzz::WriteInput("odometry_pairs.json", bytes);
  nlohmann::json j = nlohmann::json::parse(bytes, nullptr, false);
  const bool has_pairs = j.is_object() && j.contains("pairs") && j["pairs"].is_object();
  f2c::PairAlignment p;
  {
    const f2c::PairCache cache(raw, "context");
    if (has_pairs) {
      for (const auto& [key, value] : j["pairs"].items()) cache.Lookup(key, &p);
    }
  }
  if (!has_pairs) return;
  // Each entry's "pair" with its checksum made right: the pair parser decides.
  for (auto& [key, value] : j["pairs"].items()) {
    if (value.is_object() && value.contains("pair"))
      value["checksum"] = f2c::HexString(f2c::HashBytes(key + value["pair"].dump()));
  }
  const auto fixed = f2c::fuzz::WriteInput("fixed_pairs.json", j.dump());
  const f2c::PairCache cache(fixed, "context");
  for (const auto& [key, value] : j["pairs"].items()) cache.Lookup(key, &p);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  Features(bytes);
  Keyframes(bytes);
  Pairs(bytes);
  return 0;
}
