#include "f2c/sim/walk.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "f2c/util/error.h"

namespace f2c::sim {
namespace {

using Vec2 = Eigen::Vector2d;

// Dense points of a Catmull-Rom spline through the waypoints (smooth turns at corners).
std::vector<Vec2> SmoothRoute(const std::vector<Vec2>& w) {
  std::vector<Vec2> route;
  for (size_t i = 0; i + 1 < w.size(); ++i) {
    const Vec2 p0 = w[i > 0 ? i - 1 : i], p1 = w[i], p2 = w[i + 1], p3 = w[i + 2 < w.size() ? i + 2 : i + 1];
    const int steps = std::max(2, static_cast<int>((p2 - p1).norm() / 0.01));
    for (int s = 0; s < steps; ++s) {
      const double t = static_cast<double>(s) / steps, t2 = t * t, t3 = t2 * t;
      route.push_back(
          0.5 * (2 * p1 + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2 + (-p0 + 3 * p1 - 3 * p2 + p3) * t3));
    }
  }
  route.push_back(w.back());
  return route;
}

// A smooth random signal in [-1, 1]: three sines of random frequency (0.3-2 Hz) and phase.
struct Wobble {
  double f[3], phase[3];
  explicit Wobble(std::mt19937_64* rng) {
    std::uniform_real_distribution<double> freq(0.3, 2.0), ph(0, 2 * M_PI);
    for (int i = 0; i < 3; ++i) {
      f[i] = freq(*rng);
      phase[i] = ph(*rng);
    }
  }
  double operator()(double t) const {
    double s = 0;
    for (int i = 0; i < 3; ++i) s += std::sin(2 * M_PI * f[i] * t + phase[i]);
    return s / 3.0;
  }
};

// The unit viewing direction of a camera turned by `yaw` about the vertical (from +x) and
// tilted by `pitch` (up positive), radians.
Eigen::Vector3d Forward(double yaw, double pitch) {
  return {std::cos(yaw) * std::cos(pitch), std::sin(yaw) * std::cos(pitch), std::sin(pitch)};
}

// world_from_camera of a camera at `position` looking along `forward` (camera x right,
// y down, z forward; the image's horizon level), rolled by `roll` about its axis.
Rigid3d LookAlong(const Eigen::Vector3d& position, const Eigen::Vector3d& forward, double roll) {
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Matrix3d r;
  r << right, down, forward;
  Rigid3d pose = Rigid3d::Identity();
  pose.linear() = r * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = position;
  return pose;
}

// An object scan: the camera circles the orbit's target at its pace, distance and height
// drifting slowly within their swings, aimed at the target with a hand's unsteadiness.
Trajectory OrbitWalk(const Orbit& orbit, const WalkOptions& o) {
  std::mt19937_64 rng(o.seed);
  const Wobble wx(&rng), wy(&rng), wz(&rng), wyaw(&rng), wpitch(&rng), wroll(&rng);
  std::uniform_real_distribution<double> ph(0, 2 * M_PI);
  const double start = ph(rng), radius_phase = ph(rng), height_phase = ph(rng);
  const double deg = M_PI / 180.0;
  // Aim: within a few degrees of the target (the hand follows it, not exactly).
  constexpr double kAimDeg = 4.0;
  Trajectory walk;
  double angle = start;
  for (int i = 0; i < o.frames; ++i) {
    const double t = i / o.fps;
    const double radius = orbit.radius + orbit.radius_swing * std::sin(2 * M_PI * t / 13.0 + radius_phase);
    const double height = orbit.height + orbit.height_swing * std::sin(2 * M_PI * t / 9.0 + height_phase);
    if (i > 0) angle += o.speed * orbit.pace / o.fps / radius;
    const Eigen::Vector3d position(orbit.target.x() + radius * std::cos(angle) + o.shake_translation * wx(t),
                                   orbit.target.y() + radius * std::sin(angle) + o.shake_translation * wy(t),
                                   height + o.shake_translation * wz(t));
    const Eigen::Vector3d to_target = (orbit.target - position).normalized();
    const double yaw =
        std::atan2(to_target.y(), to_target.x()) + (kAimDeg * wyaw(0.5 * t) + o.shake_rotation_deg * wyaw(t)) * deg;
    const double pitch =
        std::asin(to_target.z()) + (kAimDeg * wpitch(0.5 * t) + o.shake_rotation_deg * wpitch(t)) * deg;
    walk.Add(t, LookAlong(position, Forward(yaw, pitch), o.shake_rotation_deg * deg * wroll(t)));
  }
  return walk;
}

}  // namespace

void WalkOptions::Check() const { CheckFields(*this); }

Trajectory GenerateWalk(const Scene& scene, const WalkOptions& o) {
  o.Check();
  if (scene.orbit) return OrbitWalk(*scene.orbit, o);
  F2C_CHECK(scene.waypoints.size() >= 2, "a scene has a route");
  const std::vector<Vec2> route = SmoothRoute(scene.waypoints);
  std::vector<double> arc(route.size(), 0.0);
  for (size_t i = 1; i < route.size(); ++i) arc[i] = arc[i - 1] + (route[i] - route[i - 1]).norm();
  const double length = arc.back();
  auto position_at = [&](double s) {  // ping-pong along the route
    const double period = 2 * length;
    s = std::fmod(s, period);
    if (s > length) s = period - s;
    const size_t j = std::min<size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin(), arc.size() - 1);
    if (j == 0) return route[0];
    const double f = (s - arc[j - 1]) / std::max(arc[j] - arc[j - 1], 1e-12);
    return Vec2(route[j - 1] + f * (route[j] - route[j - 1]));
  };
  std::mt19937_64 rng(o.seed);
  const Wobble wx(&rng), wy(&rng), wz(&rng), wyaw(&rng), wpitch(&rng), wroll(&rng);
  std::uniform_real_distribution<double> ph(0, 2 * M_PI);
  const double sweep_phase = ph(rng);
  const double deg = M_PI / 180.0;
  Trajectory walk;
  double body = 0;  // body heading, rate-limited towards the route's direction
  for (int i = 0; i < o.frames; ++i) {
    const double t = i / o.fps, s = o.speed * t;
    const Vec2 p = position_at(s);
    // Walking direction from a point 0.3 m ahead (or behind at the route's ends).
    Vec2 dir = position_at(s + 0.3) - p;
    if (dir.norm() < 1e-6) dir = p - position_at(s - 0.3);
    const double heading = std::atan2(dir.y(), dir.x());
    if (i == 0) {
      body = heading;
    } else {
      const double max_step = o.max_turn_rate_deg * deg / o.fps;
      const double error = std::remainder(heading - body, 2 * M_PI);
      body += std::clamp(error, -max_step, max_step);
    }
    const double yaw = body + o.sweep_deg * deg * std::sin(2 * M_PI * t / o.sweep_period + sweep_phase) +
                       o.shake_rotation_deg * deg * wyaw(t);
    const double pitch = o.pitch_deg * deg + o.shake_rotation_deg * deg * wpitch(t);
    const double roll = o.shake_rotation_deg * deg * wroll(t);
    walk.Add(t, LookAlong(Eigen::Vector3d(p.x() + o.shake_translation * wx(t), p.y() + o.shake_translation * wy(t),
                                          o.eye_height + o.shake_translation * wz(t)),
                          Forward(yaw, pitch), roll));
  }
  return walk;
}

}  // namespace f2c::sim
