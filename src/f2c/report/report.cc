#include "f2c/report/report.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "f2c/eval/correspondence_error.h"
#include <optional>
#include "f2c/eval/trajectory_error.h"
#include "f2c/geometry/coord_table.h"
#include "f2c/report/svg_plot.h"

namespace f2c {

std::vector<int> Histogram(const std::vector<double>& values, double max, int bins) {
  std::vector<int> h(std::max(bins, 1), 0);
  for (double v : values) {
    if (!std::isfinite(v) || v < 0) continue;
    const int i = std::min(static_cast<int>(v / max * bins), bins - 1);
    ++h[i];
  }
  return h;
}

namespace {

// One number of a statistic, or n/a when nothing was measured (a 0 would read as perfect).
std::string Cell(const ErrorStatistics& s, double value, int digits) {
  return s.count == 0 ? std::string("n/a") : fmt::format("{:.{}f}", value, digits);
}

// The ground-truth pose nearest in time to t (within max_dt), if any. Stamps are sorted.
std::optional<Rigid3d> TruthAt(const Trajectory& truth, double t, double max_dt) {
  const auto it = std::lower_bound(truth.timestamps.begin(), truth.timestamps.end(), t);
  std::optional<Rigid3d> best;
  double best_dt = max_dt;
  for (auto c : {it, it == truth.timestamps.begin() ? it : it - 1}) {
    if (c == truth.timestamps.end()) continue;
    const double dt = std::abs(*c - t);
    if (dt <= best_dt) best_dt = dt, best = truth.world_from_camera[c - truth.timestamps.begin()];
  }
  return best;
}

double RotationDeg(const Eigen::Matrix3d& r) {
  return Eigen::AngleAxisd(Eigen::Quaterniond(r).normalized()).angle() * 180.0 / M_PI;
}

// The principal axes of the points: a top view (first two) and a side view (first, third).
Eigen::Matrix3d PrincipalAxes(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < 3) return Eigen::Matrix3d::Identity();
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& p : points) mean += p;
  mean /= points.size();
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& p : points) cov += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Matrix3d axes;
  axes.col(0) = eig.eigenvectors().col(2), axes.col(1) = eig.eigenvectors().col(1);
  axes.col(2) = axes.col(0).cross(axes.col(1));
  return axes;
}

std::string Section(const std::string& title, const std::string& body) {
  return fmt::format("<section><h2>{}</h2>\n{}</section>\n", EscapeXml(title), body);
}

std::string Note(const std::string& text) { return fmt::format("<p class=\"note\">{}</p>\n", EscapeXml(text)); }

