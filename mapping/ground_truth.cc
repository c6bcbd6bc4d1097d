#include "mapping/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "mapping/fsgp_bgk_mapper.h"
#include "mapping/traversability_mapper.h"

namespace trav::mapping {

common::GridLayers ComputeGroundTruth(const common::GridGeometry& map_geometry,
                                      const common::GridGeometry& world_geometry,
                                      const Eigen::MatrixXf& ground_m,
                                      const Eigen::MatrixXf& obstacle_m, const FsgpConfig& score,
                                      const GroundTruthConfig& config) {
  common::GridLayers truth(
      map_geometry, {layers::kTraversability, layers::kSlope, layers::kCurvature, layers::kGradient,
                     layers::kElevation, layers::kRoughness});
  const double step = world_geometry.resolution_m;
  const double half_cell_m = 0.5 * map_geometry.resolution_m;
  const int reach = static_cast<int>(std::ceil(
      std::max({config.neighbourhood_radius_m, config.footprint_radius_m, half_cell_m}) / step));
  // storage reused from cell to cell (the neighbourhoods have the same size away from the edges)
  std::vector<Eigen::Vector3d> samples;
  Eigen::MatrixXd design;
  Eigen::VectorXd z;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> plane_fit;
  Eigen::MatrixXf& slope_rad = truth.Layer(layers::kSlope);
  Eigen::MatrixXf& curvature_layer = truth.Layer(layers::kCurvature);
  Eigen::MatrixXf& gradient_m = truth.Layer(layers::kGradient);
  Eigen::MatrixXf& elevation_m = truth.Layer(layers::kElevation);
  Eigen::MatrixXf& traversability = truth.Layer(layers::kTraversability);
  for (int mx = 0; mx < map_geometry.num_x; ++mx) {
    for (int my = 0; my < map_geometry.num_y; ++my) {
      const Eigen::Vector2d centre = map_geometry.CellCenter(mx, my);
      const std::optional<Eigen::Vector2i> world_cell = world_geometry.CellIndex(centre);
      if (!world_cell) continue;
      const Eigen::Vector2i c = *world_cell;
      const double centre_z = ground_m(c.x(), c.y()) + obstacle_m(c.x(), c.y());
      samples.clear();
      bool blocked = false;
      for (int dx = -reach; dx <= reach; ++dx) {
        for (int dy = -reach; dy <= reach; ++dy) {
          const int wx = c.x() + dx, wy = c.y() + dy;
          if (!world_geometry.Contains(wx, wy)) continue;
          const Eigen::Vector2d p = world_geometry.CellCenter(wx, wy);
          const double distance = (p - centre).norm();
          const bool in_cell = (p - centre).cwiseAbs().maxCoeff() <= half_cell_m;
          if ((in_cell || distance <= config.footprint_radius_m) &&
              obstacle_m(wx, wy) > config.clearance_m)
            blocked = true;
          if (distance <= config.neighbourhood_radius_m) {
            samples.emplace_back(p.x(), p.y(), ground_m(wx, wy) + obstacle_m(wx, wy));
          }
        }
      }
      if (samples.size() < 3) continue;
      // plane, covariance and height differences of the neighbourhood
      const auto n = static_cast<Eigen::Index>(samples.size());
      design.resize(n, 3);
      z.resize(n);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      double gradient = 0.0;
      for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::Vector3d& s = samples[static_cast<std::size_t>(i)];
        design.row(i) << s.x() - centre.x(), s.y() - centre.y(), 1.0;
        z[i] = s.z();
        mean += s;
        gradient += std::abs(s.z() - centre_z);
      }
      mean /= static_cast<double>(n);
      gradient /= static_cast<double>(n);
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
      for (const Eigen::Vector3d& s : samples) covariance += (s - mean) * (s - mean).transpose();
      covariance /= static_cast<double>(n - 1);
      const Eigen::Vector3d eigenvalues =
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance, Eigen::EigenvaluesOnly)
              .eigenvalues();
      const double curvature = std::max(0.0, eigenvalues[0]) / (eigenvalues.sum() + 1e-6);
      const Eigen::Vector3d plane = plane_fit.compute(design).solve(z);
      const double slope = std::atan(plane.head<2>().norm());

      slope_rad(mx, my) = static_cast<float>(slope);
      curvature_layer(mx, my) = static_cast<float>(curvature);
      gradient_m(mx, my) = static_cast<float>(gradient);
      elevation_m(mx, my) = static_cast<float>(centre_z);
      traversability(mx, my) =
          blocked ? 1.0f : static_cast<float>(PreliminaryScore(score, curvature, gradient, slope));
    }
  }
  const Eigen::MatrixXf& elevation = truth.Layer(layers::kElevation);
  Eigen::MatrixXf& roughness = truth.Layer(layers::kRoughness);
  for (int mx = 0; mx < map_geometry.num_x; ++mx) {
    for (int my = 0; my < map_geometry.num_y; ++my) {
      if (std::isnan(elevation(mx, my))) continue;
      roughness(mx, my) = static_cast<float>(common::Roughness(elevation, mx, my));
    }
  }
  return truth;
}

}  // namespace trav::mapping
