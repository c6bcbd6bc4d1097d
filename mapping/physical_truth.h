#pragma once

#include <string>

#include <Eigen/Core>

#include "common/grid.h"
#include "mapping/ground_truth.h"

namespace trav::mapping {

/// The parts of a four-wheeled robot that rest on the terrain, in its base frame B (x forward,
/// y left). The defaults are the Scout Mini of models/scout_mini.xml (tests/sim/simulation_test.cc
/// checks them against the footprint measured from that file).
struct RestingBody {
  double wheel_x_m{0.2255};            ///< wheel centres ahead of and behind B (half wheelbase) [m]
  double wheel_y_m{0.245};             ///< wheel centres left and right of B (half track) [m]
  double wheel_radius_m{0.0875};       ///< [m]
  double wheel_half_width_m{0.04};     ///< [m]
  double chassis_half_length_m{0.28};  ///< the belly's half extent along x_B [m]
  double chassis_half_width_m{0.17};   ///< the belly's half extent along y_B [m]
};

/// The dense world the robot rests on: the ground heights (bilinear between samples, as MuJoCo's
/// height field) plus the obstacle surfaces' heights above the ground (constant over each sample's
/// cell), both on `geometry`.
struct RestingSurface {
  const common::GridGeometry& geometry;
  const Eigen::MatrixXf& ground_m;
  const Eigen::MatrixXf& obstacle_m;

  /// Height of the surface at p_W [m]; the grid's border value outside it.
  double HeightAt(const Eigen::Vector2d& p_W) const;
  /// True if p_W lies within the grid's extent.
  bool Contains(const Eigen::Vector2d& p_W) const;
};

/// How the robot rests at one pose (position and heading), and what that asks of it.
struct PoseAssessment {
  double pitch_rad{0.0};  ///< of the chassis plane along the heading (nose up positive)
  double roll_rad{0.0};   ///< of the chassis plane across the heading (left side up positive)
  /// The largest height difference within one wheel's contact patch relative to the chassis
  /// plane: the step a wheel climbs (or drops) [m].
  double step_m{0.0};
  /// The highest terrain under the belly above the plane of the wheel contacts [m]; the belly
  /// touches at the clearance.
  double belly_m{0.0};
  /// The largest normalised violation margin: max(|pitch| / max_pitch, |roll| / max_roll,
  /// tilt / max(max_pitch, max_roll), step / max_step, belly / clearance), clipped to [0, 1]; 1 is
  /// untraversable. The tilt is the chassis plane's own slope, whatever the heading.
  double cost{0.0};
  bool traversable{true};  ///< every ratio of `cost` below 1
  bool known{false};       ///< the robot's contact patches and belly lie within the world
};

/// Rests `body` on `surface` at p_W with heading yaw [rad] and compares the pose with the limits
/// of `config` (max_pitch, max_roll, max_step, clearance). Each wheel sits where its rim first
/// touches the surface over its contact patch (length 2 r along the heading, the wheel's width
/// across); the chassis plane is the least-squares plane of the four contacts (the independent
/// suspension shares a twist between the wheels).
PoseAssessment AssessPose(const RestingSurface& surface, const Eigen::Vector2d& p_W, double yaw,
                          const RestingBody& body, const GroundTruthConfig& config);

/// The layer of heading k (0 .. headings - 1, heading k * 360 / headings deg):
/// "traversability_h00".
std::string HeadingLayer(int k);

/// The physical, method-independent ground truth (docs/ground-truth.md) on `map_geometry`: per map
/// cell and each of `config.headings` headings, AssessPose at the cell's centre. Layers:
/// `traversability` (the cost at the best heading; 1: no heading is traversable), one
/// HeadingLayer per heading, `elevation` (the surface at the centre) and `traversable_headings`
/// (how many headings are traversable). Cells where the robot would stand partly off the world are
/// NaN. No mapper's terms or weights enter it.
common::GridLayers ComputePhysicalTruth(const common::GridGeometry& map_geometry,
                                        const common::GridGeometry& world_geometry,
                                        const Eigen::MatrixXf& ground_m,
                                        const Eigen::MatrixXf& obstacle_m, const RestingBody& body,
                                        const GroundTruthConfig& config);

/// Layer of ComputePhysicalTruth: how many headings are traversable at the cell.
inline const std::string kTraversableHeadings = "traversable_headings";

}  // namespace trav::mapping
