#pragma once
// A hand-held walk through a scene's waypoints: ~1 m/s, eye height ~1.5 m, the head
// sweeping left and right, a small shake; when the frames outlast the route it walks back,
// so long sequences revisit rooms (loop closures). In a scene with an orbit (an object scan)
// the camera circles the object instead (scene.h's Orbit), and the route's options (speed
// aside, which scales the orbit's pace; eye height, pitch, sweep, turn rate) do not apply.

#include <cstdint>

#include "f2c/io/trajectory.h"
#include "f2c/sim/scene.h"
#include "f2c/util/fields.h"

namespace f2c::sim {

struct WalkOptions {
  int frames = 900;
  double fps = 30.0;
  double speed = 1.0;         // metres per second along the route
  double eye_height = 1.5;    // metres
  double pitch_deg = -15.0;   // looking slightly down
  double sweep_deg = 35.0;    // head turning amplitude around the walking direction
  double sweep_period = 6.0;  // seconds
  // People turn their body at a bounded rate: the walking direction the head sweeps around
  // follows the route's direction at most this fast (degrees per second), so dead ends and
  // corners become gradual turns instead of jumps.
  double max_turn_rate_deg = 60.0;
  double shake_translation = 0.004;  // metres (hand tremor, smooth)
  double shake_rotation_deg = 0.4;
  uint64_t seed = 0;

  template <class V>
  void Fields(V& v) {
    v.Group("Simulation");
    F2C_FIELD(v, frames, "--frames", Between(1, 100000), "frames at 30 Hz (at most 100,000: 55 minutes of walking)");
    F2C_FIELD(v, fps, "", Positive(), "frame rate (Hz)");
    F2C_FIELD(v, speed, "", Positive(), "walking speed (m/s)");
    F2C_FIELD(v, eye_height, "", Positive(), "camera height (m)");
    F2C_FIELD(v, pitch_deg, "", Between(-90, 90), "camera pitch (deg)");
    F2C_FIELD(v, sweep_deg, "", Between(0, 180), "head sweep amplitude (deg)");
    F2C_FIELD(v, sweep_period, "", Positive(), "head sweep period (s)");
    F2C_FIELD(v, max_turn_rate_deg, "", Positive(), "fastest body turn (deg/s)");
    F2C_FIELD(v, shake_translation, "", AtLeast(0), "hand shake (m)");
    F2C_FIELD(v, shake_rotation_deg, "", AtLeast(0), "hand shake (deg)");
    F2C_FIELD(v, seed, "", {}, "seed of the walk");
  }
  void Check() const;
};

// world_from_camera per frame (camera x right, y down, z forward), time stamps i / fps.
Trajectory GenerateWalk(const Scene& scene, const WalkOptions& options);

}  // namespace f2c::sim
