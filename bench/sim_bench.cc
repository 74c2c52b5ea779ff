// Frames per second of the simulator's renderer (640x480, PrimeSense-like intrinsics) on the
// three scenes, with the sensor model on and off, and of writing the PNGs.
//   ./build/bench/sim_bench [frames]

#include <fmt/format.h>

#include <cstdio>
#include <string>
#include <vector>

#include "f2c/io/image_write.h"
#include "f2c/sim/render.h"
#include "f2c/sim/walk.h"
#include "f2c/util/timer.h"

int main(int argc, char** argv) {
  using namespace f2c;
  const int frames = argc > 1 ? std::stoi(argv[1]) : 60;
  const CameraIntrinsics k{525.0, 525.0, 319.5, 239.5, 640, 480};
  std::printf(
      "| scene | triangles | exact render (frames/s) | with sensor model (frames/s) | PNG encode colour+depth "
      "(frames/s) |\n");
  std::printf("|---|---|---|---|---|\n");
  for (const std::string& name : sim::SceneNames()) {
    const sim::Scene scene = sim::BuildScene(name, 0);
    const sim::Renderer renderer(scene);
    sim::WalkOptions walk;
    walk.frames = frames;
    const Trajectory poses = sim::GenerateWalk(scene, walk);
    double rates[2];
    sim::RenderedView last;
    for (int mode = 0; mode < 2; ++mode) {
      const sim::SensorOptions sensor = mode == 0 ? sim::SensorOptions::Exact() : sim::SensorOptions();
      Timer timer;
      for (int i = 0; i < frames; ++i) last = renderer.Render(k, poses.world_from_camera[i], sensor, i);
      rates[mode] = frames / timer.Seconds();
    }
    Timer timer;
    std::string buffer;
    cv::Mat depth16;
    for (int i = 0; i < frames; ++i) {
      last.depth.convertTo(depth16, CV_16U, 5000.0);
      buffer = EncodePng(last.color);
      buffer = EncodePng(depth16);
    }
    std::printf("| %s | %zu | %.1f | %.1f | %.1f |\n", name.c_str(), scene.triangles.size(), rates[0], rates[1],
                frames / timer.Seconds());
  }
  return 0;
}
