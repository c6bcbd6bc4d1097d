#include "renders/image.h"

#include <png.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "common/input_error.h"
#include "renders/overlay.h"

namespace trav::renders {
namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

// Writes rows with libpng; `bit_depth` 8 (RGB) or 16 (gray, big-endian rows prepared by the
// caller).
void WriteRows(const std::string& path, int width, int height, int bit_depth, int color_type,
               const std::vector<png_bytep>& rows) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "wb"));
  if (!file) throw std::runtime_error("cannot write " + path);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (png == nullptr || info == nullptr) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng: out of memory writing " + path);
  }
  // libpng reports errors by longjmp
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng: cannot write " + path);
  }
  png_init_io(png, file.get());
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height),
               bit_depth, color_type, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  png_write_image(png, const_cast<png_bytepp>(rows.data()));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  // a full disk shows only when the buffered bytes go out
  const bool flushed = std::fflush(file.get()) == 0;
  if (std::fclose(file.release()) != 0 || !flushed) {
    throw common::InputError(path, "", std::string("cannot write: ") + std::strerror(errno));
  }
}

}  // namespace

Image TraversabilityImage(const Eigen::MatrixXf& values) {
  Image image;
  image.width = static_cast<int>(values.rows());
  image.height = static_cast<int>(values.cols());
  image.rgb.resize(static_cast<std::size_t>(image.width) * image.height * 3);
  for (int row = 0; row < image.height; ++row) {
    for (int ix = 0; ix < image.width; ++ix) {
      const float value = values(ix, image.height - 1 - row);
      const Eigen::Vector3f color = std::isnan(value) ? Eigen::Vector3f(0.5f, 0.5f, 0.5f)
                                                      : TraversabilityColor(value, 0.0f, 1.0f);
      std::uint8_t* pixel =
          image.rgb.data() + 3 * (static_cast<std::size_t>(row) * image.width + ix);
      for (int c = 0; c < 3; ++c)
        pixel[c] = static_cast<std::uint8_t>(std::lround(255.0f * color[c]));
    }
  }
  return image;
}

void WritePng(const std::string& path, const Image& image) {
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.height));
  for (int y = 0; y < image.height; ++y) {
    rows[static_cast<std::size_t>(y)] = const_cast<png_bytep>(image.Pixel(0, y));
  }
  WriteRows(path, image.width, image.height, 8, PNG_COLOR_TYPE_RGB, rows);
}

void WritePng16(const std::string& path, int width, int height,
                const std::vector<std::uint16_t>& values) {
  // PNG stores 16-bit samples big-endian
  std::vector<png_byte> bytes(values.size() * 2);
  for (std::size_t i = 0; i < values.size(); ++i) {
    bytes[2 * i] = static_cast<png_byte>(values[i] >> 8);
    bytes[2 * i + 1] = static_cast<png_byte>(values[i] & 0xff);
  }
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) rows[static_cast<std::size_t>(y)] = bytes.data() + 2 * y * width;
  WriteRows(path, width, height, 16, PNG_COLOR_TYPE_GRAY, rows);
}

void FillRect(Image* image, int x0, int y0, int x1, int y1, const Eigen::Vector3i& rgb) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, image->width);
  y1 = std::min(y1, image->height);
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      std::uint8_t* p = image->rgb.data() + 3 * (static_cast<std::size_t>(y) * image->width + x);
      for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(std::clamp(rgb[c], 0, 255));
    }
  }
}

Image ReadPngRgb(const std::string& path, std::size_t max_pixels) {
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  if (png_image_begin_read_from_file(&png, path.c_str()) == 0) {
    throw std::runtime_error("cannot read the PNG " + path + ": " + png.message);
  }
  if (static_cast<std::size_t>(png.width) * png.height > max_pixels) {
    png_image_free(&png);
    throw std::runtime_error(path + " has more than " + std::to_string(max_pixels) + " pixels");
  }
  png.format = PNG_FORMAT_RGB;
  Image image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.rgb.resize(PNG_IMAGE_SIZE(png));
  const png_color black{0, 0, 0};
  if (png_image_finish_read(&png, &black, image.rgb.data(), 0, nullptr) == 0) {
    throw std::runtime_error("cannot read the PNG " + path + ": " + png.message);
  }
  return image;
}

