// Every options struct, through its one field list (docs/options.md): the defaults pass, every
// bound is enforced by the struct's own Check() with a message naming the flag, nested
// structs are reached, and no two fields of the register command share a flag.

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <set>
#include <string>
#include <type_traits>

#include "f2c/eval/mesh_error.h"
#include "f2c/eval/trajectory_error.h"
#include "f2c/features/depth_features.h"
#include "f2c/fusion/fuse.h"
#include "f2c/io/sequence.h"
#include "f2c/odometry/odometry.h"
#include "f2c/refine/refine.h"
#include "f2c/report/slice.h"
#include "f2c/sim/simulate.h"
#include "f2c/util/fields_json.h"

namespace f2c {
namespace {

enum class Breach { kBelow, kAbove, kNan };

// Counts the numeric fields (Apply < 0), or puts the target-th one just outside its bounds.
class Breaker {
 public:
  Breaker(int target, Breach breach) : target_(target), breach_(breach) {}
  void Group(const char*) {}
  template <class T>
  void Field(T& value, const char* key, const char* flag, const Bounds& b, const char*) {
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
      if (index_++ != target_) return;
      if constexpr (std::is_unsigned_v<T>) return;  // seeds: any value
      std::optional<double> bad;
      const double step = std::is_integral_v<T> ? 1.0 : 0.5;
      if (breach_ == Breach::kBelow && std::isfinite(b.min)) bad = b.min_open ? b.min : b.min - step;
      if (breach_ == Breach::kAbove && std::isfinite(b.max)) bad = b.max_open ? b.max : b.max + step;
      if (breach_ == Breach::kNan && std::is_floating_point_v<T>) bad = std::nan("");
      if (!bad) return;
      value = static_cast<T>(*bad);
      expected_ = FieldName(flag, key) + ": must be " + b.Describe() + ", got ";
    }
  }
  template <class S>
  void Nested(S& options, const char*, bool = true) {
    options.Fields(*this);
  }
  int count() const { return index_; }
  const std::optional<std::string>& expected() const { return expected_; }

 private:
  int target_;
  Breach breach_;
  int index_ = 0;
  std::optional<std::string> expected_;
};

template <class S>
std::string CheckMessage(const S& options) {
  try {
    options.Check();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Returns how many breaches were checked.
template <class S>
int ExpectEveryBoundEnforced(const char* name) {
  EXPECT_EQ(CheckMessage(S()), "") << name << ": the defaults must pass";
  Breaker counter(-1, Breach::kBelow);
  S counted;
  counted.Fields(counter);
  int checked = 0;
  for (int k = 0; k < counter.count(); ++k) {
    for (Breach breach : {Breach::kBelow, Breach::kAbove, Breach::kNan}) {
      S options;
      Breaker breaker(k, breach);
      options.Fields(breaker);
      if (!breaker.expected()) continue;
      const std::string message = CheckMessage(options);
      EXPECT_EQ(message.rfind(*breaker.expected(), 0), 0u)
          << name << " field " << k << ": '" << message << "' should start '" << *breaker.expected() << "'";
      ++checked;
    }
  }
  return checked;
}

TEST(Options, EveryBoundOfEveryStructIsEnforcedNamingItsFlag) {
  int checked = 0;
  checked += ExpectEveryBoundEnforced<IoOptions>("IoOptions");
  checked += ExpectEveryBoundEnforced<OdometryOptions>("OdometryOptions");
  checked += ExpectEveryBoundEnforced<FeatureOptions>("FeatureOptions");
  checked += ExpectEveryBoundEnforced<RefineOptions>("RefineOptions");
  checked += ExpectEveryBoundEnforced<FusionOptions>("FusionOptions");
  checked += ExpectEveryBoundEnforced<EvaluationOptions>("EvaluationOptions");
  checked += ExpectEveryBoundEnforced<MeshErrorOptions>("MeshErrorOptions");
  checked += ExpectEveryBoundEnforced<SliceOptions>("SliceOptions");
  checked += ExpectEveryBoundEnforced<sim::SimulateOptions>("SimulateOptions");
  EXPECT_GT(checked, 300);  // every double's NaN, and each finite bound from both sides
}

// The flags' long names of a struct, as CLI11 would register them.
class FlagCollector {
 public:
  void Group(const char*) {}
  template <class T>
  void Field(T&, const char*, const char* flag, const Bounds&, const char*) {
    std::string spec = flag;
    spec = spec.substr(0, spec.find('='));
    size_t start = 0;
    while (start < spec.size()) {
      size_t end = spec.find(',', start);
      if (end == std::string::npos) end = spec.size();
      std::string name = spec.substr(start, end - start);
      if (!name.empty() && name[0] == '!') name.erase(0, 1);
      if (!name.empty()) {
        EXPECT_TRUE(names.insert(name).second) << name << " is declared twice";
        EXPECT_EQ(name.rfind("--", 0), 0u) << name;
      }
      start = end + 1;
    }
  }
  template <class S>
  void Nested(S& options, const char*, bool with_flags = true) {
    if (with_flags) options.Fields(*this);
  }
  std::set<std::string> names;
};

TEST(Options, NoTwoFieldsOfRegisterShareAFlag) {
  FlagCollector c;
  IoOptions io;
  OdometryOptions odometry;
  FeatureOptions features;
  RefineOptions refine;
  FusionOptions fusion;
  io.Fields(c);
  odometry.Fields(c);
  features.Fields(c);
  refine.Fields(c);
  fusion.Fields(c);
  EXPECT_GT(c.names.size(), 120u);
  EXPECT_TRUE(c.names.count("--window-frames"));
  EXPECT_TRUE(c.names.count("--no-sift-loops"));
}

TEST(Options, JsonRecordsEveryFieldWithItsValue) {
  RefineOptions o;
  o.windows.initial_frames = 16;
  o.windows.mode = WindowMode::kPath;
  o.relations.sigma_deg = 9;
  o.correspondences.type_weights[4] = 0.7;
  o.loops.ransac.max_iterations = 77;
  const nlohmann::json j = FieldsToJson(o);
  EXPECT_EQ(j["windows"]["initial_frames"], 16);
  EXPECT_EQ(j["windows"]["mode"], "path");
  EXPECT_EQ(j["relations"]["sigma_deg"], 9.0);
  EXPECT_EQ(j["correspondences"]["weight_ridge"], 0.7);
  EXPECT_EQ(j["loops"]["ransac"]["max_iterations"], 77);  // internal copies are recorded too
  EXPECT_EQ(j["solver"]["solve"], "one-step");
}

}  // namespace
}  // namespace f2c
