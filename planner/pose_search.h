#pragma once

#include <optional>
#include <vector>

#include <Eigen/Core>

#include "common/pose.h"
#include "planner/cost_field.h"
#include "planner/manoeuvres.h"

namespace trav::planner {

/// A reverse drive of the pose search costs this many times its time: the robot's way is ahead.
inline constexpr double kPoseSearchReverseFactor = 2.0;

/// The way of a skid-steer robot's footprint from `start` to within one cell of goal_W in straight
/// drives, forward or backward, and turns in place, on which every body point keeps
/// FootprintDistance >= min(clearance_m, its gap at the start): a state-lattice A* over (position,
/// heading). Positions are the start's plus whole cells of the field's grid; the 16 headings are
/// the directions of the steps to the 5 x 5 neighbourhood's outer cells, (1, 0), (2, 1), (1, 1),
/// (1, 2), ..., so that a drive of one step along a heading lands exactly on the lattice; a move is
/// one step forward or backward, or a turn to a neighbouring heading (the start turns to any
/// heading the shorter way). A move costs its time at the creep speed or yaw rate of `config` (the
/// speeds CreepThrough drives the way at; reverse drives kPoseSearchReverseFactor times), and is
/// checked at samples where no body point moves more than half a cell; the heuristic is the
/// straight-line time to the goal's tolerance. Poses farther than `config.search_reach_m` from the
/// start (per axis, plus one cell) are not searched, and the search gives up after expanding
/// `config.search_expansions` poses (> 0). Deterministic: ties go to the pose found first.
///
/// The fallback for a footprint that must turn where the search's path and its optimisation do not
/// let it (a doorway opening on furniture, the end of a dead end): Smac's state lattice in Nav2
/// does this; written here on the planner's own distance field and footprint (no library plans
/// on a rectangle's exact distance with turns in place).
///
/// @param circumscribed_radius_m the footprint's (common::Footprint::CircumscribedRadius): how far
///        a body point moves in a turn.
/// @return the poses at which the motion changes, the start excluded: each is reached from the one
///         before by a turn in place (the shorter way, at most 3 pi / 4) to its yaw, then a
///         straight drive to its position, forward or backward along that yaw. Empty if the start
///         is within the tolerance; nullopt if no way is found within the reach and the
///         expansions.
std::optional<std::vector<common::Pose2>> SearchPoses(
    const CostField& field, const std::vector<Eigen::Vector2d>& body_points_B,
    double circumscribed_radius_m, double clearance_m, const common::Pose2& start,
    const Eigen::Vector2d& goal_W, const FallbackConfig& config);

}  // namespace trav::planner
