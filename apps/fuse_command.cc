// fine2coarse fuse: a dataset folder and a trajectory to a coloured mesh (PLY).

#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>

#include "apps/commands.h"
#include "apps/fields_cli.h"
#include "f2c/io/image.h"
#include "f2c/io/image_write.h"
#include "f2c/report/mesh_views.h"
#include "f2c/util/error.h"
#include "f2c/util/fields_json.h"
#include "f2c/util/file.h"
#include "f2c/util/memory.h"

namespace f2c::app {
namespace fs = std::filesystem;
using nlohmann::json;

int RunFuse(const FuseArgs& args) {
  args.fusion.Check();
  const fs::path out = args.output;
  if (out.extension() != ".ply") ThrowInputError(out, "the mesh is written as PLY: give a .ply file");
  const RgbdSequence seq = ReadSequence(args.input, args.io);  // the inputs first: no folder left behind
  RequireIntrinsics(seq);
  RequireSomeValidDepth(seq);
  const Trajectory trajectory = ReadTrajectoryFile(args.trajectory);
  const OutputFolder output_folder(out.parent_path().empty() ? fs::path(".") : out.parent_path());
  const auto poses = PosesForFrames(seq, trajectory, args.io.max_time_difference, args.trajectory);
  spdlog::info("{}: {} frames, {} with a pose in {}", args.input, seq.frames.size(),
               std::count_if(poses.begin(), poses.end(), [](const auto& p) { return p.has_value(); }), args.trajectory);
  const FusionResult fused = FuseTsdf(seq, poses, args.fusion, args.quiet);
  WritePly(out, fused.mesh);
  std::vector<fs::path> pictures;
  if (args.pictures) {
    // Up: the horizontal surfaces' normal nearest the cameras' mean -y (people hold the
    // camera about level in roll); ahead: the first posed camera's viewing direction.
    Eigen::Vector3d camera_up = Eigen::Vector3d::Zero();
    for (const auto& p : poses) {
      if (p) camera_up -= p->linear().col(1);
    }
    const auto first = std::find_if(poses.begin(), poses.end(), [](const auto& p) { return p.has_value(); });
    const Eigen::Vector3d up = EstimateUp(fused.mesh, camera_up), ahead = (*first)->linear().col(2);
    const std::string stem = (out.parent_path() / out.stem()).string();
    const std::pair<std::string, MeshView> views[] = {
        {stem + "_top.png", TopView(fused.mesh, up, ahead, 1024)},
        {stem + "_view.png", PerspectiveView(fused.mesh, up, ahead, 1024, 768)}};
    for (const auto& [path, view] : views) {
      WritePngFile(path, RenderMesh(fused.mesh, view));
      pictures.push_back(path);
    }
  }
  const FusionTimings& t = fused.timings;
  if (args.json) {
    json report = ToJson(t, fused.mesh);
    report["options"] = FieldsToJson(args.fusion);
    report["peak_memory_bytes"] = PeakResidentBytes();
    report["frames"] = t.frames_fused;
    std::printf("%s\n", report.dump(2).c_str());
  } else {
    std::printf("wrote %s: %zu vertices, %zu triangles\n", out.string().c_str(), fused.mesh.positions.size(),
                fused.mesh.faces.size());
    for (const fs::path& p : pictures) std::printf("wrote %s\n", p.string().c_str());
    std::printf("%d frames fused in %.1f s (%.1f ms per frame, mesh %.1f s), %d blocks, %.0f MiB of voxels\n",
                t.frames_fused, t.wall, 1000.0 * t.integrate / std::max(t.frames_fused, 1), t.mesh, t.blocks,
                t.volume_bytes / 1048576.0);
  }
  return 0;
}

Subcommand AddFuseCommand(CLI::App* app) {
  auto args = std::make_shared<FuseArgs>();
  CLI::App* cmd = app->add_subcommand(
      "fuse",
      "fuse a dataset's frames at a trajectory's poses (TUM, .log or .conf) into a sparse TSDF volume and "
      "write its surface as a coloured triangle mesh (binary PLY)");
  cmd->add_option("INPUT", args->input,
                  "dataset folder (any layout register reads), .conf, or a recording (.sens, ROS 1 or 2 bag)")
      ->required();
  cmd->add_option("--trajectory", args->trajectory, "the poses: TUM text, Redwood .log or the authors' .conf")
      ->required();
  cmd->add_option("-o,--output", args->output, "the mesh, a .ply file")->required();
  AddFieldFlags(cmd, &args->io);
  cmd->add_option("--max-time-difference", args->io.max_time_difference,
                  "a TUM pose belongs to the frame within this many seconds")
      ->capture_default_str();
  AddFieldFlags(cmd, &args->fusion);
  cmd->add_flag("--pictures", args->pictures,
                "also draw the mesh from above and in perspective: <mesh>_top.png, <mesh>_view.png");
  cmd->add_flag("--json", args->json, "print the timings and sizes as JSON");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress output");
  return {cmd, [args] {
            if (args->quiet) spdlog::set_level(spdlog::level::warn);
            return RunFuse(*args);
          }};
}

}  // namespace f2c::app
