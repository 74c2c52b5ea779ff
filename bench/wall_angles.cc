// The angle between walls as a registration reconstructs them (issue 9: off-square walls
// must stay off-square). For each frame, its per-image planar proxies (from register's
// feature cache) are placed in the world twice: by the ground-truth pose, to decide which
// wall a proxy lies on, and by the estimated pose, to measure that wall's normal as the
// estimate sees it. The angle between two walls' mean estimated normals, against the same
// from the ground truth, says whether the registration bent the room.
//
//   wall_angles DATASET FEATURES_CACHE ESTIMATE --wall NAME x0 y0 x1 y1 [--wall ...]
//
// DATASET: a simulated scan (its ground truth and frame times); FEATURES_CACHE: register's
// cache/features.f2cf for it; ESTIMATE: a TUM trajectory. Walls are floor-plan segments
// (metres, the simulator's world frame: z up). Prints, for every two walls, the true and the
// estimated angle between their planes (0-90 degrees) and how many proxies each had.
//
// After the angles, the proxies' own error on each wall: the mean signed turn of their
// normals about the vertical, placed by the true pose, from the wall's (degrees), for the
// views that see the wall from one side (the ray to the proxy's centre more than 0.2 along
// the wall, one way or the other) and from straight on; first the proxies' least-squares
// planes, then their planes without the estimated depth noise (PlanarProxy::noise, as the
// structural model's children take them). Depth noise along the rays turns a least-squares
// plane towards them, so the two sides differ in sign.

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "f2c/features/feature_set.h"
#include "f2c/io/sequence.h"
#include "f2c/io/trajectory.h"
#include "f2c/refine/hierarchy.h"
#include "f2c/util/error.h"

namespace {

struct Wall {
  std::string name;
  Eigen::Vector2d a, b;
  Eigen::Vector3d true_sum = Eigen::Vector3d::Zero(), estimated_sum = Eigen::Vector3d::Zero();
  int proxies = 0;
  // The proxies' turn from the wall under the true pose (radians), by plane (least squares,
  // without the noise) and view (ray along the wall < -0.2, within +-0.2, > 0.2).
  double turn_sum[2][3] = {{0, 0, 0}, {0, 0, 0}};
  int turn_count[3] = {0, 0, 0};
};

// Whether a proxy (world normal and centroid under the true pose) lies on the wall: normal
// within 5 degrees of the wall's, centroid within 5 cm of its plane, at least 0.3 m from its
// ends (corners hold the neighbouring wall's proxies too) and between floor and ceiling.
bool OnWall(const Wall& w, const Eigen::Vector3d& normal, const Eigen::Vector3d& centroid) {
  const Eigen::Vector2d d = (w.b - w.a).normalized();
  const Eigen::Vector3d wall_normal(-d.y(), d.x(), 0);
  if (std::abs(normal.dot(wall_normal)) < std::cos(5 * M_PI / 180)) return false;
  const Eigen::Vector2d p = centroid.head<2>() - w.a;
  const double along = p.dot(d), across = std::abs(p.x() * wall_normal.x() + p.y() * wall_normal.y());
  return across <= 0.05 && along >= 0.3 && along <= (w.b - w.a).norm() - 0.3 && centroid.z() > 0.1 &&
         centroid.z() < 2.4;
}

double PlaneAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * 180 / M_PI;
}

// A number of a --wall argument, or an InputError naming it.
double Number(const char* text, const std::string& wall) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v)) {
    throw f2c::InputError(fmt::format("--wall {}: '{}' is not a number", wall, text));
  }
  return v;
}

