#pragma once
// The authors' scan configuration (.conf) format:
//
//   dataset <name>                 tum | sun3d | 7scenes | 3dmatch | redwood, any case
//                                  (selects depth decoding; another name is an error)
//   intrinsics <file>              3x3 camera matrix file, relative to the .conf's folder
//   intrinsics_matrix fx 0 cx 0 fy cy 0 0 1     (alternative to `intrinsics`)
//   n_images <n>
//   depth_directory <dir>          relative to the .conf's folder (or absolute)
//   image_directory <dir>
//   scan <depth file> <colour file> m00 m01 ... m33    row-major 4x4 camera-to-world
//
// As a trajectory over a dataset, a scan line's pose belongs to the frame whose depth image
// has its name (FramesOfPoses), so lines in any order mean the same; a name given twice is
// an error.
//
// Unknown keys are errors: a misspelt key that is silently skipped is how runs go wrong.

#include <filesystem>

#include "f2c/io/sequence.h"

namespace f2c {

struct ConfFile {
  RgbdSequence sequence;  // frames, intrinsics and depth decoding
  Trajectory trajectory;  // the scan poses: timestamps = line index (has_timestamps=false), frame_names
};

ConfFile ReadConf(const std::filesystem::path& path, double assumed_fps = 30.0);

// Writes `trajectory` (one pose per frame of `sequence`) as a .conf whose directories point
// at the sequence's image folders (absolute paths, so the file can live anywhere).
void WriteConf(const std::filesystem::path& path, const RgbdSequence& sequence, const Trajectory& trajectory);

}  // namespace f2c
