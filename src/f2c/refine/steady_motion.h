#pragma once
// E_V's constraints (beyond the paper; optim/cost_functions.h, SteadyMotionCost): every three
// frames consecutive in time, frames k - 1, k, k + 1. A hand-held camera's velocity changes
// little from one frame to the next at video rate, so E_V asks each triple to move steadily;
// it decides only where nothing else does (a camera facing one plain wall, an odometry pair
// that E_L would otherwise repeat).
//
// Time stamps set the scales. E_V compares velocities, each increment divided by its own
// interval, in units of one frame at reference_rate (a depth camera's 30 Hz): an increment
// over dt counts (1 / reference_rate) / dt times, so a dropped frame does not read as a jolt,
// and at a lower frame rate, where a hand-held camera's motion changes more from one frame
// to the next, E_V asks for proportionally less. A triple whose interval exceeds max_gap
// times the median, or is not positive, is left out: across a gap (a recording paused, a long
// run of missing frames) the motion is not predictable.

#include <vector>

#include "f2c/optim/constraints.h"
#include "f2c/util/fields.h"

namespace f2c {

struct SteadyMotionOptions {
  double reference_rate = 30;  // Hz: velocities in units of one frame at this rate
  double max_gap = 3;          // intervals longer than this times the median break the chain
  // Where an odometry pair left directions to the motion prior (an ICP fallback facing a plain
  // wall, or the prior itself), the prior was the odometry's only measurement of them, and
  // E_L holds them no better than that (refine/local_alignment.h); a triple that contains such
  // a pair weighs this many times a plain one. Measured: 3 against 1 with E_L
  // whitened through the fallbacks; 10 once the polish iterations
  // sample 600 n correspondences (refine/correspondences.h).
  double unmeasured_weight = 10;

  template <class V>
  void Fields(V& v) {
    v.Group("Refinement: energy and solver (paper 4.3)");
    F2C_FIELD(v, reference_rate, "--velocity-reference-rate", Positive(),
              "E_V compares velocities in units of one frame at this rate (Hz)");
    F2C_FIELD(v, max_gap, "--velocity-max-gap", AtLeast(1),
              "E_V leaves out triples with an interval over this times the median interval");
    F2C_FIELD(v, unmeasured_weight, "--velocity-unmeasured-weight", AtLeast(0),
              "E_V triples containing an odometry pair that left directions to the motion prior weigh this much");
  }
  void Check() const;
};

// One constraint per triple (k - 1, k, k + 1) whose two intervals are within the gap;
// `timestamps` in seconds, one per frame, in frame order. unmeasured[k] (optional, one per
// frame): frame k's odometry pair left directions to the motion prior.
std::vector<SteadyMotionConstraint> SteadyMotionConstraints(const std::vector<double>& timestamps,
                                                            const SteadyMotionOptions& options,
                                                            const std::vector<char>& unmeasured = {});

}  // namespace f2c
