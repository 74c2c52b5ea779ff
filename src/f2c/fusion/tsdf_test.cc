#include "f2c/fusion/tsdf.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <random>

#include "f2c/fusion/marching_cubes.h"
#include "f2c/testing/synthetic_scene.h"

namespace f2c {
namespace {

TEST(TsdfVolume, PlaneZeroCrossingOnThePlaneAndBlocksOnlyInTheBand) {
  const CameraIntrinsics k = testing::TestIntrinsics();
  // A wall 1.8 m ahead, turned 15 degrees about the vertical; the camera somewhere in the world.
  const Eigen::Vector3d n_cam = Eigen::AngleAxisd(15 * M_PI / 180, Eigen::Vector3d::UnitY()) * Eigen::Vector3d::UnitZ();
  const double d_cam = 1.8;
  Rigid3d world_from_camera = Rigid3d::Identity();
  world_from_camera.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  world_from_camera.translation() = Eigen::Vector3d(0.37, -1.21, 0.55);
  TsdfOptions o;
  TsdfVolume volume(o);
  volume.Integrate(testing::PlaneDepth(k, n_cam, d_cam), cv::Mat(), k, world_from_camera);
  // The plane in the world: n_w . x = d_w.
  const Eigen::Vector3d n_w = world_from_camera.linear() * n_cam;
  const double d_w = d_cam + n_w.dot(world_from_camera.translation());

  const PlyPoints mesh = ExtractMesh(volume);
  ASSERT_GT(mesh.faces.size(), 10000u);
  double worst = 0;
  for (const Eigen::Vector3f& p : mesh.positions) worst = std::max(worst, std::abs(n_w.dot(p.cast<double>()) - d_w));
  EXPECT_LT(worst, 0.1 * o.voxel_size);

  // Every block meets the band |distance| <= truncation (its centre within the truncation
  // plus half the block's diagonal), and the band's blocks are all there is.
  const double block = o.voxel_size * kTsdfBlockSide, half_diagonal = 0.5 * std::sqrt(3.0) * block;
  for (int b = 0; b < volume.BlockCount(); ++b) {
    const Eigen::Vector3d centre = (volume.BlockCoords(b).cast<double>() + Eigen::Vector3d::Constant(0.5)) * block;
    EXPECT_LE(std::abs(n_w.dot(centre) - d_w), o.Truncation() + half_diagonal) << "block " << b;
  }
  // And the band is all there: around every pixel's surface point, from half the truncation
  // in front to half behind, the voxels exist.
  const Eigen::Matrix3d r = world_from_camera.linear();
  for (int v = 3; v < k.height; v += 7) {
    for (int u = 3; u < k.width; u += 7) {
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const double z = d_cam / n_cam.dot(ray);
      for (double s : {-0.5, -0.25, 0.0, 0.25, 0.5}) {
        // The grid point below p: within sqrt(3) voxels of it, so inside the band.
        const Eigen::Vector3d p = world_from_camera.translation() + r * (ray * (z + s * o.Truncation()));
        const Eigen::Vector3i voxel = (p / o.voxel_size).array().floor().cast<int>();
        ASSERT_NE(volume.Find(voxel), nullptr) << "pixel " << u << "," << v << " offset " << s;
      }
    }
  }
}

double Percentile90(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() * 9 / 10, v.end());
  return v[v.size() * 9 / 10];
}

std::vector<Rigid3d> LookAround(int frames) {
  std::vector<Rigid3d> poses;
  for (int i = 0; i < frames; ++i) {
    Rigid3d t = Rigid3d::Identity();
    t.linear() = (Eigen::AngleAxisd(0.35 * i, Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(0.15 * std::sin(i), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    t.translation() = Eigen::Vector3d(0.3 * std::cos(0.7 * i), 0.1 * std::sin(i), -0.4 + 0.05 * i);
    poses.push_back(t);
  }
  return poses;
}

std::vector<testing::RenderedFrame> RenderAll(const std::vector<Rigid3d>& poses) {
  std::vector<testing::RenderedFrame> frames;
  for (const Rigid3d& pose : poses)
    frames.push_back(testing::Render(testing::SyntheticScene(), testing::TestIntrinsics(), pose));
  return frames;
}

// The frames fused at `fuse`: the 90th percentile of the mesh vertices' distance to the
// scene's true surfaces.
double Fuse90(const std::vector<testing::RenderedFrame>& frames, const std::vector<Rigid3d>& fuse,
              PlyPoints* mesh_out = nullptr) {
  const testing::SyntheticScene scene;
  TsdfVolume volume(TsdfOptions{});
  for (size_t i = 0; i < frames.size(); ++i) {
    volume.Integrate(frames[i].depth, frames[i].color, testing::TestIntrinsics(), fuse[i]);
  }
  const PlyPoints mesh = ExtractMesh(volume);
  std::vector<double> d;
  for (const Eigen::Vector3f& p : mesh.positions) d.push_back(testing::SurfaceDistance(scene, p.cast<double>()));
  if (mesh_out) *mesh_out = mesh;
  return d.empty() ? 1e9 : Percentile90(d);
}

TEST(TsdfVolume, BoxRoomWithTruePosesLiesOnItsWallsAndWrongPosesShow) {
  const std::vector<Rigid3d> truth = LookAround(5);
  const std::vector<testing::RenderedFrame> frames = RenderAll(truth);
  PlyPoints mesh;
  const double exact = Fuse90(frames, truth, &mesh);
  EXPECT_LT(exact, 0.01);
  EXPECT_GT(mesh.faces.size(), 100000u);
  // Each pose off by 5 cm in a random direction: doubled, blurred walls.
  std::vector<Rigid3d> perturbed = truth;
  std::mt19937 rng(3);
  std::normal_distribution<double> g;
  for (Rigid3d& t : perturbed) t.translation() += 0.05 * Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
  const double off = Fuse90(frames, perturbed);
  EXPECT_GT(off, 2 * exact);
  EXPECT_GT(off, 0.01);
}

TEST(TsdfVolume, SameVolumeForAnyThreadCount) {
  const std::vector<Rigid3d> poses = LookAround(3);
  const std::vector<testing::RenderedFrame> frames = RenderAll(poses);
  PlyPoints one, many;
  {
    tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    Fuse90(frames, poses, &one);
  }
  Fuse90(frames, poses, &many);
  EXPECT_EQ(one.positions, many.positions);
  EXPECT_EQ(one.colors, many.colors);
  EXPECT_EQ(one.faces, many.faces);
}

TEST(TsdfOptions, CheckNamesTheOption) {
  TsdfOptions o;
  o.voxel_size = 0;
  EXPECT_EQ(testing::InputErrorMessage([&] { o.Check(); }), "--voxel-size: must be in [0.001, 0.5], got 0");
  o = {};
  o.max_depth = 0.1;
  EXPECT_EQ(testing::InputErrorMessage([&] { o.Check(); }),
            "--fuse-max-depth: must exceed the nearest depth (0.3), got 0.1");
}

}  // namespace
}  // namespace f2c
