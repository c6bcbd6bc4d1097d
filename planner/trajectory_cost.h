#pragma once

#include <vector>

#include <Eigen/Core>

#include "planner/cost_field.h"
#include "planner/minco.h"

namespace trav::planner {

/// Dynamic limits of the base, defaults for the AgileX Scout Mini (3 m/s top speed, 2.52 rad/s top
/// yaw rate; accelerations between its ROS controller's 3 m/s^2 and its description's 1 m/s^2).
struct DynamicLimits {
  double max_speed_m_s{1.5};                      ///< |v|, (0, 3]
  double max_yaw_rate_rad_s{2.5};                 ///< |omega|, > 0
  double max_acceleration_m_s2{1.5};              ///< |dv/dt|, > 0
  double max_yaw_acceleration_rad_s2{4.0};        ///< |domega/dt|, > 0
  double max_centripetal_acceleration_m_s2{2.0};  ///< |v omega| (skid and roll-over), > 0
};

/// Weights of the trajectory cost. Penalties use the C^2 smoothed L1 function of GCOPTER / DDR-opt
/// on the constraint's violation, integrated over time.
struct TrajectoryCostWeights {
  double yaw_jerk{0.33};           ///< energy weight of yaw jerk [1/(rad^2 s^-5)]
  double arc_length_jerk{1.0};     ///< energy weight of arc-length jerk
  double time{50.0};               ///< per second of duration
  double traversability{50.0};     ///< per metre driven on cost 1 (int c |v| dt)
  double limits{1.0e4};            ///< on the dynamic limits, the terrain's speed and the slope
  double clearance{1.0e5};         ///< on the clearance from lethal cells
  double moving_obstacles{1.0e5};  ///< on the clearance from moving obstacles
};

/// A moving obstacle as the planner predicts it: a disc at constant velocity.
struct MovingObstacle {
  Eigen::Vector2d position_W{Eigen::Vector2d::Zero()};  ///< centre at time t_s [m]
  Eigen::Vector2d velocity_W{Eigen::Vector2d::Zero()};  ///< [m/s]
  double radius_m{0.3};                                 ///< [m]
  double t_s{0.0};                                      ///< time of position_W [s]

  /// Predicted centre at time t [s].
  Eigen::Vector2d PositionAt(double t) const { return position_W + (t - t_s) * velocity_W; }
};

/// Everything the cost needs besides the decision vector.
struct TrajectoryCostSetup {
  DynamicLimits limits;
  TrajectoryCostWeights weights;
  double clearance_m{0.35};  ///< distance kept from lethal cells by every body point [m]
  /// The points of the robot's body in its base frame B that keep the clearance (the boundary of
  /// its footprint, common::Footprint::BoundaryPoints_B) [m]; the default is the base's origin.
  std::vector<Eigen::Vector2d> body_points_B{Eigen::Vector2d::Zero()};
  /// The largest distance of a body point from the base's origin [m] (0 for the default): where
  /// the field's distance at the base exceeds the clearance by sqrt(2) times this, no body point
  /// can be closer than the clearance (the bilinear distance field changes by at most sqrt(2) m per
  /// metre), and the points are not evaluated.
  double body_reach_m{0.0};
  double robot_radius_m{0.35};        ///< disc around the base for moving obstacles [m]
  double obstacle_clearance_m{0.3};   ///< gap kept between that disc and a mover's [m]
  double clearance_growth_m_s{0.05};  ///< the gap grows by this per second ahead (prediction error)
  int samples_per_piece{8};           ///< integration intervals per piece, even, >= 2
  double smoothing{1.0e-2};           ///< width of the smoothed L1 function
  double start_time_s{0.0};           ///< absolute time of the trajectory's start [s]
  Eigen::Vector2d start_W{Eigen::Vector2d::Zero()};  ///< position at the start [m]
  /// Yaw (column 0, [rad]) and arc length (column 1, [m]) at the start: value, rate, acceleration.
  Eigen::Matrix<double, 3, 2> head{Eigen::Matrix<double, 3, 2>::Zero()};
  Eigen::Vector2d goal_W{Eigen::Vector2d::Zero()};  ///< end position, held by augmented Lagrangian
  std::vector<MovingObstacle> obstacles;
};

/// The value of each cost term.
struct CostTerms {
  double energy{0.0};
  double time{0.0};
  double limits{0.0};
  double clearance{0.0};
  double traversability{0.0};
  double moving_obstacles{0.0};
  double terminal{0.0};  ///< augmented-Lagrangian term of the end position

