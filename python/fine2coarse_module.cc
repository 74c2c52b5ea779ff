// The Python module `fine2coarse` (docs/python.md): the library's pipeline (pipeline/register.h),
// evaluation and simulator, NumPy in and out. Options are keyword arguments named as the
// command line's long options, with '_' for '-' (util/fields_set.h); bad input raises
// fine2coarse.InputError (a ValueError) with the command line's one-line message, a missing
// path FileNotFoundError. The GIL is released while the pipeline works. This file binds the
// names; python/register_call.h, datasets.h and arguments.h do the work.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "f2c/eval/trajectory_error.h"
#include "f2c/pipeline/outputs.h"
#include "f2c/util/error.h"
#include "python/arguments.h"
#include "python/datasets.h"
#include "python/register_call.h"

namespace fs = std::filesystem;

PYBIND11_MODULE(fine2coarse, m) {
  using namespace f2c::python;
  m.doc() =
      "fine2coarse: globally consistent camera poses and a mesh from an RGB-D video (fine-to-coarse global "
      "registration, Halber & Funkhouser, CVPR 2017). See docs/python.md.";
  py::register_exception<f2c::InputError>(m, "InputError", PyExc_ValueError);

  py::class_<Result>(m, "Result", "A registration's result: poses as arrays, the run's record, the mesh when asked.")
      .def_property_readonly(
          "poses", [](const Result& r) { return PoseArray(r.result.poses.world_from_camera); },
          "N x 4 x 4 float64: each frame's camera-to-world pose (refined, or T0 where the refinement did not run)")
      .def_property_readonly(
          "t0", [](const Result& r) { return PoseArray(r.result.odometry.t0.world_from_camera); },
          "N x 4 x 4 float64: the odometry's poses (T0)")
      .def_property_readonly(
          "timestamps", [](const Result& r) { return py::array_t<double>(py::cast(r.result.poses.timestamps)); },
          "N float64: each frame's time stamp (seconds)")
      .def_property_readonly(
          "frame_ids",
          [](const Result& r) {
            std::vector<std::string> ids;
            for (const f2c::RgbdFrame& f : r.result.sequence.frames) ids.push_back(f.name);
            return ids;
          },
          "each frame's name (its depth image's file name)")
      .def_property_readonly(
          "odometry",
          [](const Result& r) {
            py::list out;
            for (const f2c::PairAlignment& p : r.result.odometry.pairs) {
              py::dict d;
              d["frame"] = p.frame;
              d["reference"] = p.Reference();
              d["method"] = f2c::MethodName(p.method);
              d["inliers"] = p.inliers;
              d["fitness"] = p.fitness;
              out.append(d);
            }
            return out;
          },
          "per frame after the first: how the odometry aligned it (frame, reference, method, inliers, fitness)")
      .def_property_readonly(
          "stats", [](const Result& r) { return JsonToPython(r.Stats()); },
          "the run's record, as the command line's run.json holds it (a dict)")
      .def_property_readonly(
          "mesh",
          [](const Result& r) -> py::object {
            return r.result.fusion ? py::object(MeshDict(r.result.fusion->mesh)) : py::none();
          },
          "with mesh=True: a dict of vertices (V x 3 float64), triangles (T x 3 int32), colors (V x 3 uint8) and "
          "normals (V x 3 float64); else None")
      .def(
          "save",
          [](const Result& r, const py::object& outdir, bool report) {
            const fs::path dir = PathArg(outdir, "outdir", false);
            f2c::OutputOptions outputs;
            outputs.report = report;
            outputs.iterations = r.options.keep_iterations;
            outputs.input = r.input;
            outputs.io = r.io;
            py::gil_scoped_release release;
            return f2c::WriteOutputs(dir, r.result, r.options, outputs);
          },
          py::arg("outdir"), py::arg("report") = true,
          "Writes the command line's files into outdir (trajectory.txt, trajectory.log, trajectory.conf, "
          "trajectory_t0.txt, odometry.json, run.json, mesh.ply when fused, report.html unless report=False); "
          "returns their names")
      .def("__repr__", [](const Result& r) {
        return "<fine2coarse.Result: " + std::to_string(r.result.poses.size()) + " frames, " +
               (r.result.refine ? "refined" : "T0") + (r.result.fusion ? ", mesh" : "") + ">";
      });

  m.def("register", &RegisterPath, py::arg("path"), py::kw_only(), py::arg("progress") = py::none(),
        R"(Registers a dataset folder (TUM, 7-Scenes/3DMatch, Redwood/Open3D, SUN3D) or a .conf file.

Keyword options are the command line's (fine2coarse register --help-all) with '_' for '-':
intrinsics='tum-fr1', every=2, first=0, last=-1, preset='fast'|'default'|'paper',
stop_after='odometry'|'refine', structure=False, self_check=False, seed=0, voxel_size=0.01, ...
Beyond them: mesh=True fuses a mesh (off by default), features=False skips the features and the
refinement, quiet=False prints the command line's progress, threads=N, save_iterations=True,
initial_trajectory=PATH. progress=callable(stage, done, total) hears each stage's progress.
The GIL is released while it works. Returns a Result.)");

  py::class_<Sequence>(m, "Sequence", "A dataset as read_sequence() reads it; frames are decoded on access.")
      .def("__len__", [](const Sequence& s) { return s.sequence.frames.size(); })
      .def("__getitem__", &Sequence::Frame, py::arg("index"),
           "(color, depth): H x W x 3 uint8 RGB and H x W float32 metres (0: no depth), as the pipeline reads them "
           "(resampled to the pinhole model where the intrinsics carry distortion)")
      .def_property_readonly("timestamps", &Sequence::Timestamps, "N float64 seconds")
      .def_property_readonly(
          "frame_ids",
          [](const Sequence& s) {
            std::vector<std::string> ids;
            for (const f2c::RgbdFrame& f : s.sequence.frames) ids.push_back(f.name);
            return ids;
          },
          "each frame's name")
      .def_property_readonly(
          "intrinsics",
          [](const Sequence& s) -> py::object {
            return s.sequence.intrinsics ? py::object(IntrinsicsDict(*s.sequence.intrinsics)) : py::none();
          },
          "fx, fy, cx, cy, width, height, distortion; None where the folder carries none (TUM: pass intrinsics=)")
      .def_property_readonly("ground_truth", &Sequence::GroundTruth,
                             "N x 4 x 4 camera-to-world poses of the frames (NaN where a frame has none), or None")
      .def_property_readonly(
          "layout", [](const Sequence& s) { return f2c::LayoutName(s.sequence.layout); }, "the layout detected")
      .def("__repr__", [](const Sequence& s) {
        return "<fine2coarse.Sequence: " + s.sequence.root.string() + ", " + f2c::LayoutName(s.sequence.layout) + ", " +
               std::to_string(s.sequence.frames.size()) + " frames>";
      });

  m.def("read_sequence", &ReadSequenceArg, py::arg("path"),
        R"(Reads a dataset folder or .conf as register() would (intrinsics=, first=, last=, every=, sequence=).
Returns a Sequence: len(), seq[i] -> (color RGB uint8, depth float32 metres), timestamps,
frame_ids, intrinsics, ground_truth (N x 4 x 4 or None), layout.)");

  m.def("register_frames", &RegisterFrames, py::arg("colors"), py::arg("depths"), py::arg("intrinsics"), py::kw_only(),
        py::arg("timestamps") = py::none(), py::arg("depth_scale") = 0.001, py::arg("progress") = py::none(),
        R"(Registers frames already in memory (from a camera's SDK): colors, a list or array of H x W x 3
uint8 RGB images; depths, H x W uint16 (units of depth_scale metres, default millimetres) or
float32 metres; intrinsics (fx, fy, cx, cy) or a dict; timestamps in seconds (default 30 Hz).
Depth is kept at 0.2 mm (TUM's unit; beyond 13.1 m it is invalid). Options as register().)");

  m.def("evaluate", &Evaluate, py::arg("estimate"), py::arg("ground_truth"), py::kw_only(),
        py::arg("timestamps") = py::none(), py::arg("ground_truth_timestamps") = py::none(),
        py::arg("max_time_difference") = f2c::EvaluationOptions().max_time_difference,
        R"(ATE, RPE and rotation drift of a trajectory against the ground truth, as `evaluate --json` gives them.

estimate: a trajectory file (TUM, .log, .conf) or an N x 4 x 4 array of camera-to-world poses
(with timestamps=, else frame indices). ground_truth: a trajectory file, a dataset folder with
ground truth, or an array (with ground_truth_timestamps=). Poses are associated by time stamp
within max_time_difference seconds. Returns a dict (ate_m, rpe_per_frame, rpe_per_second,
rotation_drift_deg, ...).)");

  m.def("fuse", &Fuse, py::arg("path"), py::arg("poses"), py::kw_only(), py::arg("timestamps") = py::none(),
        py::arg("out") = py::none(),
        R"(Fuses a dataset's frames at the given poses into a mesh, as `fine2coarse fuse` does: poses an N x 4 x 4
array of camera-to-world poses (one per frame, or placed by timestamps=) or a trajectory file;
options voxel_size=, fuse_every=, intrinsics=, first=, last=, every=, ... Returns the mesh as
a dict of arrays (vertices, triangles, colors, normals); out=PATH also writes it as PLY.)");

  m.def("simulate", &Simulate, py::arg("scene"), py::arg("frames"), py::arg("seed"), py::arg("out"), py::kw_only(),
        py::arg("correspondences") = 400, py::arg("overwrite") = false,
        R"(Simulates a scan into the folder out (a TUM layout with groundtruth.txt, correspondences.txt and
scene.ply), as `fine2coarse simulate` does: scene two-rooms, apartment, apartment-square,
corridor or object. A folder that is not empty is an error unless overwrite=True (which replaces
the scan in it). Returns the true poses (frames x 4 x 4).)");
}
