// Prototype (measured, not kept; BENCHMARKS.md "Twenty-seventh stop"): each frame re-aligned
// to the surface fused from every frame at the given poses, by point-to-plane ICP against the
// mesh's vertices, moving only along the directions its depth constrains (eigenvalues of
// J^T J at least RATIO times the largest).
//   [F2C_INTRINSICS=preset] model_realign DATASET TRAJECTORY OUT.txt [stride] [iterations] [ratio] [voxel]
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <cmath>
#include <nanoflann.hpp>

#include "f2c/fusion/fuse.h"
#include "f2c/io/image.h"
#include "f2c/io/sequence.h"
#include "f2c/io/trajectory.h"

namespace {
struct Cloud {
  const std::vector<Eigen::Vector3f>* p;
  size_t kdtree_get_point_count() const { return p->size(); }
  float kdtree_get_pt(size_t i, size_t d) const { return (*p)[i][static_cast<int>(d)]; }
  template <class B>
  bool kdtree_get_bbox(B&) const { return false; }
};
using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud, 3, uint32_t>;

Eigen::Matrix3d Exp(const Eigen::Vector3d& w) {
  const double a = w.norm();
  if (a < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(a, w / a).toRotationMatrix();
}
}  // namespace

int main(int argc, char** argv) {
  using namespace f2c;
  if (argc < 4) {
    fmt::print(stderr, "usage: model_realign DATASET TRAJECTORY OUT.txt [stride] [iters] [ratio] [voxel]\n");
    return 2;
  }
  const int stride = argc > 4 ? std::atoi(argv[4]) : 8;
  const int iterations = argc > 5 ? std::atoi(argv[5]) : 6;
  const double ratio = argc > 6 ? std::atof(argv[6]) : 0.01;
  const double voxel = argc > 7 ? std::atof(argv[7]) : 0.01;
  IoOptions io;
  if (const char* k = std::getenv("F2C_INTRINSICS")) io.intrinsics = k;
  RgbdSequence seq = ReadSequence(argv[1], io);
  const Trajectory traj = ReadTrajectoryFile(argv[2]);
  auto poses = PosesForFrames(seq, traj, 0.02, argv[2]);
  FusionOptions fo;
  fo.tsdf.voxel_size = voxel;
  const FusionResult fused = FuseTsdf(seq, poses, fo, true);
  const auto& P = fused.mesh.positions;
  const auto& N = fused.mesh.normals;
  Cloud cloud{&P};
  Tree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(12));
  tree.buildIndex();
  fmt::print(stderr, "model: {} vertices\n", P.size());
  const CameraIntrinsics& K = *seq.intrinsics;
  const double max_dist = 0.05;
  std::vector<std::optional<Rigid3d>> out = poses;
  tbb::parallel_for(0, static_cast<int>(seq.frames.size()), [&](int f) {
    if (!poses[f]) return;
    const cv::Mat depth = LoadDepthMeters(seq, seq.frames[f]);
    std::vector<Eigen::Vector3d> pts;
    std::vector<double> sig;
    for (int v = stride / 2; v < depth.rows; v += stride) {
      for (int u = stride / 2; u < depth.cols; u += stride) {
        const float z = depth.at<float>(v, u);
        if (!(z > 0.3f && z < 4.0f)) continue;
        pts.push_back(K.Unproject(u, v, z));
        sig.push_back(0.0012 + 0.0019 * (z - 0.4) * (z - 0.4) + 0.002);
      }
    }
    const Rigid3d start = *poses[f];
    Rigid3d T = start;
    for (int it = 0; it < iterations; ++it) {
      Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
      Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
      for (size_t i = 0; i < pts.size(); ++i) {
        const Eigen::Vector3d q = T * pts[i];
        const Eigen::Vector3f qf = q.cast<float>();
        uint32_t idx;
        float d2;
        nanoflann::KNNResultSet<float, uint32_t, size_t> rs(1);
        rs.init(&idx, &d2);
        tree.findNeighbors(rs, qf.data(), nanoflann::SearchParams());
        if (rs.size() == 0 || d2 > max_dist * max_dist) continue;
        const Eigen::Vector3d n = N[idx].cast<double>().normalized();
        const double r = n.dot(q - P[idx].cast<double>()) / sig[i];
        const double c = 2.0;  // Huber in sigmas
        const double w = std::abs(r) <= c ? 1.0 : c / std::abs(r);
        // Right perturbation T exp(delta): the camera-frame point p moves by w x p + t.
        const Eigen::Vector3d nc = T.linear().transpose() * n;
        Eigen::Matrix<double, 6, 1> J;
        J.head<3>() = pts[i].cross(nc) / sig[i];
        J.tail<3>() = nc / sig[i];
        H += w * J * J.transpose();
        b += w * J * r;
      }
      // Only directions the frame's depth constrains well move (eigenvalues above ratio x max).
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> es(H);
      const double top = es.eigenvalues().maxCoeff();
      Eigen::Matrix<double, 6, 1> delta = Eigen::Matrix<double, 6, 1>::Zero();
      for (int k = 0; k < 6; ++k) {
        const double l = es.eigenvalues()(k);
        if (l < ratio * top || l <= 0) continue;
        delta -= (es.eigenvectors().col(k).dot(b) / l) * es.eigenvectors().col(k);
      }
      Rigid3d step = Rigid3d::Identity();
      step.linear() = Exp(delta.head<3>());
      step.translation() = delta.tail<3>();
      T = T * step;
    }
    out[f] = T;
  });
  Trajectory result;
  for (size_t f = 0; f < out.size(); ++f) {
    if (out[f]) result.Add(seq.frames[f].timestamp, *out[f]);
  }
  WriteTumTrajectory(argv[3], result);
  return 0;
}
