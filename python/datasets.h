#pragma once
// read_sequence(), evaluate(), fuse() and simulate() of the module `fine2coarse`: datasets as
// arrays, the evaluation as evaluate --json gives it, the TSDF mesh and the simulator.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <string>

#include "f2c/io/sequence.h"

namespace f2c::python {

namespace py = pybind11;

// A dataset as read_sequence() returns it: frames decoded on access.
struct Sequence {
  RgbdSequence sequence;

  // (color, depth): H x W x 3 uint8 RGB and H x W float32 metres; negative indices count from
  // the end; IndexError beyond it.
  py::tuple Frame(py::ssize_t i) const;
  py::array_t<double> Timestamps() const;
  py::object GroundTruth() const;  // N x 4 x 4 at the frames (NaN where none), or None
};

Sequence ReadSequenceArg(const py::object& path, const py::kwargs& kwargs);

py::dict Evaluate(const py::object& estimate, const py::object& ground_truth, const py::object& timestamps,
                  const py::object& ground_truth_timestamps, double max_time_difference);

py::dict Fuse(const py::object& path, const py::object& poses, const py::object& timestamps, const py::object& out,
              const py::kwargs& kwargs);

py::array_t<double> Simulate(const std::string& scene, int frames, uint64_t seed, const py::object& out,
                             int correspondences, bool overwrite);

}  // namespace f2c::python
