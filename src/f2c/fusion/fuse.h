#pragma once
// The fusion stage: a sequence's frames, with their poses, into a sparse TSDF volume and out
// as a coloured triangle mesh (tsdf.h, marching_cubes.h, docs/fusion.md).

#include <filesystem>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <vector>

#include "f2c/fusion/marching_cubes.h"
#include "f2c/fusion/tsdf.h"
#include "f2c/io/sequence.h"
#include "f2c/io/trajectory.h"
#include "f2c/util/fields.h"

namespace f2c {

struct FusionOptions {
  TsdfOptions tsdf;
  MeshOptions mesh;
  int every = 1;  // fuse every n-th frame that has a pose (--fuse-every)

  template <class V>
  void Fields(V& v) {
    F2C_NESTED(v, tsdf);
    F2C_FIELD(v, every, "--fuse-every", AtLeast(1), "fuse every N-th frame that has a pose");
    F2C_NESTED(v, mesh);
  }
  void Check() const;
};

struct FusionTimings {
  int frames_fused = 0;
  int frames_without_pose = 0;
  double decode_cpu = 0;  // seconds of CPU decoding colour and depth (in parallel with the rest)
  double integrate = 0;   // seconds of wall time integrating
  double mesh = 0;        // seconds of wall time extracting the mesh
  double wall = 0;        // the whole stage
  int blocks = 0;
  size_t volume_bytes = 0;
};

struct FusionResult {
  PlyPoints mesh;  // world frame (the trajectory's), metres
  FusionTimings timings;
};

// `poses[k]`: frame k's world_from_camera, or nullopt to leave it out.
FusionResult FuseTsdf(const RgbdSequence& sequence, const std::vector<std::optional<Rigid3d>>& poses,
                      const FusionOptions& options, bool quiet);

// A trajectory's poses placed on the sequence's frames: by time stamp (the nearest within
// max_time_difference seconds) or, for files without time stamps, by frame id (.log) or image
// name (.conf). InputError naming `file` when no frame gets a pose or a frame id is out of range.
std::vector<std::optional<Rigid3d>> PosesForFrames(const RgbdSequence& sequence, const Trajectory& trajectory,
                                                   double max_time_difference, const std::filesystem::path& file);

// The stage's record in run.json (with the mesh's size).
nlohmann::json ToJson(const FusionTimings& timings, const PlyPoints& mesh);

}  // namespace f2c
