#include "f2c/report/report.h"

#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <Eigen/Geometry>

namespace f2c {
namespace {

TEST(Histogram, EqualBinsAndOverflowInTheLast) {
  EXPECT_EQ(Histogram({0.0, 0.05, 0.1, 0.19, 0.2, 0.5, -1.0}, 0.2, 2), (std::vector<int>{2, 4}));
}

Trajectory Walk(int n, double noise_per_frame) {
  Trajectory t;
  for (int i = 0; i < n; ++i) {
    Rigid3d p = Rigid3d::Identity();
    p.linear() = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    p.translation() = Eigen::Vector3d(0.1 * i, 0.02 * std::sin(i) + noise_per_frame * i * i, 0.05 * i);
    t.Add(1.0 + i / 30.0, p);
  }
  return t;
}

TEST(BuildReport, EverySectionWithPlotsThatParse) {
  ReportInput in;
  in.title = "test <run>";
  in.facts = {{"frames", "20"}, {"layout", "tum"}};
  in.ground_truth = Walk(20, 0);
  in.estimates = {{"T0", Walk(20, 0.001), "#d62728"}, {"final", Walk(20, 0.0001), "#2ca02c"}};
  in.fallback_times = {1.0 + 5 / 30.0};
  for (int i = 0; i < 20; ++i) in.frame_timestamps.push_back(1.0 + i / 30.0);
  for (int a = 0; a < 20; a += 3) {
    for (int b = a + 1; b < 20; b += 4) {
      Correspondence c;
      c.frame_a = a, c.frame_b = b;
      const Eigen::Vector3d world(0.3 * a, 0.1 * b, 2.0);
      c.point_in_a = in.ground_truth->world_from_camera[a].inverse() * world;
      c.point_in_b = in.ground_truth->world_from_camera[b].inverse() * world;
      in.correspondences.push_back(c);
    }
  }
  for (int i = 0; i < 4; ++i) {
    ReportIteration it;
    it.window_length = 8 << i, it.windows = 8 >> i, it.seconds = 0.1 * (i + 1);
    it.cost_after = {{"E_C", 1.0 / (i + 1)}, {"E_L", 0.01}};
    if (i > 0) it.cost_after.emplace_back("E_P", 0.5);  // a term that starts later
    it.correspondences_by_type = {{"plane", 100 * i}, {"silhouette", 10}};
    it.check_before = 0.02 - 0.001 * i, it.check_after = i == 2 ? 0.03 : 0.019 - 0.001 * i;
    it.undone = i == 2;
    in.iterations.push_back(it);
  }
  // Five frames seeing a wall (x = 3) and a floor (y = 1; the cameras' up is -y).
  for (int i = 0; i < 20; i += 4) {
    in.slice_timestamps.push_back(1.0 + i / 30.0);
    SliceFrame f;
    const Rigid3d camera_from_world = in.ground_truth->world_from_camera[i].inverse();
    for (int k = 0; k < 200; ++k) {
      const bool wall = k % 2;
      const Eigen::Vector3d p =
          wall ? Eigen::Vector3d(3, -1 + 0.01 * k, 0.01 * k) : Eigen::Vector3d(0.01 * k, 1, 0.01 * k);
      const Eigen::Vector3d n = wall ? Eigen::Vector3d(-1, 0, 0) : Eigen::Vector3d(0, -1, 0);
      f.points.push_back((camera_from_world * p).cast<float>());
      f.normals.push_back((camera_from_world.linear() * n).cast<float>());
    }
    in.slice_frames.push_back(std::move(f));
  }
  const std::string html = BuildReport(in);
  in.options_json = R"({"refine": {"window_frames": 8}})";
  const std::string html_with_options = BuildReport(in);
  EXPECT_NE(html_with_options.find("<summary>Options (run.json)</summary><pre>{&quot;refine&quot;"), std::string::npos);
  in.options_json.clear();
  for (const char* s : {"<h2>Run</h2>", "<h2>Top-down slice of the registered points</h2>", "<th>ATE RMSE (m)</th>",
                        "<h2>Trajectories</h2>", "<h2>Errors</h2>", "<h2>Correspondence errors</h2>",
                        "<h2>Refinement</h2>", ">E_P</text>", ">silhouette</text>",
                        "Self-check: how far held-out features lie off", ">undone: what it would have been</text>",
                        "the paper&#39;s Fig. 9", "test &lt;run&gt;", ">ICP / motion prior<"}) {
    EXPECT_NE(html.find(s), std::string::npos) << s;
  }
  // Every SVG is XML with drawn content.
  int svgs = 0;
  for (size_t at = html.find("<svg"); at != std::string::npos; at = html.find("<svg", at + 1)) {
    const size_t end = html.find("</svg>", at) + 6;
    const std::string svg = html.substr(at, end - at);
    tinyxml2::XMLDocument doc;
    EXPECT_EQ(doc.Parse(svg.c_str()), tinyxml2::XML_SUCCESS) << svg.substr(0, 200);
    EXPECT_EQ(svg.find("no data"), std::string::npos) << svg.substr(0, 200);
    ++svgs;
  }
  EXPECT_EQ(svgs, 15);               // 2 maps, 3 slices, 3 error plots, Fig. 9, histogram, 5 per-iteration plots
  EXPECT_EQ(html, BuildReport(in));  // the same bytes every time

  // Without ground truth or correspondences: the maps, and lines saying what is missing.
  ReportInput bare;
  bare.estimates = in.estimates;
  const std::string b = BuildReport(bare);
  EXPECT_NE(b.find("No ground truth in this dataset"), std::string::npos);
  EXPECT_NE(b.find("No ground-truth correspondences"), std::string::npos);
  EXPECT_EQ(b.find("<h2>Top-down slice"), std::string::npos);  // no frames, no reason: no section
  bare.no_slice_reason = "pass --intrinsics";
  EXPECT_NE(BuildReport(bare).find(
                "<h2>Top-down slice of the registered points</h2>\n<p class=\"note\">pass --intrinsics</p>"),
            std::string::npos);
}

}  // namespace
}  // namespace f2c
