#pragma once
// Pictures and point sets of one frame's features, to look at (visualisation stays out of
// the library stages).

#include <opencv2/core.hpp>

#include "f2c/features/depth_features.h"
#include "f2c/io/ply.h"

namespace f2c::app {

// Colour of a feature type (BGR): plane grey, silhouette red, shadow blue, border yellow,
// ridge green, valley magenta.
cv::Vec3b FeatureColor(FeatureType type);

// The depth image shaded by its normals, each proxy's cells tinted with its own colour, and
// every feature as a dot in its type's colour (edges with a short stroke along their
// direction).
cv::Mat DrawFeatures(const FrameFeatures& features, const FeatureDebug& debug, const CameraIntrinsics& intrinsics);

// Features as points in camera coordinates: planes carry their normal, edges their direction;
// colours by type.
PlyPoints FeaturesToPly(const FrameFeatures& features);

}  // namespace f2c::app
