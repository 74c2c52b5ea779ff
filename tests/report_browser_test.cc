// report.html in a real browser (headless Chromium): the page loads without console errors,
// and the 3D view draws something. A small real sequence when ../shared/data has one, else
// a synthetic scan, so the browser is exercised wherever Chromium is installed.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <opencv2/imgcodecs.hpp>  // the decoding flags

#include "f2c/io/image.h"
#include "f2c/testing/synthetic_scene.h"
#include "f2c/util/file.h"

namespace f2c {
namespace {
namespace fs = std::filesystem;

std::string RunCommand(const std::string& command, int* code) {
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  std::string out;
  std::array<char, 4096> buffer;
  size_t n = 0;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) out.append(buffer.data(), n);
  const int status = pclose(pipe);
  *code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

std::string Chromium() {
  for (const char* path : {"/usr/bin/chromium", "/usr/bin/chromium-browser"}) {
    if (fs::exists(path)) return path;
  }
  return "";
}

std::string Headless(const std::string& chromium, const fs::path& page, const fs::path& screenshot, int* code) {
  return RunCommand(chromium +
                        " --headless --no-sandbox --enable-unsafe-swiftshader --virtual-time-budget=10000 "
                        "--enable-logging=stderr --v=0 --window-size=1100,800 --screenshot=" +
                        screenshot.string() + " file://" + page.string(),
                    code);
}

TEST(ReportInABrowser, LoadsWithoutErrorsAndDrawsThe3dView) {
  const std::string chromium = Chromium();
  if (chromium.empty()) GTEST_SKIP() << "chromium absent (scripts/setup.sh installs it)";
  if (!fs::exists("/usr/share/javascript/three/three.min.js")) GTEST_SKIP() << "libjs-three absent";
  const fs::path dir = testing::FreshTempDir("report_browser");
  const fs::path real = fs::path(F2C_SHARED_DATA_DIR) / "tum_fr1_xyz_15hz";
  std::string input;
  if (fs::is_directory(real)) {
    input = real.string() + " --intrinsics tum-fr1 --last 19";
  } else {
    std::vector<Rigid3d, Eigen::aligned_allocator<Rigid3d>> poses;
    for (int i = 0; i < 8; ++i) {
      Rigid3d pose = Rigid3d::Identity();
      pose.linear() = Eigen::AngleAxisd(0.03 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
      pose.translation() = Eigen::Vector3d(0.03 * i, 0, -0.6);
      poses.push_back(pose);
    }
    testing::WriteTumSequence(dir / "scan", testing::SyntheticScene(), testing::TestIntrinsics(), poses);
    input = (dir / "scan").string() + " --intrinsics primesense --window-frames 4";
  }
  int code = 0;
  const std::string reg = RunCommand(
      std::string(F2C_CLI_PATH) + " register " + input + " -q --voxel-size 0.02 -o " + (dir / "out").string(), &code);
  ASSERT_EQ(code, 0) << reg;
  const fs::path report = dir / "out" / "report.html";
  ASSERT_TRUE(fs::exists(report));

  // The whole page: no console messages but the software renderer's own.
  const std::string log = Headless(chromium, report, dir / "page.png", &code);
  ASSERT_EQ(code, 0) << log;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    if (line.find(":CONSOLE") == std::string::npos) continue;
    if (line.find("GL Driver Message") != std::string::npos || line.find("swiftshader") != std::string::npos) continue;
    ADD_FAILURE() << "console: " << line;
  }
  // The 3D view alone at the top of a page (headless screenshots show the top): not blank.
  const std::string html = ReadFileToString(report);
  const size_t run = html.find("<section><h2>Run</h2>"), view = html.find("<section><h2>3D view</h2>");
  ASSERT_NE(view, std::string::npos);
  ASSERT_NE(html.find("<canvas id=\"view3d\""), std::string::npos) << "no 3D view in the report";
  WriteFileAtomic(dir / "view.html", html.substr(0, run) + html.substr(view));
  Headless(chromium, dir / "view.html", dir / "view.png", &code);
  const cv::Mat shot = DecodeImageFile(dir / "view.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(shot.empty());
  // The canvas (1000 x 640, its border at x = 0 and y = 150 under the headings), well inside
  // its border: not all one colour (a canvas never drawn is all black; an empty scene, all
  // white). Pixels far from the most common value are the drawing.
  const cv::Mat canvas = shot(cv::Rect(20, 170, 960, 600));
  std::array<int, 256> histogram{};
  for (int y = 0; y < canvas.rows; ++y) {
    for (int x = 0; x < canvas.cols; ++x) ++histogram[canvas.at<uint8_t>(y, x)];
  }
  const int mode = static_cast<int>(std::max_element(histogram.begin(), histogram.end()) - histogram.begin());
  int drawn = 0;
  for (int v = 0; v < 256; ++v) drawn += std::abs(v - mode) > 30 ? histogram[v] : 0;
  EXPECT_GT(drawn, 2000) << "the 3D view looks blank (one colour, " << mode << ")";
}

}  // namespace
}  // namespace f2c