  double Total() const {
    return energy + time + limits + clearance + traversability + moving_obstacles + terminal;
  }
};

/// The DDR-opt trajectory cost for a differential-drive base (Zhang et al., "Universal Trajectory
/// Optimization Framework for Differential Drive Robot Class", IEEE T-ASE 22, 2025), written from
/// its mathematics, with a traversability integral and moving-obstacle clearance added.
///
/// The flat outputs yaw theta(t) and arc length s(t) are one 2-D MinimumJerkPolynomial of N pieces;
/// v = ds/dt (negative: reversing), omega = dtheta/dt. The position is not a variable: x, y are
/// integrated from v (cos theta, sin theta) by composite Simpson's rule over `samples_per_piece`
/// intervals per piece, and the gradient of every position-dependent term flows back through all
/// earlier integration nodes. Constraints are penalties integrated by the trapezoidal rule at the
/// interval ends; the terrain's speed limit (CostField::SpeedLimit, v^2 <= limit(p)^2) and the
/// slope limits (the elevation's gradient along and across the heading within the tangents of
/// the largest pitch and roll, CostField::Elevation) and the steps' square (the heading within
/// StepCrossing::max_angle of a climbable step's normal while the footprint reaches it,
/// CostField::StepWeight) are limits too, soft: a start faster than the limit, on a slope or
/// askew on a step, cannot change at once, so they do not count in the optimiser's feasibility.
///
/// Decision vector z (size 3N): [theta_1..theta_{N-1} | s_1..s_{N-1} | theta_T | s_T |
/// tau_1..tau_N] with inner waypoints of yaw and arc length, the free end yaw and end arc length,
/// and virtual times mapped to durations by GCOPTER's C^2 map T(tau) (always positive). The end
/// rates and accelerations are zero (the trajectory ends at rest).
class TrajectoryCost {
 public:
  /// @throws std::invalid_argument if num_pieces < 1 or samples_per_piece is odd or < 2.
  TrajectoryCost(const CostField& field, TrajectoryCostSetup setup, int num_pieces);

  int num_pieces() const { return num_pieces_; }
  int num_variables() const { return 3 * num_pieces_; }
  const TrajectoryCostSetup& setup() const { return setup_; }

  /// The augmented-Lagrangian parameters of the end-position equality h = p(T) - goal: the term is
  /// rho / 2 ||h + lambda / rho||^2.
  void SetTerminalMultiplier(const Eigen::Vector2d& lambda, double rho);

  /// Cost at z; fills `gradient` (resized) unless null, and `terms` unless null.
  double Evaluate(const Eigen::VectorXd& z, Eigen::VectorXd* gradient, CostTerms* terms = nullptr);

  /// The polynomial at z (after `Evaluate` or `Decode`).
  const MinimumJerkPolynomial& polynomial() const { return polynomial_; }

  /// Sets the polynomial to z without evaluating the cost.
  void Decode(const Eigen::VectorXd& z);

  /// End position reached by the integration at the last Evaluate [m].
  const Eigen::Vector2d& end_position_W() const { return end_W_; }

  /// GCOPTER's map from a virtual time to a duration: 1/2 tau^2 + tau + 1 for tau > 0,
  /// 1 / (1/2 tau^2 - tau + 1) otherwise; C^2, positive and onto (0, inf).
  static double DurationFromVirtual(double tau);
  /// Its inverse.
  static double VirtualFromDuration(double duration_s);
  /// dT/dtau.
  static double DurationGradient(double tau);

 private:
  // The gradient over the variables z from dK/dc and dK/dT, through MINCO and the duration map.
  void ChainToVariables(const Eigen::VectorXd& z, const Eigen::MatrixXd& dK_dc,
                        const Eigen::VectorXd& dK_dT, Eigen::VectorXd* gradient) const;

  const CostField* field_;
  TrajectoryCostSetup setup_;
  int num_pieces_;
  MinimumJerkPolynomial polynomial_;
  Eigen::Vector2d lambda_{Eigen::Vector2d::Zero()};
  double rho_{1.0};
  Eigen::Vector2d end_W_{Eigen::Vector2d::Zero()};
};

/// GCOPTER's smoothed L1 penalty: 0 below 0, x^3/mu^2 - x^4/(2 mu^3) on [0, mu], x - mu/2 above;
/// C^2. Returns the value and sets `slope` to its derivative.
double SmoothedL1(double x, double mu, double* slope);

}  // namespace trav::planner
