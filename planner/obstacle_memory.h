#pragma once

#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/grid.h"
#include "planner/cost_map.h"

namespace trav::planner {

/// What the robot remembers of the obstacles it has seen, on a world-fixed grid over the operating
/// area. The traversability map is a window round the robot (`mapping.map_size`) and forgets what
/// leaves it; the memory keeps, for every cell it has seen, whether that cell was lethal when last
/// seen (IsLethal of a known cost). A* reads it where its map ends (GridPlanner): the way on from
/// the map's edge to a goal beyond it is measured round the remembered obstacles instead of
/// straight across them, so that a dead end left behind is not entered again once it has left
/// the window. Only the lethal cells are remembered, not their inflation: the memory's ways may
/// pass gaps the robot cannot, which is why it only ranks the ways out of the map and never lays
/// the robot's path. A copyable value; reads are const and thread-safe.
class ObstacleMemory {
 public:
  /// Remembers nothing, on cells of `map_lattice`'s resolution with centres on its lattice (a
  /// rolling map's cells stay on one lattice, GridLayers::Recenter) covering `area_W`.
  ObstacleMemory(const Eigen::AlignedBox2d& area_W, const common::GridGeometry& map_lattice);

  /// True if the cells of `map` lie on this memory's lattice (same resolution, centres on it), so
  /// that Record can take them.
  bool SharesLattice(const common::GridGeometry& map) const;

  /// Takes what a map shows (`layer` on `map`, costs in [0, 1], NaN unknown): cells with a lethal
  /// known cost are remembered blocked, cells with a known cost below it free; unknown cells keep
  /// what was remembered, and cells off the memory's grid are ignored. Precondition (checked):
  /// SharesLattice(map).
  void Record(const common::GridGeometry& map, const Eigen::MatrixXf& layer,
              const CostMapConfig& config);

  /// True if p_W lies in a cell remembered blocked; false off the grid.
  bool Blocked(const Eigen::Vector2d& p_W) const;

  /// True if the straight segment a_W-b_W crosses a cell remembered blocked (sampled at most half
  /// a cell apart, both ends included).
  bool Obstructed(const Eigen::Vector2d& a_W, const Eigen::Vector2d& b_W) const;

  /// The length of the shortest way [m] from goal_W to every cell, 8-connected over the cells not
  /// remembered blocked (a diagonal step only where both cells beside it are free too): from the
  /// cell nearest to goal_W (clamped onto the grid), which is the source even if blocked;
  /// infinity where the remembered obstacles wall a cell off. Deterministic.
  Eigen::MatrixXd DistancesFrom(const Eigen::Vector2d& goal_W) const;

  /// The memory's cells.
  const common::GridGeometry& geometry() const { return geometry_; }

 private:
  common::GridGeometry geometry_;
  Eigen::Matrix<std::uint8_t, Eigen::Dynamic, Eigen::Dynamic> blocked_;  // 1 remembered blocked
};

}  // namespace trav::planner