// One series per name, over the iterations (NaN where an iteration lacks it).
template <typename T>
std::vector<PlotSeries> ByName(const std::vector<ReportIteration>& its,
                               std::vector<std::pair<std::string, T>> ReportIteration::*field) {
  std::vector<std::string> names;
  for (const ReportIteration& it : its) {
    for (const auto& [name, value] : it.*field) {
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
  }
  std::vector<PlotSeries> series;
  for (size_t n = 0; n < names.size(); ++n) {
    PlotSeries s{names[n], {}, {}, SeriesColor(static_cast<int>(n)), PlotSeries::Style::kLine, 2};
    for (size_t i = 0; i < its.size(); ++i) {
      double v = std::numeric_limits<double>::quiet_NaN();
      for (const auto& [name, value] : its[i].*field) {
        if (name == names[n]) v = static_cast<double>(value);
      }
      s.x.push_back(static_cast<double>(i + 1)), s.y.push_back(v);
    }
    series.push_back(std::move(s));
  }
  return series;
}

// The self-check's measure after each iteration (and before it, where it was undone: the
// poses it kept), with the undone iterations marked; empty when no iteration was checked.
std::string SelfCheckPlot(const std::vector<ReportIteration>& its) {
  PlotSeries kept{"held-out RMS after the iteration (m)", {}, {}, "#1f77b4", PlotSeries::Style::kLine, 2};
  PlotSeries undone{"undone: what it would have been", {}, {}, "#d62728", PlotSeries::Style::kPoints, 2};
  bool any = false;
  for (size_t i = 0; i < its.size(); ++i) {
    const double x = static_cast<double>(i + 1);
    any = any || std::isfinite(its[i].check_after);
    kept.x.push_back(x), kept.y.push_back(its[i].undone ? its[i].check_before : its[i].check_after);
    if (its[i].undone) undone.x.push_back(x), undone.y.push_back(its[i].check_after);
  }
  if (!any) return "";
  Plot plot;
  plot.title = "Self-check: how far held-out features lie off the other frames' surfaces";
  plot.x.label = "iteration";
  plot.y.label = "RMS, truncated (m)";
  plot.series = {kept, undone};
  plot.width = 640, plot.height = 340;
  return RenderSvg(plot);
}

std::string IterationPlots(const std::vector<ReportIteration>& its) {
  Plot cost, corr, window, time;
  cost.title = "Energy after each iteration, by term";
  cost.x.label = corr.x.label = window.x.label = time.x.label = "iteration";
  cost.y.label = "cost";
  cost.y.log = true;
  cost.series = ByName(its, &ReportIteration::cost_after);
  corr.title = "Correspondences by type";
  corr.y.label = "correspondences";
  corr.series = ByName(its, &ReportIteration::correspondences_by_type);
  window.title = "Window length";
  window.y.label = "frames (or metres of path)";
  window.y.log = true;
  time.title = "Time per iteration";
  time.y.label = "seconds";
  PlotSeries w{"", {}, {}, "#1f77b4", PlotSeries::Style::kLine, 2}, t{"", {}, {}, "#1f77b4", PlotSeries::Style::kBars};
  for (size_t i = 0; i < its.size(); ++i) {
    w.x.push_back(i + 1.0), w.y.push_back(its[i].window_length);
    t.x.push_back(i + 1.0), t.y.push_back(its[i].seconds);
  }
  window.series = {w};
  time.series = {t};
  for (Plot* p : {&cost, &corr, &window, &time}) p->width = 640, p->height = 340;
  return "<div class=\"plots\">\n" + RenderSvg(cost) + SelfCheckPlot(its) + RenderSvg(corr) + RenderSvg(window) +
         RenderSvg(time) + "</div>\n";
}

template <typename T>
std::string Bytes(const std::vector<T>& v) {
  return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

// A canvas drawn by three.js: the points (coloured), the camera path (red), orbit and zoom
// with the mouse. Without JavaScript the rest of the page still shows.
std::string View3d(const ReportInput& in) {
  if (in.three_js.empty()) return Note("three.js is not installed (Debian's libjs-three): no 3D view.");
  if (in.points.empty() && in.camera_path.empty()) return Note("Nothing to show in 3D (no mesh, no path).");
  std::vector<float> points, path;
  for (const Eigen::Vector3f& p : in.points) points.insert(points.end(), p.data(), p.data() + 3);
  for (const Eigen::Vector3f& p : in.camera_path) path.insert(path.end(), p.data(), p.data() + 3);
  std::vector<uint8_t> colors;
  for (size_t i = 0; i < in.points.size(); ++i) {
    const std::array<uint8_t, 3> c =
        i < in.point_colors.size() ? in.point_colors[i] : std::array<uint8_t, 3>{90, 90, 90};
    colors.insert(colors.end(), c.begin(), c.end());
  }
  return fmt::format(R"(<canvas id="view3d" width="1000" height="640" style="border:1px solid #ccc"></canvas>
<p class="note">{} points and the camera path (red); drag to orbit, scroll to zoom, right-drag to pan.</p>
<script>{}</script>
<script>
(function () {{
  function decode(s) {{ const b = atob(s), u = new Uint8Array(b.length); for (let i = 0; i < b.length; ++i) u[i] = b.charCodeAt(i); return u.buffer; }}
  const points = new Float32Array(decode("{}")), colors = new Uint8Array(decode("{}")), path = new Float32Array(decode("{}"));
  const canvas = document.getElementById("view3d");
  const renderer = new THREE.WebGLRenderer({{canvas: canvas, antialias: true, preserveDrawingBuffer: true}});
  renderer.setClearColor(0xffffff);
  const scene = new THREE.Scene();
  const cloud = new THREE.BufferGeometry();
  cloud.setAttribute("position", new THREE.BufferAttribute(points, 3));
  cloud.setAttribute("color", new THREE.BufferAttribute(colors, 3, true));
  const line = new THREE.BufferGeometry();
  line.setAttribute("position", new THREE.BufferAttribute(path, 3));
  const all = new THREE.BufferGeometry();
  all.setAttribute("position", new THREE.BufferAttribute(points.length ? points : path, 3));
  all.computeBoundingSphere();
  const sphere = all.boundingSphere, r = Math.max(sphere.radius, 0.1);
  scene.add(new THREE.Points(cloud, new THREE.PointsMaterial({{size: r / 250, vertexColors: true}})));
  scene.add(new THREE.Line(line, new THREE.LineBasicMaterial({{color: 0xd62728}})));
  const camera = new THREE.PerspectiveCamera(55, canvas.width / canvas.height, r / 200, r * 20);
  const up = new THREE.Vector3({}, {}, {}).normalize();
  camera.up.copy(up);
  const side = new THREE.Vector3(1, 0, 0);
  if (Math.abs(side.dot(up)) > 0.9) side.set(0, 1, 0);
  side.sub(up.clone().multiplyScalar(side.dot(up))).normalize();
  camera.position.copy(sphere.center).add(side.multiplyScalar(1.6 * r)).add(up.clone().multiplyScalar(1.1 * r));
  const controls = new THREE.OrbitControls(camera, canvas);
  controls.target.copy(sphere.center);
  controls.update();
  const draw = function () {{ renderer.render(scene, camera); }};
  controls.addEventListener("change", draw);
  draw();
}})();
</script>
)",
                     in.points.size(), in.three_js, Base64(Bytes(points)), Base64(Bytes(colors)), Base64(Bytes(path)),
                     in.up.x(), in.up.y(), in.up.z());
}

// The slice from above under each set of poses, on shared axes: x along the result's slice
// points' main direction, y across it; one dot per occupied cell of a 1/500-extent grid.
std::string SliceSection(const ReportInput& in,
                         const std::vector<std::pair<const ReportTrajectory*, Rigid3d>>& estimates) {
  std::vector<std::pair<std::string, std::string>> names;  // name, colour
  std::vector<std::vector<std::optional<Rigid3d>>> pose_sets;
  std::vector<std::optional<Rigid3d>> truth;
  if (in.ground_truth) {
    for (double t : in.slice_timestamps) truth.push_back(TruthAt(*in.ground_truth, t, in.max_time_difference));
    names.emplace_back("ground truth", "#444444");
    pose_sets.push_back(truth);
  }
  for (const auto& [e, ate_alignment] : estimates) {
    auto poses = PosesAtFrames(e->trajectory, in.slice_timestamps, in.max_time_difference);
    // Aligned by whole poses: each frame's position and the tips of its axes (1 m long). The
    // positions alone leave the rotation free when the camera moved along a line (a few
    // frames), which would turn the drawing.
    Rigid3d gt_from_estimate = ate_alignment;
    std::vector<Eigen::Vector3d> from, to;
    for (size_t k = 0; k < truth.size(); ++k) {
      if (!poses[k] || !truth[k]) continue;
      for (int axis = -1; axis < 3; ++axis) {
        const Eigen::Vector3d local =
            axis < 0 ? Eigen::Vector3d(Eigen::Vector3d::Zero()) : Eigen::Vector3d(Eigen::Vector3d::Unit(axis));
        from.push_back(*poses[k] * local), to.push_back(*truth[k] * local);
      }
    }
    if (from.size() >= 8) {
      Eigen::Matrix3Xd a(3, from.size()), b(3, to.size());
      for (size_t i = 0; i < from.size(); ++i) a.col(i) = from[i], b.col(i) = to[i];
      gt_from_estimate.matrix() = Eigen::umeyama(a, b, false);
    }
    for (auto& p : poses) {
      if (p) p = gt_from_estimate * *p;
    }
    names.emplace_back(e->name, e->color);
    pose_sets.push_back(std::move(poses));
  }
  const SliceBand band = ChooseSliceBand(in.slice_frames, pose_sets.back(), in.slice_options);
  std::vector<std::vector<Eigen::Vector3d>> slices;
  for (const auto& poses : pose_sets) slices.push_back(SlicePoints(in.slice_frames, poses, band));
  // Horizontal axes from the result's slice.
  Eigen::Vector3d a = band.up.unitOrthogonal(), b = band.up.cross(a);
  if (slices.back().size() >= 3) {
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& p : slices.back()) mean += Eigen::Vector2d(p.dot(a), p.dot(b));
    mean /= static_cast<double>(slices.back().size());
    Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
    for (const auto& p : slices.back()) {
      const Eigen::Vector2d d = Eigen::Vector2d(p.dot(a), p.dot(b)) - mean;
      cov += d * d.transpose();
    }
    const Eigen::Vector2d major = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(cov).eigenvectors().col(1);
    const Eigen::Vector3d x = major.x() * a + major.y() * b;
    a = x.normalized(), b = band.up.cross(a);
  }
  // Shared extent: every set's 0.5th to 99.5th percentile, so that a few far points do not
  // shrink the drawing.
  std::vector<double> xs, ys;
  for (const auto& s : slices) {
    for (const auto& p : s) xs.push_back(p.dot(a)), ys.push_back(p.dot(b));
  }
  if (xs.empty()) return Note("No points in the slab: nothing to draw.");
  auto quantile = [](std::vector<double> v, double q) {
    const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())));
    std::nth_element(v.begin(), v.begin() + static_cast<long>(i), v.end());
    return v[i];
  };
  const double x0 = quantile(xs, 0.005), x1 = quantile(xs, 0.995), y0 = quantile(ys, 0.005), y1 = quantile(ys, 0.995);
  const double cell = std::max({x1 - x0, y1 - y0, 1e-3}) / 500;
  std::string plots = "<div class=\"plots\">\n";
  for (size_t s = 0; s < slices.size(); ++s) {
    Plot p;
    p.title = names[s].first;
    p.x.label = p.y.label = "m";
    p.x.min = x0, p.x.max = x1, p.y.min = y0, p.y.max = y1;
    p.equal_aspect = true;
    p.width = 420, p.height = 420;
    PlotSeries dots{"", {}, {}, names[s].second, PlotSeries::Style::kDots, 1.2};
    CoordTable seen(4096);
    for (const auto& q : slices[s]) {
      const double x = q.dot(a), y = q.dot(b);
      if (x < x0 || x > x1 || y < y0 || y > y1) continue;
      int& drawn = seen.At(PackCoords(
          {static_cast<int>(std::floor((x - x0) / cell)), static_cast<int>(std::floor((y - y0) / cell)), 0}));
      if (drawn >= 0) continue;
      drawn = 1;
      dots.x.push_back(x), dots.y.push_back(y);
    }
    p.series.push_back(std::move(dots));
    plots += RenderSvg(p);
  }
  return plots + "</div>\n" +
         Note(fmt::format("The points of {} frames within {:.2f} m of {:.2f} m height (the layer with the most wall "
                          "points), seen from above{}. A consistent registration draws each wall once, as a thin line.",
                          in.slice_frames.size(), 0.5 * band.thickness, band.height,
                          in.ground_truth
                              ? "; each estimate rigidly aligned to the ground truth by its poses (positions and axes)"
                              : ""));
}

}  // namespace

