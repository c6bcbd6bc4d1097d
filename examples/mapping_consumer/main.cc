// FSGP-BGK on frames of flat ground with a 2 m wall across the way, then A* round the wall on the
// map: trav's mapper and planner used from another project (find_package(trav)). Prints the mapped
// cells, the wall's cost and the path.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "common/point_cloud.h"
#include "mapping/fsgp_bgk_mapper.h"
#include "planner/astar.h"

namespace {

// Ground every 0.1 m over 10 x 10 m around `centre` and a wall 1 m high along y at x = 2 from
// y = -1 to 1.
trav::common::PointCloud Frame(const Eigen::Vector2d& centre) {
  std::vector<Eigen::Vector3f> points;
  for (double x = centre.x() - 5.0; x <= centre.x() + 5.0; x += 0.1) {
    for (double y = centre.y() - 5.0; y <= centre.y() + 5.0; y += 0.1) {
      points.emplace_back(static_cast<float>(x), static_cast<float>(y), 0.0f);
    }
  }
  for (double y = -1.0; y <= 1.0; y += 0.05) {
    for (double z = 0.05; z <= 1.0; z += 0.05) {
      points.emplace_back(2.0f, static_cast<float>(y), static_cast<float>(z));
    }
  }
  return trav::common::MakePointCloud(points);
}

}  // namespace

int main() {
  trav::mapping::FsgpBgkMapper mapper(trav::mapping::FsgpConfig{});
  for (int k = 0; k < 3; ++k) {
    Eigen::Isometry3d X_WB = Eigen::Isometry3d::Identity();
    X_WB.translation() = Eigen::Vector3d(0.2 * k, 0.0, 0.3);
    const trav::mapping::MapUpdateResult result =
        mapper.Update(Frame({0.2 * k, 0.0}), X_WB, 0.1 * k);
    std::printf("frame %d: %d training points, %d cells\n", k, result.training_points,
                result.observed_cells);
  }
  const std::optional<float> wall =
      mapper.map().At(trav::mapping::layers::kTraversability, Eigen::Vector2d(2.0, 0.0));
  std::printf("wall cost %.2f\n", wall ? *wall : -1.0f);

  const trav::planner::GridPlanner planner(mapper.map(), trav::planner::AStarConfig{});
  const trav::planner::GridPath path =
      planner.Plan(Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(4.0, 0.0));
  double widest = 0.0;
  for (const Eigen::Vector2d& p : path.points_W) widest = std::max(widest, std::abs(p.y()));
  std::printf("path %s, %zu cells, %.2f m off the straight line\n",
              path.status == trav::planner::PlanStatus::kFound ? "found" : "not found",
              path.points_W.size(), widest);
  return path.status == trav::planner::PlanStatus::kFound ? 0 : 1;
}
