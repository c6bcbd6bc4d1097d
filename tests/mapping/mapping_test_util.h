#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/grid.h"
#include "common/point_cloud.h"
#include "common/random.h"

namespace trav::mapping::testing {

// A dense cloud of z = height(x, y) over a square of `half` around `centre`, spacing 0.1 m, with a
// little seeded noise.
inline common::PointCloud Surface(const std::function<double(double, double)>& height,
                                  const Eigen::Vector2d& centre, double half = 5.0,
                                  double noise = 0.002) {
  common::Random random(11);
  std::vector<Eigen::Vector3f> points;
  for (double x = centre.x() - half; x <= centre.x() + half; x += 0.1) {
    for (double y = centre.y() - half; y <= centre.y() + half; y += 0.1) {
      points.emplace_back(static_cast<float>(x), static_cast<float>(y),
                          static_cast<float>(height(x, y) + noise * random.Normal()));
    }
  }
  return common::MakePointCloud(points);
}

inline Eigen::Isometry3d RobotAt(double x, double y, double z = 0.3) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.translation() = Eigen::Vector3d(x, y, z);
  return X;
}

// Mean of a layer over known cells within `radius` of p.
inline double MeanNear(const common::GridLayers& map, const std::string& layer,
                       const Eigen::Vector2d& p, double radius) {
  const common::GridGeometry& g = map.geometry();
  double sum = 0.0;
  int n = 0;
  for (int ix = 0; ix < g.num_x; ++ix) {
    for (int iy = 0; iy < g.num_y; ++iy) {
      const float v = map.Layer(layer)(ix, iy);
      if (!std::isnan(v) && (g.CellCenter(ix, iy) - p).norm() <= radius) {
        sum += v;
        ++n;
      }
    }
  }
  return n > 0 ? sum / n : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace trav::mapping::testing
