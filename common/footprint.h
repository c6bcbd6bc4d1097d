#pragma once

#include <vector>

#include <Eigen/Core>

namespace trav::common {

/// The robot's outline seen from above: a rectangle centred on the base frame B's origin, x forward
/// and y left (REP-103), that holds every collision geometry of the robot (chassis and wheels). The
/// one robot model for clearance that the ground truth, the search and the trajectory optimiser
/// share (docs/navigation.md). The defaults are the Scout Mini of models/scout_mini.xml: wheel
/// centres 0.2255 m ahead and behind, wheels of radius 0.0875 m; wheel outer faces 0.285 m to the
/// side.
struct Footprint {
  double half_length_m{0.313};  ///< along x_B [m], > 0
  double half_width_m{0.285};   ///< along y_B [m], > 0

  /// Radius of the largest disc inside the rectangle [m]: a robot whose centre keeps this far from
  /// an obstacle clears it broadside.
  double InscribedRadius() const;

  /// Radius of the smallest disc round the rectangle [m]: a robot whose centre keeps this far from
  /// every obstacle can turn in place.
  double CircumscribedRadius() const;

  /// Points on the rectangle's boundary in B [m]: the four corners and, along each side, as many
  /// evenly spaced points as keep neighbours at most `max_spacing_m` apart (> 0).
  std::vector<Eigen::Vector2d> BoundaryPoints_B(double max_spacing_m) const;
};

}  // namespace trav::common
