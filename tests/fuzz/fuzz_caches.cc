// What register reads back from OUTDIR/cache: the feature cache (binary) and the pair cache
// (JSON). A damaged feature cache is an InputError; a damaged pair cache is ignored (or its
// entry recomputed), so neither may throw anything else.
#include <nlohmann/json.hpp>

#include "f2c/features/feature_set.h"
#include "f2c/odometry/odometry.h"
#include "f2c/odometry/pair_cache.h"
#include "tests/fuzz/fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const auto features = f2c::fuzz::WriteInput("features.f2cf", bytes);
  uint64_t context = 0;
  f2c::fuzz::Expect([&] { f2c::ReadFeatureCache(features, &context); });
  const auto pairs = f2c::fuzz::WriteInput("odometry_pairs.json", bytes);
  const f2c::PairCache cache(pairs, "context");
  // Every key the file holds, looked up as register would.
  const nlohmann::json j = nlohmann::json::parse(bytes, nullptr, false);
  if (j.is_object() && j.contains("pairs") && j["pairs"].is_object()) {
    f2c::PairAlignment p;
    for (const auto& [key, value] : j["pairs"].items()) cache.Lookup(key, &p);
  }
  return 0;
}
