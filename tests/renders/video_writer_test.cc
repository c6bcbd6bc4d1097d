#include "renders/video_writer.h"

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "renders/renderer.h"
#include "tests/renders/render_test_util.h"

namespace trav::renders {
namespace {

// Frames in a video file, decoded by ffprobe.
int DecodedFrames(const std::string& path) {
  const std::string command =
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=nb_read_frames -of csv=p=0 '" +
      path + "'";
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) return -1;
  int frames = -1;
  if (std::fscanf(pipe.get(), "%d", &frames) != 1) return -1;
  return frames;
}

TEST(VideoWriterTest, TwoSecondsOfRenderedFramesDecodeWithTheExpectedCount) {
  auto simulation = testing::FlatWorldWithRobotAt(Eigen::Vector2d::Zero());
  RenderConfig config;
  config.width = 160;
  config.height = 120;
  Renderer renderer(simulation.get(), config);
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("trav_video_test_" + std::to_string(getpid()) + ".mp4"))
                               .string();
  VideoWriter dut(path, config.width, config.height, 30.0);
  ChaseCamera camera;
  Image frame;
  // 2 s of simulation at 500 Hz with a frame every 1/30 s
  for (int step = 0, frames = 0; step < 1000; ++step) {
    if (step * 0.002 >= frames / 30.0 - 1e-9) {
      renderer.Render(*simulation, camera.Update(simulation->State().X_WB, 1.0 / 30.0), {}, &frame);
      dut.Write(frame);
      ++frames;
    }
    simulation->Step();
  }
  dut.Close();
  EXPECT_EQ(dut.frames_written(), 60);
  EXPECT_EQ(DecodedFrames(path), 60);
  std::filesystem::remove(path);
}

TEST(VideoWriterTest, RejectsFramesOfTheWrongSize) {
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("trav_video_size_" + std::to_string(getpid()) + ".mp4"))
                               .string();
  VideoWriter dut(path, 64, 48, 30.0);
  Image frame;
  frame.width = 32;
  frame.height = 48;
  frame.rgb.resize(32 * 48 * 3);
  EXPECT_THROW(dut.Write(frame), std::runtime_error);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace trav::renders
