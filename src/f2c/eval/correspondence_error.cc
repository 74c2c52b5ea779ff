#include "f2c/eval/correspondence_error.h"

#include <fmt/format.h>

#include "f2c/io/readers.h"
#include "f2c/util/error.h"

namespace f2c {

std::vector<std::optional<Rigid3d>> PosesAtFrames(const Trajectory& estimate, const std::vector<double>& frame_timestamps,
                                                  double max_time_difference) {
  std::vector<std::optional<Rigid3d>> poses(frame_timestamps.size());
  for (const auto& [frame, pose] :
       internal::AssociateTimestamps(frame_timestamps, estimate.timestamps, max_time_difference)) {
    poses[frame] = estimate.world_from_camera[pose];
  }
  return poses;
}

CorrespondenceResult CorrespondenceError(const std::vector<std::optional<Rigid3d>>& world_from_frame,
                                         const std::vector<Correspondence>& correspondences, const std::string& source) {
  CorrespondenceResult result;
  std::vector<double> distances;
  const int frames = static_cast<int>(world_from_frame.size());
  for (const Correspondence& c : correspondences) {
    for (int frame : {c.frame_a, c.frame_b}) {
      if (frame < 0 || frame >= frames) {
        ThrowInputError(source, fmt::format("a correspondence refers to frame {} but the dataset has {} frames",
                                            frame, frames));
      }
    }
    const auto& a = world_from_frame[c.frame_a];
    const auto& b = world_from_frame[c.frame_b];
    if (!a || !b) {
      ++result.skipped;
      continue;
    }
    distances.push_back((*a * c.point_in_a - *b * c.point_in_b).norm());
  }
  result.distance = ComputeStatistics(std::move(distances));
  return result;
}

}  // namespace f2c
