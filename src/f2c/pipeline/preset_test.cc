#include "f2c/pipeline/preset.h"

#include <gtest/gtest.h>

#include "f2c/pipeline/register.h"
#include "f2c/util/fields_json.h"

namespace f2c {
namespace {

TEST(Preset, DefaultChangesNothing) {
  RegisterOptions options;
  ApplyPreset(Preset::kDefault, &options);
  EXPECT_EQ(FieldsToJson(options.refine), FieldsToJson(RefineOptions()));
  EXPECT_EQ(FieldsToJson(options.fusion), FieldsToJson(FusionOptions()));
  EXPECT_EQ(options.preset, Preset::kDefault);
}

TEST(Preset, PaperTurnsOffWhatTheRefinementAddsToThePaper) {
  RegisterOptions options;
  ApplyPreset(Preset::kPaper, &options);
  EXPECT_FALSE(options.refine.loops.enabled);
  EXPECT_EQ(options.refine.windows.polish_iterations, 0);
  EXPECT_EQ(options.refine.solver.weight_velocity, 0.0);
  EXPECT_FALSE(options.refine.local.information);
  EXPECT_FALSE(options.refine.self_check.enabled);
  EXPECT_TRUE(options.refine.structure);  // the paper's structural model stays
  EXPECT_EQ(options.preset, Preset::kPaper);
}

TEST(Preset, AnOptionTheUserGaveKeepsItsValue) {
  RegisterOptions options;
  options.refine.windows.polish_iterations = 5;
  ApplyPreset(Preset::kFast, &options, [](const std::string& flag) { return flag == "--polish-iterations"; });
  EXPECT_EQ(options.refine.windows.polish_iterations, 5);
  EXPECT_EQ(options.fusion.tsdf.voxel_size, 0.02);
  EXPECT_FALSE(options.refine.self_check.enabled);
}

}  // namespace
}  // namespace f2c