Image Downscale(const Image& image, int max_width, int max_height) {
  const double scale = std::min({1.0, static_cast<double>(max_width) / image.width,
                                 static_cast<double>(max_height) / image.height});
  if (scale >= 1.0) return image;
  Image out;
  out.width = std::max(1, static_cast<int>(image.width * scale));
  out.height = std::max(1, static_cast<int>(image.height * scale));
  out.rgb.resize(static_cast<std::size_t>(3 * out.width * out.height));
  for (int y = 0; y < out.height; ++y) {
    const int y0 = y * image.height / out.height, y1 = (y + 1) * image.height / out.height;
    for (int x = 0; x < out.width; ++x) {
      const int x0 = x * image.width / out.width, x1 = (x + 1) * image.width / out.width;
      int sum[3] = {0, 0, 0};
      for (int sy = y0; sy < y1; ++sy) {
        for (int sx = x0; sx < x1; ++sx) {
          for (int c = 0; c < 3; ++c) sum[c] += image.Pixel(sx, sy)[c];
        }
      }
      const int n = (y1 - y0) * (x1 - x0);
      for (int c = 0; c < 3; ++c) {
        out.rgb[static_cast<std::size_t>(3 * (y * out.width + x) + c)] =
            static_cast<std::uint8_t>((sum[c] + n / 2) / n);
      }
    }
  }
  return out;
}

GrayImage16 ReadPng16(const std::string& path, std::size_t max_pixels) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file)
    throw common::InputError(path, "", std::string("cannot read: ") + std::strerror(errno));
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (png == nullptr || info == nullptr) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw std::runtime_error("libpng: out of memory reading " + path);
  }
  GrayImage16 image;
  std::vector<png_byte> bytes;
  std::vector<png_bytep> rows;
  // libpng reports errors by longjmp; nothing with a destructor is created between here and the
  // end of reading
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw common::InputError(path, "", "not a readable PNG");
  }
  png_init_io(png, file.get());
  png_read_info(png, info);
  const int color_type = png_get_color_type(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  const std::size_t width = png_get_image_width(png, info);
  const std::size_t height = png_get_image_height(png, info);
  if (color_type != PNG_COLOR_TYPE_GRAY || width * height > max_pixels) {
    png_destroy_read_struct(&png, &info, nullptr);
    throw common::InputError(path, "",
                             color_type != PNG_COLOR_TYPE_GRAY
                                 ? "must be a grayscale PNG without alpha (a heightmap)"
                                 : "has more than " + std::to_string(max_pixels) + " pixels");
  }
  if (bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  png_read_update_info(png, info);
  const std::size_t row_bytes = png_get_rowbytes(png, info);
  bytes.resize(row_bytes * height);
  rows.resize(height);
  for (std::size_t y = 0; y < height; ++y) rows[y] = bytes.data() + y * row_bytes;
  png_read_image(png, rows.data());
  png_read_end(png, nullptr);
  png_destroy_read_struct(&png, &info, nullptr);

  image.width = static_cast<int>(width);
  image.height = static_cast<int>(height);
  image.values.resize(width * height);
  const bool sixteen = bit_depth == 16;
  constexpr int kEightToSixteen = 257;  // 255 -> 65535
  for (std::size_t y = 0; y < height; ++y) {
    for (std::size_t x = 0; x < width; ++x) {
      const png_byte* sample = rows[y] + (sixteen ? 2 * x : x);
      // 16-bit samples are big-endian; lower depths were expanded to 8 bits (libpng scales 1 to
      // 255)
      const int value = sixteen ? (sample[0] << 8) | sample[1] : sample[0] * kEightToSixteen;
      image.values[y * width + x] = static_cast<std::uint16_t>(value);
    }
  }
  return image;
}

}  // namespace trav::renders
