#include "common/footprint.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace trav::common {

double Footprint::InscribedRadius() const { return std::min(half_length_m, half_width_m); }

double Footprint::CircumscribedRadius() const { return std::hypot(half_length_m, half_width_m); }

std::vector<Eigen::Vector2d> Footprint::BoundaryPoints_B(double max_spacing_m) const {
  TRAV_DEMAND(max_spacing_m > 0.0);
  const Eigen::Vector2d corners[4] = {{half_length_m, half_width_m},
                                      {-half_length_m, half_width_m},
                                      {-half_length_m, -half_width_m},
                                      {half_length_m, -half_width_m}};
  std::vector<Eigen::Vector2d> points;
  for (int side = 0; side < 4; ++side) {
    const Eigen::Vector2d& from = corners[side];
    const Eigen::Vector2d& to = corners[(side + 1) % 4];
    const int intervals =
        std::max(1, static_cast<int>(std::ceil((to - from).norm() / max_spacing_m)));
    // each side contributes its first corner and the points before the next corner
    for (int k = 0; k < intervals; ++k) {
      points.push_back(from + (to - from) * (static_cast<double>(k) / intervals));
    }
  }
  return points;
}

}  // namespace trav::common
