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

/// A grid layer (num_x, num_y), values in [0, 1], as an image with +y up: green (0) through yellow
/// to red (1), unknown (NaN) grey. One pixel per cell.
Image TraversabilityImage(const Eigen::MatrixXf& values);

/// Writes an 8-bit RGB PNG. @throws std::runtime_error if the file cannot be written.
void WritePng(const std::string& path, const Image& image);

/// Writes a 16-bit grayscale PNG of `width` x `height` values (rows top to bottom).
/// @throws std::runtime_error if the file cannot be written.
void WritePng16(const std::string& path, int width, int height,
                const std::vector<std::uint16_t>& values);

}  // namespace trav::renders
