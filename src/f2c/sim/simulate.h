#pragma once
// A simulated scan on disk, in TUM layout so every tool reads it: rgb/, depth/ (uint16,
// metres * 5000), rgb.txt, depth.txt, groundtruth.txt, camera-intrinsics.txt, and
// correspondences.txt, ground-truth correspondences in the authors' benchmark format
// (io/correspondences.h), and scene.ply, the true surfaces (the triangles it renders, in
// the ground truth's world frame) to measure reconstructed meshes against.

#include <filesystem>
#include <string>

#include "f2c/io/correspondences.h"
#include "f2c/io/ply.h"
#include "f2c/sim/render.h"
#include "f2c/sim/walk.h"
#include "f2c/util/fields.h"

namespace f2c::sim {

struct SimulateOptions {
  std::string scene = "apartment";
  uint64_t seed = 0;  // scene furniture, walk and noise
  CameraIntrinsics intrinsics{525.0, 525.0, 319.5, 239.5, 640, 480};
  SensorOptions sensor;
  WalkOptions walk;           // walk.frames = number of frames
  int correspondences = 400;  // about half nearby pairs, half loop closures
  // Colour and depth taken at different moments, as by cameras whose two streams are not
  // synchronised (TUM's Kinect): each frame's colour is rendered where the camera was a
  // moment drawn evenly in [-color_offset_ms, color_offset_ms] from its depth's (the walk's
  // poses interpolated), and rgb.txt lists it at that time. 0: one moment, as before.
  double color_offset_ms = 0;

  template <class V>
  void Fields(V& v) {
    v.Group("Simulation");
    F2C_FIELD(v, scene, "--scene", {},
              "two-rooms, apartment (its living room a trapezoid, side walls 14 deg off square), apartment-square (the "
              "same at 6 deg), corridor, or object (a table of curved and cluttered objects, circled at 1-1.5 m)");
    F2C_FIELD(v, seed, "--seed", {}, "furniture, walk and noise");
    F2C_FIELD(v, color_offset_ms, "--color-offset", Between(0, 100),
              "colour taken up to this many ms before or after depth (unsynchronised streams; 0: one moment)");
    F2C_FIELD(v, correspondences, "--correspondences", Between(0, 1000000),
              "ground-truth correspondences to write (at most 1,000,000)");
    F2C_NESTED(v, walk);
    F2C_NESTED(v, sensor);
  }
  void Check() const;
};

// Writes the scan into `dir` (created; files written atomically). Returns the poses. A folder
// that is not empty is an InputError unless `overwrite`, which first removes the entries a
// simulated scan is made of (a scan written over another would keep the old frames beyond
// the new count, and the old images between rewritten lists); other files stay.
Trajectory Simulate(const std::filesystem::path& dir, const SimulateOptions& options, bool quiet,
                    bool overwrite = false);

// The scene's triangles as a PLY mesh (three vertices per triangle, with its normal).
PlyPoints SceneSurfaces(const Scene& scene);

// Ground-truth correspondences on exact geometry (no sensor noise), visible in both frames.
std::vector<Correspondence> SampleCorrespondences(const Scene& scene, const Renderer& renderer,
                                                  const CameraIntrinsics& intrinsics, const Trajectory& poses,
                                                  int count, uint64_t seed);

}  // namespace f2c::sim
