#include "f2c/odometry/pair_cache.h"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "f2c/odometry/odometry.h"
#include "f2c/testing/log_capture.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {

PairAlignment SomePair() {
  PairAlignment p;
  p.frame = 5, p.reference = 3, p.keyframe = true;
  p.prev_from_curr.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  p.prev_from_curr.translation() = Eigen::Vector3d(0.01, -0.02, 0.03);
  p.method = AlignmentMethod::kIcp;
  p.keypoints_prev = 300, p.keypoints_curr = 280, p.matches = 120, p.inliers = 100;
  p.inlier_rmse = 0.004, p.fitness = 0.93, p.overlap_rmse = 0.006, p.degenerate = 1;
  return p;
}

// The reason a damaged entry is refused (empty: accepted).
std::string Refusal(const nlohmann::json& j) {
  try {
    PairAlignmentFromJson(j);
    return "";
  } catch (const std::exception& e) {
    return e.what();
  }
}

TEST(PairAlignmentJson, RoundTripsEveryField) {
  const PairAlignment a = SomePair();
  const PairAlignment b = PairAlignmentFromJson(ToJson(a));
  EXPECT_EQ(b.frame, 5);
  EXPECT_EQ(b.reference, 3);
  EXPECT_TRUE(b.keyframe);
  EXPECT_TRUE(b.prev_from_curr.isApprox(a.prev_from_curr, 1e-15));
  EXPECT_EQ(b.method, AlignmentMethod::kIcp);
  EXPECT_EQ(b.matches, 120);
  EXPECT_EQ(b.inliers, 100);
  EXPECT_DOUBLE_EQ(b.fitness, 0.93);
  EXPECT_EQ(b.degenerate, 1);
  // Old caches have no reference: the previous frame.
  nlohmann::json old = ToJson(a);
  old.erase("reference");
  EXPECT_EQ(PairAlignmentFromJson(old).Reference(), 4);
}

// A pair's information travels as its 36 entries (SIFT, tracked and ICP pairs), bit for bit
// even where rounding left it not quite symmetric (a cached run then refines exactly as the
// run that computed it); 21 upper-triangle entries (older files) read as the symmetric
// matrix; a motion-prior pair carries none, and entries without it read back as unmeasured.
TEST(PairAlignmentJson, InformationOfFittedPairsRoundTrips) {
  PairAlignment a = SomePair();
  a.method = AlignmentMethod::kTrack;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) a.information(r, c) = r == c ? 1e6 * (r + 1) : 10.0 * (r + c);
  }
  a.information(2, 1) = std::nextafter(a.information(1, 2), 1e9);
  const nlohmann::json j = ToJson(a);
  ASSERT_EQ(j.at("information").size(), 36u);
  EXPECT_EQ(j.at("information")[1].get<double>(), 10.0);  // row 0, column 1
  EXPECT_EQ(PairAlignmentFromJson(j).information, a.information);
  nlohmann::json upper = j;
  upper["information"] = nlohmann::json::array();
  for (int r = 0; r < 6; ++r) {
    for (int c = r; c < 6; ++c) upper["information"].push_back(a.information(r, c));
  }
  const Eigen::Matrix<double, 6, 6> symmetric = PairAlignmentFromJson(upper).information;
  EXPECT_EQ(symmetric, symmetric.transpose());
  EXPECT_EQ(symmetric(2, 1), a.information(1, 2));
  a.method = AlignmentMethod::kIcp;
  EXPECT_EQ(PairAlignmentFromJson(ToJson(a)).information, a.information);
  a.method = AlignmentMethod::kMotionPrior;
  EXPECT_FALSE(ToJson(a).contains("information"));
  EXPECT_TRUE(PairAlignmentFromJson(ToJson(a)).information.isZero());
  nlohmann::json short_list = j, negative = j;
  short_list["information"].erase(0);
  negative["information"][0] = -1.0;
  EXPECT_EQ(Refusal(short_list), "information needs 36 numbers (or its 21 upper-triangle ones)");
  EXPECT_EQ(Refusal(negative), "information is not finite or has a negative diagonal");
}

