#include "python/datasets.h"

#include <fmt/format.h>

#include <cstring>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <pybind11/stl.h>
#include <vector>

#include "f2c/eval/correspondence_error.h"
#include "f2c/eval/trajectory_error.h"
#include "f2c/fusion/fuse.h"
#include "f2c/io/image.h"
#include "f2c/io/ply.h"
#include "f2c/sim/simulate.h"
#include "f2c/util/error.h"
#include "python/arguments.h"

namespace f2c::python {
namespace fs = std::filesystem;

py::tuple Sequence::Frame(py::ssize_t i) const {
  const auto n = static_cast<py::ssize_t>(sequence.frames.size());
  if (i < 0) i += n;
  if (i < 0 || i >= n) throw py::index_error("frame " + std::to_string(i) + " of " + std::to_string(n));
  const RgbdFrame& frame = sequence.frames[i];
  cv::Mat depth, color;
  {
    py::gil_scoped_release release;
    depth = LoadDepthMeters(sequence, frame);
    color = LoadColor(sequence, frame, depth.size());
    cv::cvtColor(color, color, cv::COLOR_BGR2RGB);
  }
  py::array_t<uint8_t> c({color.rows, color.cols, 3});
  py::array_t<float> d({depth.rows, depth.cols});
  for (int y = 0; y < color.rows; ++y) {
    std::memcpy(c.mutable_data(y, 0, 0), color.ptr<uint8_t>(y), static_cast<size_t>(color.cols) * 3);
    std::memcpy(d.mutable_data(y, 0), depth.ptr<float>(y), static_cast<size_t>(depth.cols) * sizeof(float));
  }
  return py::make_tuple(c, d);
}

py::array_t<double> Sequence::Timestamps() const {
  std::vector<double> t;
  for (const RgbdFrame& f : sequence.frames) t.push_back(f.timestamp);
  return py::array_t<double>(py::cast(t));
}

py::object Sequence::GroundTruth() const {
  if (!sequence.ground_truth) return py::none();
  return PoseArray(
      PosesForFrames(sequence, *sequence.ground_truth, IoOptions().max_time_difference, sequence.ground_truth_source));
}

Sequence ReadSequenceArg(const py::object& path, const py::kwargs& kwargs) {
  const fs::path input = PathArg(path, "path", true);
  IoOptions io;
  ForEachOption(kwargs, [&](const std::string& name, const std::string& flag, const py::handle& value) {
    if (!SetFieldByFlag(io, flag, ToFieldValue(flag, value))) {
      ThrowInputError(name,
                      "unknown option (read_sequence takes intrinsics, first, last, every, "
                      "sequence)");
    }
  });
  io.Check();
  return Sequence{ReadSequence(input, io)};
}

py::dict Evaluate(const py::object& estimate, const py::object& ground_truth, const py::object& timestamps,
                  const py::object& ground_truth_timestamps, double max_time_difference) {
  EvaluationOptions options;
  options.max_time_difference = max_time_difference;
  options.Check();
  Trajectory gt;
  std::optional<RgbdSequence> dataset;
  fs::path correspondence_file;
  if (IsPath(ground_truth)) {
    const fs::path path = PathArg(ground_truth, "ground_truth", true);
    gt = fs::is_directory(path) || IsRecordingFile(path) ? LoadGroundTruth(path, IoOptions(), &dataset)
                                                         : ReadTrajectoryFile(path);
    if (dataset && fs::exists(path / "correspondences.txt")) correspondence_file = path / "correspondences.txt";
  } else {
    gt = TrajectoryArg(ground_truth, ground_truth_timestamps, "ground_truth");
  }
  Trajectory est = TrajectoryArg(estimate, timestamps, "estimate");
  if (dataset && gt.has_timestamps) est = PlaceAtFrames(std::move(est), *dataset, "estimate");
  EvaluationResult r;
  std::optional<CorrespondenceResult> corr;
  {
    py::gil_scoped_release release;
    r = f2c::Evaluate(est, gt, options);
    if (!correspondence_file.empty()) {
      // The authors' metric on the folder's ground-truth correspondences, as evaluate gives it.
      std::vector<double> frame_timestamps;
      for (const RgbdFrame& f : dataset->frames) frame_timestamps.push_back(f.timestamp);
      corr = CorrespondenceError(PosesAtFrames(est, frame_timestamps, max_time_difference),
                                 ReadCorrespondences(correspondence_file), correspondence_file.string());
    }
  }
  nlohmann::json j = ToJson(r);
  if (corr) {
    j["correspondences"] = ToJson(*corr);
    j["correspondences"]["file"] = correspondence_file.string();
  }
  return JsonToPython(j);
}

// The frames of a dataset fused at the given poses (fuse's TSDF and marching cubes).
py::dict Fuse(const py::object& path, const py::object& poses, const py::object& timestamps, const py::object& out,
              const py::kwargs& kwargs) {
  const fs::path input = PathArg(path, "path", true);
  IoOptions io;
  FusionOptions fusion;
  ForEachOption(kwargs, [&](const std::string& name, const std::string& flag, const py::handle& value) {
    const FieldValue v = ToFieldValue(flag, value);
    if (!SetFieldByFlag(io, flag, v) && !SetFieldByFlag(fusion, flag, v)) {
      ThrowInputError(name, "unknown option (fuse's options, with '_' for '-': fine2coarse fuse --help)");
    }
  });
  io.Check();
  fusion.Check();
  const RgbdSequence sequence = ReadSequence(input, io);
  RequireIntrinsics(sequence);
  RequireSomeValidDepth(sequence);
  const Trajectory trajectory = TrajectoryArg(poses, timestamps, "poses");
  std::vector<std::optional<Rigid3d>> at;
  if (trajectory.has_timestamps || !trajectory.frame_names.empty()) {  // by time, or a .conf by name
    at = PosesForFrames(sequence, trajectory, io.max_time_difference, "poses");
  } else {
    if (trajectory.size() != sequence.frames.size()) {
      ThrowInputError("poses", fmt::format("{} poses for {} frames (give timestamps= to place them by time)",
                                           trajectory.size(), sequence.frames.size()));
    }
    for (const Rigid3d& p : trajectory.world_from_camera) at.emplace_back(p);
  }
  FusionResult result;
  {
    py::gil_scoped_release release;
    result = FuseTsdf(sequence, at, fusion, true);
  }
  if (!out.is_none()) WritePly(PathArg(out, "out", false), result.mesh);
  return MeshDict(result.mesh);
}

py::array_t<double> Simulate(const std::string& scene, int frames, uint64_t seed, const py::object& out,
                             int correspondences, bool overwrite) {
  const fs::path dir = PathArg(out, "out", false);
  sim::SimulateOptions options;
  options.scene = scene;
  options.seed = seed;
  options.walk.frames = frames;
  options.correspondences = correspondences;
  options.Check();
  Trajectory truth;
  {
    py::gil_scoped_release release;
    truth = sim::Simulate(dir, options, true, overwrite);
  }
  return PoseArray(truth.world_from_camera);
}

}  // namespace f2c::python
