#include "renders/map_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "renders/overlay.h"

namespace trav::renders {
namespace {

// World to pixel for a square view: +x right, +y up.
struct View {
  Eigen::Vector2d corner_W;  // bottom-left [m]
  double pixels_per_m;
  int size_px;

  Eigen::Vector2d ToPixel(const Eigen::Vector2d& p_W) const {
    const Eigen::Vector2d q = (p_W - corner_W) * pixels_per_m;
    return {q.x(), size_px - q.y()};
  }
  Eigen::Vector2d ToWorld(double px, double py) const {
    return corner_W + Eigen::Vector2d(px, size_px - py) / pixels_per_m;
  }
};

void Put(Image* image, int x, int y, const Eigen::Vector3i& rgb) {
  if (x < 0 || y < 0 || x >= image->width || y >= image->height) return;
  std::uint8_t* p = image->rgb.data() + 3 * (y * image->width + x);
  for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(std::clamp(rgb[c], 0, 255));
}

// A square brush of `width` pixels stamped along the segment a-b.
void Segment(Image* image, const Eigen::Vector2d& a, const Eigen::Vector2d& b, int width,
             const Eigen::Vector3i& rgb) {
  const int steps = static_cast<int>(std::ceil((b - a).norm())) + 1;
  const int low = -(width - 1) / 2, high = width / 2;
  for (int k = 0; k <= steps; ++k) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(k) / steps);
    for (int dx = low; dx <= high; ++dx) {
      for (int dy = low; dy <= high; ++dy) {
        Put(image, static_cast<int>(std::floor(p.x())) + dx,
            static_cast<int>(std::floor(p.y())) + dy, rgb);
      }
    }
  }
}

}  // namespace

Image DrawMapPanel(const common::GridLayers& map, const Eigen::MatrixXf& layer,
                   const Eigen::Vector2d& centre_W, double span_m, int size_px,
                   const PanelOverlay& overlay) {
  Image image;
  image.width = image.height = size_px;
  image.rgb.assign(static_cast<std::size_t>(3 * size_px * size_px), 0);
  const View view{centre_W - Eigen::Vector2d::Constant(0.5 * span_m), size_px / span_m, size_px};
  const common::GridGeometry& g = map.geometry();
  const Eigen::Vector3i unknown(128, 128, 128);
  for (int py = 0; py < size_px; ++py) {
    for (int px = 0; px < size_px; ++px) {
      const std::optional<Eigen::Vector2i> cell = g.CellIndex(view.ToWorld(px + 0.5, py + 0.5));
      const float value = cell ? layer(cell->x(), cell->y()) : NAN;
      if (std::isnan(value)) {
        Put(&image, px, py, unknown);
      } else {
        const Eigen::Vector3f c = TraversabilityColor(value, 0.0f, 1.0f);
        Put(&image, px, py, (255.0f * c).cast<int>());
      }
    }
  }
  for (const PanelPath& path : overlay.paths) {
    for (std::size_t i = 1; i < path.points_W.size(); ++i) {
      Segment(&image, view.ToPixel(path.points_W[i - 1]), view.ToPixel(path.points_W[i]),
              path.width_px, path.rgb);
    }
  }
  for (const Eigen::Vector2d& p_W : overlay.points_W) {
    const Eigen::Vector2d p = view.ToPixel(p_W);
    Put(&image, static_cast<int>(std::floor(p.x())), static_cast<int>(std::floor(p.y())),
        overlay.points_rgb);
  }
  for (const PanelDisc& disc : overlay.discs) {
    const Eigen::Vector2d c = view.ToPixel(disc.centre_W);
    const double r = std::max(1.5, disc.radius_m * view.pixels_per_m);
    const int reach = static_cast<int>(std::ceil(r));
    for (int dx = -reach; dx <= reach; ++dx) {
      for (int dy = -reach; dy <= reach; ++dy) {
        const double d = std::hypot(dx, dy);
        if (d > r || (!disc.filled && d < r - 1.5)) continue;
        Put(&image, static_cast<int>(std::floor(c.x())) + dx,
            static_cast<int>(std::floor(c.y())) + dy, disc.rgb);
      }
    }
  }
  return image;
}

Image SideBySide(const Image& left, const Image& right) {
  if (left.height != right.height) {
    throw std::invalid_argument("SideBySide: the images must have the same height");
  }
  Image out;
  out.width = left.width + right.width;
  out.height = left.height;
  out.rgb.resize(static_cast<std::size_t>(3 * out.width * out.height));
  for (int y = 0; y < out.height; ++y) {
    std::copy_n(left.Pixel(0, y), 3 * left.width, out.rgb.data() + 3 * (y * out.width));
    std::copy_n(right.Pixel(0, y), 3 * right.width,
                out.rgb.data() + 3 * (y * out.width + left.width));
  }
  return out;
}

}  // namespace trav::renders
