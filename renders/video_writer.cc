#include "renders/video_writer.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <sys/wait.h>

extern char** environ;

namespace trav::renders {

bool FfmpegAvailable() {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::stringstream directories(path);
  for (std::string directory; std::getline(directories, directory, ':');) {
    if (!directory.empty() && access((directory + "/ffmpeg").c_str(), X_OK) == 0) return true;
  }
  return false;
}

VideoWriter::VideoWriter(const std::string& path, int width, int height, double fps, int crf)
    : path_(path), width_(width), height_(height) {
  if (!FfmpegAvailable()) {
    throw std::runtime_error("video needs ffmpeg on the PATH (install the ffmpeg package)");
  }
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot create a pipe to ffmpeg");

  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  const std::string rate = fmt::format("{:g}", fps);
  const std::string quality = std::to_string(crf);
  // absolute, so that no file name (one starting with '-') can reach ffmpeg as an option
  const std::string output = std::filesystem::absolute(path).string();
  std::vector<std::string> args = {
      "ffmpeg",        "-loglevel", "error",       "-nostdin",   "-y",         "-f",   "rawvideo",
      "-pixel_format", "rgb24",     "-video_size", size,         "-framerate", rate,   "-i",
      "pipe:0",        "-c:v",      "libx264",     "-preset",    "veryfast",   "-crf", quality,
      "-pix_fmt",      "yuv420p",   "-movflags",   "+faststart", "-f",         "mp4",  output};
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);

  // the child's stdin is the pipe's read end; -nostdin keeps ffmpeg from reading the terminal
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
  const int status = posix_spawnp(&pid_, "ffmpeg", &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(fds[0]);
  if (status != 0) {
    close(fds[1]);
    throw std::runtime_error(std::string("cannot start ffmpeg: ") + std::strerror(status));
  }
  pipe_fd_ = fds[1];
  // a dead ffmpeg must surface as a write error, not kill this process
  signal(SIGPIPE, SIG_IGN);
}

VideoWriter::~VideoWriter() {
  if (pipe_fd_ >= 0) close(pipe_fd_);
  if (pid_ > 0) {
    int status = 0;
    waitpid(pid_, &status, 0);
  }
}

void VideoWriter::Write(const Image& frame) {
  if (frame.width != width_ || frame.height != height_) {
    throw std::runtime_error("video frame is " + std::to_string(frame.width) + "x" +
                             std::to_string(frame.height) + ", the video " +
                             std::to_string(width_) + "x" + std::to_string(height_));
  }
  if (pipe_fd_ < 0) throw std::runtime_error("video " + path_ + " is closed");
  const std::uint8_t* data = frame.rgb.data();
  std::size_t remaining = frame.rgb.size();
  while (remaining > 0) {
    const ssize_t written = write(pipe_fd_, data, remaining);
    if (written < 0) {
      if (errno == EINTR) continue;
      throw std::runtime_error("ffmpeg stopped while writing " + path_ + ": " +
                               std::strerror(errno));
    }
    data += written;
    remaining -= static_cast<std::size_t>(written);
  }
  ++frames_written_;
}

void VideoWriter::Close() {
  if (pipe_fd_ >= 0) {
    close(pipe_fd_);
    pipe_fd_ = -1;
  }
  if (pid_ <= 0) return;
  int status = 0;
  while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw std::runtime_error("ffmpeg failed to encode " + path_);
  }
}

}  // namespace trav::renders
