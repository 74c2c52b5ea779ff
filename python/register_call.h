#pragma once
// register() and register_frames() of the module `fine2coarse`: keyword options to the
// pipeline's options, the progress callback, the GIL released while Register (pipeline/
// register.h) works, and the typed result the Python Result wraps.

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "f2c/pipeline/register.h"

namespace f2c::python {

namespace py = pybind11;

// What register() returns: the typed result, turned into arrays on access.
struct Result {
  RegisterResult result;
  RegisterOptions options;
  IoOptions io;
  std::string input;

  nlohmann::json Stats() const;  // run.json's contents
};

// register(path, progress=, **options).
Result RegisterPath(const py::object& path, const py::object& progress, const py::kwargs& kwargs);

// register_frames(colors, depths, intrinsics, timestamps=, depth_scale=, progress=, **options).
Result RegisterFrames(const py::sequence& colors, const py::sequence& depths, const py::object& intrinsics,
                      const py::object& timestamps, double depth_scale, const py::object& progress,
                      const py::kwargs& kwargs);

}  // namespace f2c::python
