#pragma once
// Quality presets: a few coherent sets of option values, so that a user picks one word
// instead of a dozen knobs. `default` is every option's default; `paper` is the paper's
// algorithm alone (none of what fine2coarse adds beyond it: SIFT loops, steady motion E_V,
// added polish iterations, E_L weighed by each pair's information, the self-check); `fast`
// takes a third off the default's time end to end at a small cost in accuracy (BENCHMARKS.md,
// "Presets").

#include <functional>
#include <string>
#include <vector>

#include "f2c/util/fields.h"

namespace f2c {

struct RegisterOptions;

enum class Preset { kDefault, kFast, kPaper };
F2C_ENUM_NAMES(Preset, {{Preset::kDefault, "default"}, {Preset::kFast, "fast"}, {Preset::kPaper, "paper"}})

// One value a preset sets: the option's flag, as the command line spells it, and the change.
struct PresetSetting {
  std::string flag;
  std::function<void(RegisterOptions*)> apply;
};
std::vector<PresetSetting> PresetSettings(Preset preset);

// Sets `preset`'s values in `options`, except those whose flag `given` says the user set
// (an option given beside a preset wins over it).
void ApplyPreset(Preset preset, RegisterOptions* options,
                 const std::function<bool(const std::string& flag)>& given = nullptr);

}  // namespace f2c
