#pragma once
// Which way is up in a scan, from its surface normals: indoor scenes have floors, table tops
// and ceilings, whose normals agree to within a few degrees, and a hand-held camera is held
// roughly upright, so its mean -y axis points roughly up. Used to look at a scan from above
// (the mesh pictures, the report's top-down slice).

#include <Eigen/Core>
#include <vector>

namespace f2c {

// The direction, within 45 degrees of `prior`, shared by the most `normals` to within 10
// degrees (each normal first flipped to the prior's side; zero normals ignored), refined as
// their mean. `prior` (normalised) when fewer than 20 normals agree. At most ~20,000 normals
// are looked at (an even stride), so the cost is bounded for any input.
Eigen::Vector3d UpFromNormals(const std::vector<Eigen::Vector3f>& normals, const Eigen::Vector3d& prior);

}  // namespace f2c