int Run(int argc, char** argv) {
  if (argc < 4) throw f2c::InputError("usage: wall_angles DATASET FEATURES_CACHE ESTIMATE --wall NAME x0 y0 x1 y1 ...");
  std::vector<Wall> walls;
  for (int i = 4; i < argc; i += 6) {
    if (std::string(argv[i]) != "--wall" || i + 5 >= argc) throw f2c::InputError("expected --wall NAME x0 y0 x1 y1");
    Wall w;
    w.name = argv[i + 1];
    w.a = {Number(argv[i + 2], w.name), Number(argv[i + 3], w.name)};
    w.b = {Number(argv[i + 4], w.name), Number(argv[i + 5], w.name)};
    walls.push_back(w);
  }
  f2c::IoOptions io;
  io.check_files = false;
  const f2c::RgbdSequence sequence = f2c::ReadSequence(argv[1], io);
  if (!sequence.ground_truth) throw f2c::InputError(std::string(argv[1]) + ": no ground truth");
  uint64_t hash = 0;
  const std::vector<f2c::FeatureCacheEntry> cache = f2c::ReadFeatureCache(argv[2], &hash);
  const f2c::Trajectory estimate = f2c::ReadTrajectoryFile(argv[3]);
  auto key = [](double t) { return std::llround(t * 1e4); };
  std::map<long long, f2c::Rigid3d> estimated, truth;
  for (size_t i = 0; i < estimate.size(); ++i) estimated[key(estimate.timestamps[i])] = estimate.world_from_camera[i];
  for (size_t i = 0; i < sequence.ground_truth->size(); ++i) {
    truth[key(sequence.ground_truth->timestamps[i])] = sequence.ground_truth->world_from_camera[i];
  }
  if (cache.size() != sequence.frames.size()) {
    throw f2c::InputError(
        fmt::format("{}: {} frames, the dataset has {}", argv[2], cache.size(), sequence.frames.size()));
  }
  for (size_t f = 0; f < cache.size(); ++f) {
    const auto e = estimated.find(key(sequence.frames[f].timestamp));
    const auto g = truth.find(key(sequence.frames[f].timestamp));
    if (e == estimated.end() || g == truth.end()) continue;
    for (const f2c::PlanarProxy& p : cache[f].features.proxies) {
      const Eigen::Vector3d n_true = g->second.linear() * p.normal.cast<double>();
      const Eigen::Vector3d c_true = g->second * p.centroid.cast<double>();
      for (Wall& w : walls) {
        if (!OnWall(w, n_true, c_true)) continue;
        const Eigen::Vector2d d = (w.b - w.a).normalized();
        const Eigen::Vector3d along(d.x(), d.y(), 0), across(-d.y(), d.x(), 0);
        const double side = (c_true - g->second.translation()).normalized().dot(along);
        const int view = side < -0.2 ? 0 : side > 0.2 ? 2 : 1;
        const Eigen::Vector3d n_clean = g->second.linear() * f2c::MakeChild(0, p, true).normal.cast<double>();
        const Eigen::Vector3d* normals[2] = {&n_true, &n_clean};
        for (int k = 0; k < 2; ++k) {
          // atan2(n . along, |n . across|): the turn towards `along`, whichever way n faces.
          const Eigen::Vector3d& n = *normals[k];
          w.turn_sum[k][view] += std::atan2(n.dot(along) * (n.dot(across) < 0 ? -1 : 1), std::abs(n.dot(across)));
        }
        w.turn_count[view]++;
        w.true_sum += p.inliers * n_true;
        w.estimated_sum += p.inliers * (e->second.linear() * p.normal.cast<double>());
        w.proxies++;
      }
    }
  }
  std::printf("%-24s %8s %8s %8s %8s\n", "walls", "true", "estimate", "error", "proxies");
  for (size_t i = 0; i < walls.size(); ++i) {
    for (size_t j = i + 1; j < walls.size(); ++j) {
      const Wall &a = walls[i], &b = walls[j];
      if (a.proxies == 0 || b.proxies == 0) {
        std::printf("%-24s no proxies on one of them\n", (a.name + "/" + b.name).c_str());
        continue;
      }
      const double t = PlaneAngle(a.true_sum, b.true_sum), est = PlaneAngle(a.estimated_sum, b.estimated_sum);
      std::printf("%-24s %8.2f %8.2f %+8.2f %4d/%d\n", (a.name + "/" + b.name).c_str(), t, est, est - t, a.proxies,
                  b.proxies);
    }
  }
  std::printf("\n%-24s %24s %24s %24s\n", "proxy turn", "seen from a (deg, n)", "straight on", "seen from b");
  for (int k = 0; k < 2; ++k) {
    for (const Wall& w : walls) {
      std::printf("%-24s", (w.name + (k == 0 ? " least squares" : " without noise")).c_str());
      for (int view = 0; view < 3; ++view) {
        if (w.turn_count[view] == 0) {
          std::printf(" %24s", "-");
        } else {
          std::printf(" %17.3f %6d", w.turn_sum[k][view] / w.turn_count[view] * 180 / M_PI, w.turn_count[view]);
        }
      }
      std::printf("\n");
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