std::string Base64(const std::string& bytes) {
  static const char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = static_cast<uint32_t>(static_cast<uint8_t>(bytes[i])) << 16 |
                       (i + 1 < bytes.size() ? static_cast<uint32_t>(static_cast<uint8_t>(bytes[i + 1])) << 8 : 0) |
                       (i + 2 < bytes.size() ? static_cast<uint32_t>(static_cast<uint8_t>(bytes[i + 2])) : 0);
    out += kDigits[n >> 18 & 63];
    out += kDigits[n >> 12 & 63];
    out += i + 1 < bytes.size() ? kDigits[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return out;
}

std::string BuildReport(const ReportInput& in) {
  std::string html = fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{0}</title>\n"
      "<style>body{{font-family:sans-serif;max-width:1340px;margin:2em auto;color:#222}}"
      "table{{border-collapse:collapse}}td,th{{border:1px solid #ccc;padding:3px 8px;text-align:left}}"
      "section{{margin:2em 0}}.plots svg{{margin:4px}}.note{{color:#666}}</style></head><body>\n<h1>{0}</h1>\n",
      EscapeXml(in.title));
  std::string facts = "<table>\n";
  for (const auto& [k, v] : in.facts)
    facts += fmt::format("<tr><th>{}</th><td>{}</td></tr>\n", EscapeXml(k), EscapeXml(v));
  if (!in.options_json.empty()) {
    facts += "</table>\n<details><summary>Options (run.json)</summary><pre>" + EscapeXml(in.options_json) +
             "</pre></details>\n";
  } else {
    facts += "</table>\n";
  }
  html += Section("Run", facts);

  // Each estimate's poses, rigidly aligned to the truth where there is one (as for ATE), and
  // the true pose at each of its frames (nearest stamp within max_time_difference).
  struct Aligned {
    const ReportTrajectory* estimate;
    std::vector<Rigid3d> poses;                 // every pose of the estimate, aligned
    std::vector<std::optional<Rigid3d>> truth;  // per pose: the ground truth, if associated
    Rigid3d gt_from_estimate = Rigid3d::Identity();
  };
  std::vector<Aligned> aligned;
  std::vector<Eigen::Vector3d> all_points;
  const Trajectory* frame =
      in.ground_truth ? &*in.ground_truth : (in.estimates.empty() ? nullptr : &in.estimates.back().trajectory);
  if (frame) {
    for (const auto& p : frame->world_from_camera) all_points.push_back(p.translation());
  }
  EvaluationOptions eval_options;
  eval_options.max_time_difference = in.max_time_difference;
  for (const ReportTrajectory& e : in.estimates) {
    Aligned a{&e, {}, {}};
    Rigid3d& gt_from_estimate = a.gt_from_estimate;
    if (in.ground_truth) {
      try {
        gt_from_estimate = ComputeAte(e.trajectory, *in.ground_truth, eval_options).gt_from_estimate;
      } catch (const std::exception&) {
        // Too few poses associate: drawn as they are.
      }
    }
    for (size_t k = 0; k < e.trajectory.size(); ++k) {
      a.poses.push_back(gt_from_estimate * e.trajectory.world_from_camera[k]);
      a.truth.push_back(in.ground_truth && e.trajectory.has_timestamps
                            ? TruthAt(*in.ground_truth, e.trajectory.timestamps[k], in.max_time_difference)
                            : std::nullopt);
    }
    aligned.push_back(std::move(a));
  }
  const Eigen::Matrix3d axes = PrincipalAxes(all_points);
  std::string maps = "<div class=\"plots\">\n";
  for (int view = 0; view < 2; ++view) {
    Plot p;
    p.title = view == 0 ? "From above (principal axes 1-2)" : "From the side (principal axes 1-3)";
    p.x.label = "m";
    p.y.label = "m";
    p.equal_aspect = true;
    p.width = 640, p.height = 480;
    auto project = [&](const Eigen::Vector3d& t, double* x, double* y) {
      const Eigen::Vector3d c = axes.transpose() * t;
      *x = c.x(), *y = view == 0 ? c.y() : c.z();
    };
    if (in.ground_truth) {
      PlotSeries s{"ground truth", {}, {}, "#444444"};
      for (const auto& pose : in.ground_truth->world_from_camera) {
        double x, y;
        project(pose.translation(), &x, &y);
        s.x.push_back(x), s.y.push_back(y);
      }
      p.series.push_back(s);
    }
    for (const Aligned& a : aligned) {
      PlotSeries s{a.estimate->name, {}, {}, a.estimate->color};
      for (const Rigid3d& pose : a.poses) {
        double x, y;
        project(pose.translation(), &x, &y);
        s.x.push_back(x), s.y.push_back(y);
      }
      p.series.push_back(s);
    }
    if (!in.fallback_times.empty() && !in.estimates.empty()) {
      // Marked on the result, at its own poses (aligned like its line).
      const Trajectory& result = in.estimates.back().trajectory;
      const auto at = PosesAtFrames(result, in.fallback_times, in.max_time_difference);
      const Rigid3d& align = aligned.back().gt_from_estimate;
      PlotSeries marks{"ICP / motion prior", {}, {}, "#ff7f0e", PlotSeries::Style::kPoints, 2.5};
      for (const auto& pose : at) {
        if (!pose) continue;
        double x, y;
        project((align * *pose).translation(), &x, &y);
        marks.x.push_back(x), marks.y.push_back(y);
      }
      p.series.push_back(marks);
    }
    maps += RenderSvg(p);
  }
  html += Section("Trajectories",
                  maps + "</div>\n" +
                      (in.ground_truth ? Note("Each estimate rigidly aligned to the ground truth as for ATE.")
                                       : Note("No ground truth: the estimates as they are.")));
  if (!in.slice_frames.empty() && !aligned.empty()) {
    std::vector<std::pair<const ReportTrajectory*, Rigid3d>> estimates;
    for (const Aligned& a : aligned) estimates.emplace_back(a.estimate, a.gt_from_estimate);
    html += Section("Top-down slice of the registered points", SliceSection(in, estimates));
  } else if (!in.no_slice_reason.empty()) {
    html += Section("Top-down slice of the registered points", Note(in.no_slice_reason));
  }

  if (!in.ground_truth) {
    html += Section("Errors", Note("No ground truth in this dataset: no error plots."));
  } else {
    const Trajectory& gt = *in.ground_truth;
    const double t0 = gt.empty() ? 0 : gt.timestamps.front();
    Plot translation, rotation, gaps;
    translation.title = "Position error over time (after ATE alignment)";
    translation.x.label = "time (s)";
    translation.y.label = "error (m)";
    rotation.title = "Rotation error over time";
    rotation.x.label = "time (s)";
    rotation.y.label = "error (deg)";
    gaps.title = "Relative pose error against frame gap";
    gaps.x.label = "frame gap";
    gaps.y.label = "translation error (m), median";
    gaps.x.log = gaps.y.log = true;
    for (const Aligned& a : aligned) {
      const ReportTrajectory& e = *a.estimate;
      PlotSeries st{e.name, {}, {}, e.color}, sr{e.name, {}, {}, e.color};
      for (size_t k = 0; k < a.poses.size(); ++k) {
        if (!a.truth[k]) continue;
        const double t = e.trajectory.timestamps[k] - t0;
        st.x.push_back(t), sr.x.push_back(t);
        st.y.push_back((a.poses[k].translation() - a.truth[k]->translation()).norm());
        sr.y.push_back(RotationDeg(a.truth[k]->linear().transpose() * a.poses[k].linear()));
      }
      translation.series.push_back(st);
      rotation.series.push_back(sr);
      // Relative errors over gaps of 1, 2, 4, ... of the estimate's frames (both associated).
      std::vector<std::pair<int, double>> rel;
      const int n = static_cast<int>(a.poses.size());
      for (int g = 1; g < n; g *= 2) {
        for (int i = 0; i + g < n; i += std::max(1, g / 8)) {
          if (!a.truth[i] || !a.truth[i + g]) continue;
          const Rigid3d truth = a.truth[i]->inverse() * *a.truth[i + g];
          const Rigid3d est = a.poses[i].inverse() * a.poses[i + g];
          rel.emplace_back(g, (truth.translation() - est.translation()).norm());
        }
      }
      PlotSeries sg{e.name, {}, {}, e.color};
      for (const GapBin& b : BinByGap(rel)) sg.x.push_back(b.gap_lo), sg.y.push_back(b.median);
      gaps.series.push_back(sg);
    }
    // The numbers `evaluate` prints, per estimate.
    std::string stats =
        "<table><tr><th>estimate</th><th>poses</th><th>ATE RMSE (m)</th><th>ATE median (m)</th><th>ATE max (m)</th>"
        "<th>RPE/frame (m)</th><th>RPE/frame (deg)</th><th>RPE/s (m)</th><th>RPE/s (deg)</th>"
        "<th>rotation drift RMS (deg)</th><th>rotation drift worst (deg)</th>" +
        fmt::format("<th>worst over {:g} s means (deg)</th></tr>\n", eval_options.drift_smoothing_seconds);
    for (const Aligned& a : aligned) {
      try {
        const EvaluationResult r = Evaluate(a.estimate->trajectory, gt, eval_options);
        stats += fmt::format(
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
            "<td>{}</td><td>{}</td><td>{}</td></tr>\n",
            EscapeXml(a.estimate->name), r.ate.translation.count, Cell(r.ate.translation, r.ate.translation.rmse, 4),
            Cell(r.ate.translation, r.ate.translation.median, 4), Cell(r.ate.translation, r.ate.translation.max, 4),
            Cell(r.rpe_per_frame.translation, r.rpe_per_frame.translation.rmse, 4),
            Cell(r.rpe_per_frame.rotation, r.rpe_per_frame.rotation.rmse, 3),
            Cell(r.rpe_per_second.translation, r.rpe_per_second.translation.rmse, 4),
            Cell(r.rpe_per_second.rotation, r.rpe_per_second.rotation.rmse, 3),
            Cell(r.drift.rotation, r.drift.rotation.rmse, 3), Cell(r.drift.rotation, r.drift.rotation.max, 2),
            Cell(r.drift_smoothed.rotation, r.drift_smoothed.rotation.max, 2));
      } catch (const std::exception& e) {
        stats += fmt::format("<tr><td>{}</td><td colspan=\"11\">{}</td></tr>\n", EscapeXml(a.estimate->name),
                             EscapeXml(e.what()));
      }
    }
    html += Section("Errors", stats + "</table>\n<div class=\"plots\">\n" + RenderSvg(translation) +
                                  RenderSvg(rotation) + RenderSvg(gaps) + "</div>\n");
  }

  // The paper's Fig. 9 and the histogram, from ground-truth correspondences.
  if (in.correspondences.empty() || in.frame_timestamps.empty()) {
    html += Section("Correspondence errors", Note("No ground-truth correspondences in this dataset."));
  } else {
    Plot fig9, hist;
    fig9.title = "Correspondence error against frame distance (the paper's Fig. 9)";
    fig9.x.label = "frame distance |a - b| (bins of powers of two)";
    fig9.y.label = "|T_a p_a - T_b p_b| (m), median";
    fig9.x.log = fig9.y.log = true;
    hist.title = "Correspondence errors";
    hist.x.label = "|T_a p_a - T_b p_b| (m)";
    hist.y.label = "correspondences";
    std::vector<std::vector<double>> errors;
    double top = 0;
    std::string table =
        "<table><tr><th>estimate</th><th>correspondences</th><th>RMSE (m)</th><th>median (m)</th></tr>\n";
    for (const ReportTrajectory& e : in.estimates) {
      const auto poses = PosesAtFrames(e.trajectory, in.frame_timestamps, in.max_time_difference);
      std::vector<std::pair<int, double>> by_gap;
      std::vector<double> all;
      for (const Correspondence& c : in.correspondences) {
        if (c.frame_a < 0 || c.frame_b < 0 || c.frame_a >= static_cast<int>(poses.size()) ||
            c.frame_b >= static_cast<int>(poses.size()) || !poses[c.frame_a] || !poses[c.frame_b]) {
          continue;
        }
        const double d = (*poses[c.frame_a] * c.point_in_a - *poses[c.frame_b] * c.point_in_b).norm();
        by_gap.emplace_back(std::abs(c.frame_b - c.frame_a), d);
        all.push_back(d);
      }
      PlotSeries s{e.name, {}, {}, e.color, PlotSeries::Style::kLine, 2};
      for (const GapBin& b : BinByGap(by_gap)) s.x.push_back(b.gap_lo), s.y.push_back(b.median);
      fig9.series.push_back(s);
      const ErrorStatistics st = ComputeStatistics(all);
      table += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n", EscapeXml(e.name), st.count,
                           Cell(st, st.rmse, 4), Cell(st, st.median, 4));
      std::vector<double> sorted = all;
      std::sort(sorted.begin(), sorted.end());
      if (!sorted.empty()) top = std::max(top, sorted[std::min(sorted.size() - 1, sorted.size() * 98 / 100)]);
      errors.push_back(std::move(all));
    }
    const int bins = 30;
    top = top > 0 ? top : 1.0;
    for (size_t i = 0; i < errors.size(); ++i) {
      const std::vector<int> h = Histogram(errors[i], top, bins);
      PlotSeries s{in.estimates[i].name, {}, {}, in.estimates[i].color, PlotSeries::Style::kLine, 2};
      for (int b = 0; b < bins; ++b) s.x.push_back((b + 0.5) * top / bins), s.y.push_back(h[b]);
      hist.series.push_back(s);
    }
    html += Section("Correspondence errors",
                    table + "</table>\n<div class=\"plots\">\n" + RenderSvg(fig9) + RenderSvg(hist) + "</div>\n" +
                        Note(fmt::format("Histogram: {} bins up to the 98th percentile; larger "
                                         "errors are counted in the last bin.",
                                         bins)));
  }
  if (!in.iterations.empty()) html += Section("Refinement", IterationPlots(in.iterations));
  html += Section("3D view", View3d(in));
  html += in.extra_html;
  html += "</body></html>\n";
  return html;
}

}  // namespace f2c
