#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace trav::renders {

/// An 8-bit RGB image, rows top to bottom, pixels left to right.
struct Image {
  int width{0};
  int height{0};
  std::vector<std::uint8_t> rgb;  ///< width * height * 3 bytes

  /// Pointer to the pixel at column x, row y (row 0 at the top).
  const std::uint8_t* Pixel(int x, int y) const { return rgb.data() + 3 * (y * width + x); }
};

/// Fills the pixels of columns [x0, x1) and rows [y0, y1) of `image` that lie in it with `rgb`
/// (components 0..255).
void FillRect(Image* image, int x0, int y0, int x1, int y1, const Eigen::Vector3i& rgb);

/// A grid layer (num_x, num_y), values in [0, 1], as an image with +y up: green (0) through yellow
/// to red (1), unknown (NaN) grey. One pixel per cell.
Image TraversabilityImage(const Eigen::MatrixXf& values);

/// Writes an 8-bit RGB PNG. @throws std::runtime_error if the file cannot be written.
void WritePng(const std::string& path, const Image& image);

/// Reads a PNG of any colour type and depth as 8-bit RGB (alpha composed over black, gray
/// expanded, 16-bit samples scaled). @throws std::runtime_error naming the file if it cannot be
/// read or holds more than `max_pixels` pixels.
Image ReadPngRgb(const std::string& path, std::size_t max_pixels);

/// `image` shrunk to fit `max_width` x `max_height`, its aspect ratio kept, each pixel the mean of
/// the source pixels it covers (a box filter); an image already within the size is returned as
/// it is.
Image Downscale(const Image& image, int max_width, int max_height);

/// A grayscale image of 16-bit samples, rows top to bottom.
struct GrayImage16 {
  int width{0};
  int height{0};
  std::vector<std::uint16_t> values;  ///< width * height samples, row by row

  std::uint16_t At(int x, int y) const {
    return values[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                  static_cast<std::size_t>(x)];
  }
};

/// Reads a grayscale PNG of 1 to 16 bits per sample (8-bit and lower samples scaled to the full
/// 16-bit range, 255 -> 65535), as `trav terrain` writes heightmap.png. The PNG must hold at most
/// `max_pixels` samples. @throws common::InputError naming the file if it is not a grayscale PNG
/// (colour, alpha, palette) or cannot be read.
GrayImage16 ReadPng16(const std::string& path, std::size_t max_pixels);

/// Writes a 16-bit grayscale PNG of `width` x `height` values (rows top to bottom).
/// @throws std::runtime_error if the file cannot be written.
void WritePng16(const std::string& path, int width, int height,
                const std::vector<std::uint16_t>& values);

}  // namespace trav::renders
