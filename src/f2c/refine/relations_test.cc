#include "f2c/refine/relations.h"

#include <gtest/gtest.h>

#include <cmath>

namespace f2c {
namespace {

constexpr double kDeg = M_PI / 180;

TEST(ClassifyRelation, TypeAndWeightByAngle) {
  const RelationOptions options;  // sigma 7.5 deg, within 27 deg, weight > 0.1
  RelationType type;
  double weight = 0;
  ASSERT_TRUE(ClassifyRelation(0, options, &type, &weight));
  EXPECT_EQ(type, RelationType::kParallel);
  EXPECT_DOUBLE_EQ(weight, 1);
  EXPECT_FALSE(ClassifyRelation(45 * kDeg, options, &type, &weight));
  ASSERT_TRUE(ClassifyRelation(80 * kDeg, options, &type, &weight));
  EXPECT_EQ(type, RelationType::kOrthogonal);
  EXPECT_NEAR(weight, std::exp(-100.0 / (2 * 7.5 * 7.5)), 1e-12);  // 0.41
  ASSERT_TRUE(ClassifyRelation(90 * kDeg, options, &type, &weight));
  EXPECT_EQ(type, RelationType::kOrthogonal);
  EXPECT_DOUBLE_EQ(weight, 1);
  ASSERT_TRUE(ClassifyRelation(180 * kDeg, options, &type, &weight));
  EXPECT_EQ(type, RelationType::kAntiparallel);
  EXPECT_NEAR(weight, 1, 1e-12);
  // 14 deg off square (the apartment's trapezoid) is admitted, weakly; 20 deg is not
  // (weight 0.03 < 0.1, though within 0.15 pi).
  ASSERT_TRUE(ClassifyRelation(76 * kDeg, options, &type, &weight));
  EXPECT_NEAR(weight, std::exp(-196.0 / (2 * 7.5 * 7.5)), 1e-12);
  EXPECT_FALSE(ClassifyRelation(70 * kDeg, options, &type, &weight));
}

// Parents A (wall), B (80 degrees from A), C (parallel to A, another room). Frame 0 sees A
// and B; frame 1 sees C alone. By the parents' planes A-B is 86 deg: orthogonal by angle,
// but frame 0 measured 80: dropped. A-C and B-C are kept as the paper has them.
TEST(DetectRelations, AnImageThatSeesBothParentsVetoesARelationItMeasuredFalse) {
  ProxyHierarchy h;
  auto child = [](int frame, const Eigen::Vector3d& n) {
    ChildProxy c;
    c.frame = frame;
    c.normal = n.normalized().cast<float>();
    c.share = 50;
    return c;
  };
  const Eigen::Vector3d a(1, 0, 0), b80(std::cos(80 * kDeg), std::sin(80 * kDeg), 0);
  h.structure.children = {child(0, a), child(0, b80), child(1, a)};
  const Eigen::Vector3d b86(std::cos(86 * kDeg), std::sin(86 * kDeg), 0);
  h.structure.parents = {{a, 0}, {b86, 0}, {Eigen::Vector3d(std::cos(2 * kDeg), std::sin(2 * kDeg), 0), 1}};
  h.child_parents = {{0}, {1}, {2}};
  h.window_parents = {{0, 1, 2}};
  h.parent_window = {0, 0, 0};
  RelationStats stats;
  std::vector<PlaneRelation> relations = DetectRelations(h, RelationOptions(), &stats);
  EXPECT_EQ(stats.dropped_covisible, 1);
  ASSERT_EQ(relations.size(), 2u);
  EXPECT_EQ(relations[0].parent_a, 0);
  EXPECT_EQ(relations[0].parent_b, 2);
  EXPECT_EQ(relations[0].type, RelationType::kParallel);
  EXPECT_NEAR(relations[0].weight, std::exp(-4.0 / (2 * 7.5 * 7.5)), 1e-6);
  EXPECT_EQ(relations[1].type, RelationType::kOrthogonal);  // B-C at 84 deg
  // Without the check the paper's rule keeps all three.
  RelationOptions paper;
  paper.covisible_tolerance_deg = 0;
  relations = DetectRelations(h, paper, &stats);
  EXPECT_EQ(relations.size(), 3u);
  EXPECT_EQ(stats.by_type[static_cast<int>(RelationType::kOrthogonal)], 2);
}

TEST(DetectRelations, AdjacentWindowsOnlyWhenAsked) {
  ProxyHierarchy h;
  ChildProxy c;
  h.structure.children = {c};
  h.structure.parents = {{Eigen::Vector3d::UnitX(), 0}, {Eigen::Vector3d::UnitY(), 0}, {Eigen::Vector3d::UnitZ(), 0}};
  h.child_parents = {{0}};
  h.window_parents = {{0}, {1}, {2}};  // windows 0 and 2 are not adjacent
  RelationStats stats;
  EXPECT_EQ(DetectRelations(h, RelationOptions(), &stats).size(), 2u);
  RelationOptions within;
  within.adjacent_windows = false;
  EXPECT_EQ(DetectRelations(h, within, &stats).size(), 0u);
}

}  // namespace
}  // namespace f2c