TEST(PairAlignmentJson, DamagedEntriesAreRefusedWithTheReason) {
  auto with = [](const char* key, const nlohmann::json& value) {
    nlohmann::json j = ToJson(SomePair());
    j[key] = value;
    return j;
  };
  std::vector<double> m = ToJson(SomePair())["prev_from_curr"].get<std::vector<double>>();
  std::vector<double> scaled = m, sheared = m, far = m, bottom = m;
  for (int i : {0, 5, 10}) scaled[i] *= 2;
  sheared[1] += 0.3;
  far[3] = 1e6;
  bottom[12] = 1;
  EXPECT_EQ(Refusal(with("prev_from_curr", scaled)), "prev_from_curr is not a rotation");
  EXPECT_EQ(Refusal(with("prev_from_curr", sheared)), "prev_from_curr is not a rotation");
  EXPECT_EQ(Refusal(with("prev_from_curr", far)), "prev_from_curr moves more than 100 m");
  EXPECT_EQ(Refusal(with("prev_from_curr", bottom)), "prev_from_curr's last row is not 0 0 0 1");
  EXPECT_EQ(Refusal(with("prev_from_curr", std::vector<double>(15, 0.0))), "prev_from_curr needs 16 numbers");
  EXPECT_EQ(Refusal(with("reference", 7)), "reference must precede frame");
  EXPECT_EQ(Refusal(with("method", "magic")), "unknown method magic");
  EXPECT_EQ(Refusal(with("fitness", 1.5)), "fitness outside [0, 1]");
  EXPECT_EQ(Refusal(with("inliers", 500)), "negative or inconsistent counts");
  EXPECT_EQ(Refusal(with("inlier_rmse", -1)), "an RMSE is negative or not finite");
  // Counts that are not whole numbers within int (a fuzz finding: 2.3e89 was converted with
  // undefined behaviour, 3.5 silently to 3).
  EXPECT_EQ(Refusal(with("matches", 2.3e89)), "matches is not a whole number");
  EXPECT_EQ(Refusal(with("keypoints_prev", 3.5)), "keypoints_prev is not a whole number");
  EXPECT_EQ(Refusal(with("frame", uint64_t{1} << 40)), "frame is out of range");
  EXPECT_EQ(Refusal(with("degenerate", "yes")), "degenerate is not a whole number");
  EXPECT_NE(Refusal(with("prev_from_curr", nullptr)), "");  // NaN is written as null
  EXPECT_EQ(Refusal(ToJson(SomePair())), "");
}

TEST(PairCache, ADamagedEntryIsAMissAndTheOthersAreUsed) {
  const auto dir = testing::FreshTempDir("pair_cache_damaged");
  const auto path = dir / "cache.json";
  {
    PairCache cache(path, "context");
    cache.Store("good", SomePair());
    cache.Store("bad", SomePair());
    cache.Save();
  }
  // Damage one entry as a disk or a hand edit could: its translation moved by 5 cm, a
  // well-formed pair that only its checksum tells from the one computed.
  nlohmann::json j = nlohmann::json::parse(ReadFileToString(path));
  j["pairs"]["bad"]["pair"]["prev_from_curr"][3] = j["pairs"]["bad"]["pair"]["prev_from_curr"][3].get<double>() + 0.05;
  WriteFileAtomic(path, j.dump());
  testing::LogCapture log;
  const PairCache cache(path, "context");
  EXPECT_EQ(log.Lines(),
            std::vector<std::string>{path.string() + ": 1 cached pair fails its checksum (edited or damaged); "
                                                     "recomputing"});
  PairAlignment p;
  EXPECT_TRUE(cache.Lookup("good", &p));
  EXPECT_TRUE(p.prev_from_curr.isApprox(SomePair().prev_from_curr, 1e-15));
  EXPECT_FALSE(cache.Lookup("bad", &p));
  EXPECT_FALSE(cache.Lookup("absent", &p));
  // A file that is not JSON, or of another version, is ignored as a whole.
  WriteFileAtomic(path, "{not json");
  EXPECT_FALSE(PairCache(path, "context").Lookup("good", &p));
  WriteFileAtomic(path, R"({"version": 1, "pairs": {}})");
  EXPECT_FALSE(PairCache(path, "context").Lookup("good", &p));
  // What is not a regular file is an error naming it, not a cache read until memory ends.
  const auto zero = dir / "zero.json";
  std::filesystem::create_symlink("/dev/zero", zero);
  EXPECT_EQ(testing::InputErrorMessage([&] { PairCache(zero, "context"); }),
            zero.string() + ": cache is not a regular file (a device, FIFO or socket)");
}

}  // namespace
}  // namespace f2c
