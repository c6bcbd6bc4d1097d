#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/enum_names.h"
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
  /// The robot's top above the ground at rest (the LiDAR's) [m]: obstacle material wholly above it
  /// does not touch the robot.
  double height_m{0.305};
};

/// The cell of the obstacle grid the physical truth rests the robot on [m]: fine enough that an
/// obstacle's outline is off by at most 1.25 cm (sim::ObstacleBandRaster).
constexpr double kObstacleOutlineResolution_m = 0.025;

/// The dense world the robot rests on: the ground heights on `ground_geometry` (bilinear between
/// samples, as MuJoCo's height field), and where an obstacle stands the height of its top on
/// `obstacle_geometry` (constant over each cell, NaN where there is none: a grid finer than the
/// ground's keeps the obstacles' outlines, sim::ObstacleBandRaster).
class RestingSurface {
 public:
  /// Keeps references: the grids must outlive the surface.
  RestingSurface(const common::GridGeometry& ground_geometry, const Eigen::MatrixXf& ground_m,
                 const common::GridGeometry& obstacle_geometry,
                 const Eigen::MatrixXf& obstacle_top_m);

  /// Height of the surface at p_W [m]: the higher of the ground (bilinear, clamped to the grid's
  /// border) and an obstacle's top at the obstacle cell holding p_W.
  double HeightAt(const Eigen::Vector2d& p_W) const;
  /// True if the disc of `radius_m` about p_W lies within the ground grid's extent.
  bool Contains(const Eigen::Vector2d& p_W, double radius_m) const;

 private:
  const common::GridGeometry& ground_geometry_;
  const Eigen::MatrixXf& ground_m_;
  const common::GridGeometry& obstacle_geometry_;
  const Eigen::MatrixXf& obstacle_top_m_;
  double ground_cells_per_m_;
  double obstacle_cells_per_m_;
};

/// The limit a pose comes closest to (or violates most).
enum class RestingLimit { kPitch, kRoll, kTilt, kStep, kFrontStep, kDrop, kBelly };

/// The names of RestingLimit's values (common/enum_names.h).
inline constexpr std::array<common::EnumName<RestingLimit>, 7> kRestingLimitNames{
    {{RestingLimit::kPitch, "pitch"},
     {RestingLimit::kRoll, "roll"},
     {RestingLimit::kTilt, "tilt"},
     {RestingLimit::kStep, "step"},
     {RestingLimit::kFrontStep, "front_step"},
     {RestingLimit::kDrop, "drop"},
     {RestingLimit::kBelly, "belly"}}};
constexpr const auto& EnumNames(RestingLimit) { return kRestingLimitNames; }

/// How the robot rests at one pose (position and heading), and what that asks of it.
struct PoseAssessment {
  double pitch_rad{0.0};  ///< of the chassis plane along the heading (nose up positive)
  double roll_rad{0.0};   ///< of the chassis plane across the heading (left side up positive)
  /// The highest step up a rear wheel climbs within its contact patch in the direction of travel,
  /// less the chassis plane's rise along it (a slope is no step) [m]; `front_step_m` a front
  /// wheel's; `drop_m` the deepest step down of any wheel.
  double step_m{0.0};
  double front_step_m{0.0};
  double drop_m{0.0};
  /// The highest terrain under the belly above the plane of the wheel contacts [m]; the belly
  /// touches at the clearance.
  double belly_m{0.0};
  /// The largest normalised violation margin: max(|pitch| / max_pitch, |roll| / max_roll,
  /// tilt / max(max_pitch, max_roll), step / max_step, front_step / max_front_step,
  /// drop / max_drop, belly / clearance), clipped to [0, 1]; 1 is untraversable. The tilt is the
  /// chassis plane's own slope, whatever the heading.
  double cost{0.0};
  bool traversable{true};                    ///< every ratio of `cost` below 1
  RestingLimit limit{RestingLimit::kPitch};  ///< the ratio that sets `cost`
  bool known{false};  ///< the robot's contact patches and belly lie within the world
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
/// cell and each of `config.headings` headings, AssessPose on `surface` at the cell's centre
/// (with an even number of headings, the second half rests the robot on the first half's surface
/// lookups mirrored: the body's samples are symmetric about its centre, so the same poses up to
/// the rotation's rounding, and half the lookups). Layers: `traversability` (the cost at the best
/// heading; 1: no heading is traversable), one HeadingLayer per heading, `elevation` (the surface
/// at the centre) and `traversable_headings` (how many headings are traversable). Cells where the
/// robot at some heading would reach off the world are NaN. No mapper's terms or weights enter it.
common::GridLayers ComputePhysicalTruth(const common::GridGeometry& map_geometry,
                                        const RestingSurface& surface, const RestingBody& body,
                                        const GroundTruthConfig& config);

/// ComputePhysicalTruth at the cells (ix, iy) of `map_geometry` in `cells` only (each cell's
/// values are its own: the same as the whole grid's there), every other cell NaN: what a score
/// over the cells a drive observed needs (`trav eval`), at a fraction of the whole grid's time.
common::GridLayers ComputePhysicalTruth(const common::GridGeometry& map_geometry,
                                        const std::vector<Eigen::Vector2i>& cells,
                                        const RestingSurface& surface, const RestingBody& body,
                                        const GroundTruthConfig& config);

/// Layer of ComputePhysicalTruth: how many headings are traversable at the cell.
inline const std::string kTraversableHeadings = "traversable_headings";

}  // namespace trav::mapping
