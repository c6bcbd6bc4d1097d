#pragma once

#include <string>

#include <sys/types.h>

#include "renders/image.h"

namespace trav::renders {

/// Encodes frames to an H.264 MP4 by piping raw RGB to an ffmpeg process (libx264, yuv420p so every
/// player opens it). ffmpeg runs as a separate process, so it costs the simulation little.
class VideoWriter {
 public:
  /// Starts ffmpeg writing `path` with frames of `width` x `height` at `fps` frames per second, at
  /// x264's constant rate factor `crf` (0 lossless .. 51; 18 looks lossless, 23 is x264's default).
  /// @throws std::runtime_error if ffmpeg is not installed or cannot be started.
  VideoWriter(const std::string& path, int width, int height, double fps, int crf = 23);
  /// Closes the pipe and waits for ffmpeg if Close() was not called (errors are ignored there).
  ~VideoWriter();
  VideoWriter(const VideoWriter&) = delete;
  VideoWriter& operator=(const VideoWriter&) = delete;

  /// Appends one frame (must have the writer's size).
  /// @throws std::runtime_error if the size differs or ffmpeg has stopped.
  void Write(const Image& frame);

  /// Finishes the file. @throws std::runtime_error if ffmpeg failed.
  void Close();

  int frames_written() const { return frames_written_; }

 private:
  std::string path_;
  int width_;
  int height_;
  int pipe_fd_{-1};
  pid_t pid_{-1};
  int frames_written_{0};
};

/// True if an `ffmpeg` executable is on the PATH.
bool FfmpegAvailable();

}  // namespace trav::renders
