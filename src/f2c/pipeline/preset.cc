#include "f2c/pipeline/preset.h"

#include "f2c/pipeline/register.h"

namespace f2c {

std::vector<PresetSetting> PresetSettings(Preset preset) {
  // What fine2coarse adds to the paper's refinement, each off.
  const std::vector<PresetSetting> paper = {
      {"--no-sift-loops", [](RegisterOptions* o) { o->refine.loops.enabled = false; }},
      {"--polish-iterations", [](RegisterOptions* o) { o->refine.windows.polish_iterations = 0; }},
      {"--weight-velocity", [](RegisterOptions* o) { o->refine.solver.weight_velocity = 0; }},
      {"--local-information", [](RegisterOptions* o) { o->refine.local.information = false; }},
      {"--no-self-check", [](RegisterOptions* o) { o->refine.self_check.enabled = false; }},
  };
  // Where the default's time goes that buys the least accuracy: the 1 cm mesh (2 cm holds an
  // eighth of the voxels), the last three polish iterations, the self-check. Fewer features
  // (--feature-step 8) or no polish iterations at all cost far more (BENCHMARKS.md, "Presets").
  const std::vector<PresetSetting> fast = {
      {"--voxel-size", [](RegisterOptions* o) { o->fusion.tsdf.voxel_size = 0.02; }},
      {"--polish-iterations", [](RegisterOptions* o) { o->refine.windows.polish_iterations = 3; }},
      {"--no-self-check", [](RegisterOptions* o) { o->refine.self_check.enabled = false; }},
  };
  switch (preset) {
    case Preset::kPaper:
      return paper;
    case Preset::kFast:
      return fast;
    case Preset::kDefault:
      break;
  }
  return {};
}

void ApplyPreset(Preset preset, RegisterOptions* options, const std::function<bool(const std::string& flag)>& given) {
  for (const PresetSetting& s : PresetSettings(preset)) {
    if (!given || !given(s.flag)) s.apply(options);
  }
  options->preset = preset;
}

}  // namespace f2c
