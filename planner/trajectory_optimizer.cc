#include "planner/trajectory_optimizer.h"

#include <lbfgs.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "common/input_error.h"
#include "common/polyline.h"
#include "common/stopwatch.h"

namespace trav::planner {
namespace {

using common::RequireValue;

// An initial guess: the decision vector and the number of pieces it describes.
struct Guess {
  int pieces{0};
  Eigen::VectorXd z;
  Eigen::Vector2d lambda{Eigen::Vector2d::Zero()};
};

Eigen::VectorXd Pack(const Eigen::MatrixXd& inner, const Eigen::Vector2d& tail,
                     const Eigen::VectorXd& durations) {
  const int n = static_cast<int>(durations.size());
  Eigen::VectorXd z(3 * n);
  z.segment(0, n - 1) = inner.col(0);
  z.segment(n - 1, n - 1) = inner.col(1);
  z(2 * n - 2) = tail.x();
  z(2 * n - 1) = tail.y();
  for (int i = 0; i < n; ++i) z(2 * n + i) = TrajectoryCost::VirtualFromDuration(durations(i));
  return z;
}

double Unwrapped(double angle, double reference) {
  return reference + std::remainder(angle - reference, 2.0 * M_PI);
}

// The polyline start -> guide -> goal, without repeated points.
common::Polyline GuidePath(const TrajectoryRequest& request) {
  std::vector<Eigen::Vector2d> points = {request.start.position_W};
  for (const Eigen::Vector2d& p : request.guide_W) {
    if ((p - points.back()).norm() > 1e-3) points.push_back(p);
  }
  if ((request.goal_W - points.back()).norm() > 1e-3) points.push_back(request.goal_W);
  return common::Polyline(std::move(points));
}

// Shortest piece a warm start keeps [s].
constexpr double kMinimumDuration_s = 1e-3;

// Turns sharper than this at a guide-path vertex get a piece of their own [rad].
constexpr double kTurnInPlace_rad = 0.3;

// The guide path as yaw and arc length: straight pieces of at most `piece_length_m` along each
// segment with the segment's heading, and a turn in place (arc length constant) before a segment
// whose heading differs by more than kTurnInPlace_rad, so that the integrated position starts on
// the guide path (a cut corner could cross a thin wall, where the distance field has no useful
// gradient). Durations cruise at a fraction of the limits, with acceleration time at both ends.
Guess ColdGuess(const TrajectoryOptimizerConfig& config, const TrajectoryRequest& request) {
  const common::Polyline path = GuidePath(request);
  const std::vector<Eigen::Vector2d>& vertices = path.points();
  const double speed = config.initial_speed_fraction * config.limits.max_speed_m_s;
  const double yaw_rate = config.initial_speed_fraction * config.limits.max_yaw_rate_rad_s;
  std::vector<Eigen::Vector2d> knots;  // (yaw, arc length) at the end of each piece
  std::vector<double> durations;
  double yaw = request.start.yaw;
  double arc = 0.0;
  for (std::size_t j = 1; j < vertices.size(); ++j) {
    const Eigen::Vector2d segment = vertices[j] - vertices[j - 1];
    const double length = segment.norm();
    const double heading = Unwrapped(std::atan2(segment.y(), segment.x()), yaw);
    if (std::abs(heading - yaw) > kTurnInPlace_rad) {
      knots.emplace_back(heading, arc);
      durations.push_back(std::abs(heading - yaw) / yaw_rate);
    }
    yaw = heading;
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / config.piece_length_m)));
    for (int k = 1; k <= pieces; ++k) {
      knots.emplace_back(yaw, arc + length * k / pieces);
      durations.push_back(length / pieces / speed);
    }
    arc += length;
  }
  // at least two pieces (a start at the goal: a short hold)
  while (knots.size() < 2) {
    knots.emplace_back(yaw, arc);
    durations.push_back(0.5);
  }
  const double ramp_s = speed / config.limits.max_acceleration_m_s2;
  durations.front() += ramp_s;
  durations.back() += ramp_s;
  const int n = static_cast<int>(knots.size());
  Eigen::MatrixXd inner(n - 1, 2);
  for (int i = 0; i < n - 1; ++i) inner.row(i) = knots[static_cast<std::size_t>(i)].transpose();
  Guess guess;
  guess.pieces = n;
  guess.z = Pack(inner, knots.back(), Eigen::Map<const Eigen::VectorXd>(durations.data(), n));
  return guess;
}

// The previous plan from the new start time on: its remaining pieces (the current one cut at the
// start time, merged into the next when little of it remains), arc lengths measured from the new
// start, yaw shifted by whole turns to match the robot's.
std::optional<Guess> WarmGuess(const MinimumJerkPolynomial& previous, double elapsed_s,
                               double start_yaw, const Eigen::Vector2d& lambda) {
  const Eigen::VectorXd& durations = previous.durations();
  const int n = previous.num_pieces();
  if (elapsed_s < 0.0 || elapsed_s >= durations.sum()) return std::nullopt;
  int first = 0;
  double local = elapsed_s;
  while (first < n - 1 && local >= durations(first)) local -= durations(first++);
  double head_duration = durations(first) - local;
  if (head_duration < 0.25 * durations(first) && first < n - 1) {
    ++first;
    head_duration += durations(first);
  }
  // arc lengths are measured from the start of the (possibly merged) first piece: after a merge
  // that is the end of the sliver merged away, a little ahead of the robot, so the guess falls a
  // little short and the augmented Lagrangian takes it up. Measuring from the robot's own point
  // did worse in the closed loop (3 of 10 ruin seeds collided, against none), so it stays.
  const Eigen::RowVectorXd now =
      previous.Evaluate(first, std::max(0.0, durations(first) - head_duration), 0);
  // rounding can leave a sliver of the last piece: the polynomial needs positive durations
  head_duration = std::max(head_duration, kMinimumDuration_s);
  const int pieces = n - first;
  Eigen::VectorXd new_durations = durations.tail(pieces);
  new_durations(0) = head_duration;
  const double turns = std::round((start_yaw - now(0)) / (2.0 * M_PI)) * 2.0 * M_PI;
  Eigen::MatrixXd inner(pieces - 1, 2);
  for (int j = 0; j < pieces - 1; ++j) {
    const int piece = first + j;
    const Eigen::RowVectorXd end = previous.Evaluate(piece, durations(piece), 0);
    inner.row(j) << end(0) + turns, end(1) - now(1);
  }
  const Eigen::RowVectorXd tail = previous.Evaluate(n - 1, durations(n - 1), 0);
  Guess guess;
  guess.pieces = pieces;
  guess.z = Pack(inner, Eigen::Vector2d(tail(0) + turns, tail(1) - now(1)), new_durations);
  guess.lambda = lambda;
  return guess;
}

// liblbfgs works on C callbacks; the instance pointer carries the cost. No exception may cross
// them: a step to virtual times whose durations are not finite and positive (overflow of the
// duration map) is answered with the largest value, which makes the line search step back.
struct LbfgsProblem {
  TrajectoryCost* cost;
  Eigen::VectorXd z;
  Eigen::VectorXd gradient;
  int evaluations{0};
  int iterations{0};
};

lbfgsfloatval_t EvaluateCost(void* instance, const lbfgsfloatval_t* x, lbfgsfloatval_t* g, int n,
                             lbfgsfloatval_t /*step*/) {
  auto* problem = static_cast<LbfgsProblem*>(instance);
  ++problem->evaluations;
  problem->z = Eigen::Map<const Eigen::VectorXd>(x, n);
  const int pieces = problem->cost->num_pieces();
  bool valid = problem->z.allFinite();
  for (int i = 0; i < pieces && valid; ++i) {
    const double duration = TrajectoryCost::DurationFromVirtual(problem->z(2 * pieces + i));
    valid = std::isfinite(duration) && duration > 0.0;
  }
  if (!valid) {
    std::fill(g, g + n, 0.0);
    return std::numeric_limits<double>::max();
  }
  const double value = problem->cost->Evaluate(problem->z, &problem->gradient);
  if (!std::isfinite(value) || !problem->gradient.allFinite()) {
    std::fill(g, g + n, 0.0);
    return std::numeric_limits<double>::max();
  }
  std::copy(problem->gradient.data(), problem->gradient.data() + n, g);
  return value;
}

int Progress(void* instance, const lbfgsfloatval_t*, const lbfgsfloatval_t*, lbfgsfloatval_t,
             lbfgsfloatval_t, lbfgsfloatval_t, lbfgsfloatval_t, int, int k, int) {
  static_cast<LbfgsProblem*>(instance)->iterations = k;
  return 0;
}

// Minimises `cost` from z with at most `max_iterations` iterations; returns the iterations used.
int Minimise(const TrajectoryOptimizerConfig& config, TrajectoryCost* cost, int max_iterations,
             Eigen::VectorXd* z, int* evaluations) {
  const int n = static_cast<int>(z->size());
  lbfgs_parameter_t parameters;
  lbfgs_parameter_init(&parameters);
  parameters.m = 16;
  parameters.epsilon = 1e-6;
  parameters.past = 3;
  parameters.delta = config.relative_cost_tolerance;
  parameters.max_iterations = max_iterations;
  parameters.max_linesearch = 40;
  parameters.min_step = 1e-20;
  // backtracking to the (weak) Wolfe conditions, as GCOPTER's Lewis-Overton search: the penalties
  // are C^2 but bilinear map lookups are only C^0 in their gradient, where More-Thuente's
  // interpolation stalls with rounding errors
  parameters.linesearch = LBFGS_LINESEARCH_BACKTRACKING_WOLFE;
  LbfgsProblem problem{cost, *z, Eigen::VectorXd(), 0, 0};
  lbfgsfloatval_t* x = lbfgs_malloc(n);
  std::copy(z->data(), z->data() + n, x);
  lbfgsfloatval_t value = 0.0;
  // every return code leaves x at the best point found (line-search failures revert the last step)
  lbfgs(n, x, &value, EvaluateCost, Progress, &problem, &parameters);
  *z = Eigen::Map<const Eigen::VectorXd>(x, n);
  lbfgs_free(x);
  *evaluations += problem.evaluations;
  return std::max(1, problem.iterations);
}

// Yaw and arc length with derivatives at time t from the polynomial's start.
struct FlatSample {
  Eigen::RowVectorXd value, rate, acceleration;
};

FlatSample SampleAt(const MinimumJerkPolynomial& polynomial, double t) {
  const Eigen::VectorXd& durations = polynomial.durations();
  int piece = 0;
  while (piece < polynomial.num_pieces() - 1 && t > durations(piece)) t -= durations(piece++);
  t = std::clamp(t, 0.0, durations(piece));
  return {polynomial.Evaluate(piece, t, 0), polynomial.Evaluate(piece, t, 1),
          polynomial.Evaluate(piece, t, 2)};
}

Eigen::Vector2d PlanarVelocity(const FlatSample& s) {
  return s.rate(1) * Eigen::Vector2d(std::cos(s.value(0)), std::sin(s.value(0)));
}

// Samples the trajectory (positions by Simpson's rule between samples) and checks it.
OptimizedTrajectory Output(const TrajectoryOptimizerConfig& config, const CostField& field,
                           const TrajectoryRequest& request, double clearance_m,
                           const std::vector<Eigen::Vector2d>& body_points_B,
                           const MinimumJerkPolynomial& polynomial) {
  OptimizedTrajectory out;
  OptimizationDiagnostics& d = out.diagnostics;
  const double duration = polynomial.durations().sum();
  const int steps =
      std::max(1, static_cast<int>(std::ceil(duration / config.output_step_s - 1e-9)));
  std::vector<common::TrajectoryPoint> points;
  points.reserve(static_cast<std::size_t>(steps) + 1);
  Eigen::Vector2d position = request.start.position_W;
  FlatSample previous = SampleAt(polynomial, 0.0);
  double previous_t = 0.0;
  d.min_clearance_m = std::numeric_limits<double>::infinity();
  d.min_obstacle_gap_m = std::numeric_limits<double>::infinity();
  const DynamicLimits& lim = config.limits;
  auto check = [&](double violation, const char* name) {
    if (violation > d.max_violation) {
      d.max_violation = violation;
      d.worst_constraint = name;
    }
  };
  for (int k = 0; k <= steps; ++k) {
    const double t = std::min(duration, k * duration / steps);
    // pieces shrunk below the resolution of the start time (a start at its goal: nothing holds
    // their durations up) give samples of one time stamp, and a trajectory's times increase
    if (k > 0 && !(request.start.t_s + t > points.back().t_s)) continue;
    const FlatSample sample = SampleAt(polynomial, t);
    if (k > 0) {
      const double h = t - previous_t;
      const FlatSample middle = SampleAt(polynomial, t - 0.5 * h);
      position +=
          h / 6.0 *
          (PlanarVelocity(previous) + 4.0 * PlanarVelocity(middle) + PlanarVelocity(sample));
    }
    previous = sample;
    previous_t = t;
    common::TrajectoryPoint p;
    p.t_s = request.start.t_s + t;
    p.position_W = position;
    p.yaw = sample.value(0);
    p.omega = sample.rate(0);
    p.v = sample.rate(1);
    p.acceleration = sample.acceleration(1);
    points.push_back(p);

    check(std::abs(p.v) / lim.max_speed_m_s - 1.0, "speed");
    check(std::abs(p.omega) / lim.max_yaw_rate_rad_s - 1.0, "yaw_rate");
    check(std::abs(p.acceleration) / lim.max_acceleration_m_s2 - 1.0, "acceleration");
    check(std::abs(sample.acceleration(0)) / lim.max_yaw_acceleration_rad_s2 - 1.0,
          "yaw_acceleration");
    check(std::abs(p.v * p.omega) / lim.max_centripetal_acceleration_m_s2 - 1.0,
          "centripetal_acceleration");
    const double distance = FootprintDistance(field, position, p.yaw, body_points_B);
    d.min_clearance_m = std::min(d.min_clearance_m, distance);
    // relative to the configured clearance (or to one cell when none is configured), so that
    // entering a lethal cell is a violation even where the clearance had to shrink
    check((clearance_m - distance) / std::max(config.clearance_m, field.geometry().resolution_m),
          "clearance");
    for (const MovingObstacle& o : request.obstacles) {
      const double gap =
          (position - o.PositionAt(p.t_s)).norm() - config.robot_radius_m - o.radius_m;
      d.min_obstacle_gap_m = std::min(d.min_obstacle_gap_m, gap);
      const double required = config.obstacle_clearance_m + config.clearance_growth_m_s * t;
      const double scale = config.robot_radius_m + o.radius_m + required;
      check((required - gap) / scale, "moving_obstacle");
    }
  }
  d.terminal_error_m = (position - request.goal_W).norm();
  out.trajectory = common::Trajectory(std::move(points));
  return out;
}

// Optimises from `guess`: L-BFGS rounds of the augmented Lagrangian until the end position is at
// the goal, then the output samples and the status. Sets the solution's polynomial and multiplier.
OptimizedTrajectory Solve(const TrajectoryOptimizerConfig& config, const CostField& field,
                          const TrajectoryRequest& request, const TrajectoryCostSetup& setup,
                          const Guess& guess, MinimumJerkPolynomial* polynomial,
                          Eigen::Vector2d* multiplier) {
  TrajectoryCost cost(field, setup, guess.pieces);
  Eigen::VectorXd z = guess.z;
  Eigen::Vector2d lambda = guess.lambda;
  double rho = config.initial_penalty;
  OptimizationDiagnostics solver;
  while (solver.rounds < config.max_rounds && solver.iterations < config.max_iterations) {
    ++solver.rounds;
    cost.SetTerminalMultiplier(lambda, rho);
    solver.iterations +=
        Minimise(config, &cost, config.max_iterations - solver.iterations, &z, &solver.evaluations);
    cost.Evaluate(z, nullptr, &solver.costs);
    const Eigen::Vector2d error = cost.end_position_W() - request.goal_W;
    if (error.norm() <= config.terminal_tolerance_m) break;
    lambda += rho * error;
    rho *= config.penalty_growth;
  }
  cost.Decode(z);

  OptimizedTrajectory out =
      Output(config, field, request, setup.clearance_m, setup.body_points_B, cost.polynomial());
  OptimizationDiagnostics& d = out.diagnostics;
  d.clearance_m = setup.clearance_m;
  d.costs = solver.costs;
  d.iterations = solver.iterations;
  d.evaluations = solver.evaluations;
  d.rounds = solver.rounds;
  d.pieces = guess.pieces;
  if (d.max_violation > config.violation_tolerance ||
      d.terminal_error_m > 10.0 * config.terminal_tolerance_m) {
    out.status = OptimizationStatus::kInfeasible;
  } else if (d.terminal_error_m <= config.terminal_tolerance_m) {
    out.status = OptimizationStatus::kConverged;
  } else {
    out.status = OptimizationStatus::kIterationLimit;
  }
  *polynomial = cost.polynomial();
  *multiplier = lambda;
  return out;
}

}  // namespace

void ValidateTrajectoryOptimizerConfig(const TrajectoryOptimizerConfig& c) {
  const DynamicLimits& l = c.limits;
  RequireValue(l.max_speed_m_s > 0.0 && l.max_speed_m_s <= 3.0, "max_speed", l.max_speed_m_s,
               "must be in (0, 3] (the Scout Mini's top speed)");
  RequireValue(l.max_yaw_rate_rad_s > 0.0, "max_yaw_rate", l.max_yaw_rate_rad_s, "must be > 0");
  RequireValue(l.max_acceleration_m_s2 > 0.0, "max_acceleration", l.max_acceleration_m_s2,
               "must be > 0");
  RequireValue(l.max_yaw_acceleration_rad_s2 > 0.0, "max_yaw_acceleration",
               l.max_yaw_acceleration_rad_s2, "must be > 0");
  RequireValue(l.max_centripetal_acceleration_m_s2 > 0.0, "max_centripetal_acceleration",
               l.max_centripetal_acceleration_m_s2, "must be > 0");
  const TrajectoryCostWeights& w = c.weights;
  for (const auto& [name, value] : {std::pair{"yaw_jerk_weight", w.yaw_jerk},
                                    {"arc_length_jerk_weight", w.arc_length_jerk},
                                    {"time_weight", w.time},
                                    {"traversability_weight", w.traversability},
                                    {"limits_weight", w.limits},
                                    {"clearance_weight", w.clearance},
                                    {"moving_obstacles_weight", w.moving_obstacles}}) {
    RequireValue(value >= 0.0, name, value, "must be >= 0");
  }
  RequireValue(c.clearance_m >= 0.0, "clearance", c.clearance_m, "must be >= 0");
  RequireValue(c.min_clearance_m >= 0.0 && c.min_clearance_m <= c.clearance_m, "min_clearance",
               c.min_clearance_m, "must be in [0, clearance]");
  RequireValue(c.footprint.half_length_m > 0.0 && c.footprint.half_width_m > 0.0, "footprint",
               c.footprint.half_length_m, "must have positive half extents");
  RequireValue(c.robot_radius_m > 0.0, "robot_radius", c.robot_radius_m, "must be > 0");
  RequireValue(c.obstacle_clearance_m >= 0.0, "obstacle_clearance", c.obstacle_clearance_m,
               "must be >= 0");
  RequireValue(c.clearance_growth_m_s >= 0.0, "clearance_growth", c.clearance_growth_m_s,
               "must be >= 0");
  RequireValue(c.piece_length_m > 0.0, "piece_length", c.piece_length_m, "must be > 0");
  RequireValue(
      c.samples_per_piece >= 2 && c.samples_per_piece <= 64 && c.samples_per_piece % 2 == 0,
      "samples_per_piece", c.samples_per_piece, "must be even and in [2, 64]");
  RequireValue(c.initial_speed_fraction > 0.0 && c.initial_speed_fraction <= 1.0,
               "initial_speed_fraction", c.initial_speed_fraction, "must be in (0, 1]");
  RequireValue(c.terminal_tolerance_m > 0.0, "terminal_tolerance", c.terminal_tolerance_m,
               "must be > 0");
  RequireValue(c.violation_tolerance >= 0.0, "violation_tolerance", c.violation_tolerance,
               "must be >= 0");
  RequireValue(c.max_iterations >= 1, "max_iterations", c.max_iterations, "must be >= 1");
  RequireValue(c.max_rounds >= 1, "max_rounds", c.max_rounds, "must be >= 1");
  RequireValue(c.initial_penalty > 0.0, "initial_penalty", c.initial_penalty, "must be > 0");
  RequireValue(c.penalty_growth > 1.0, "penalty_growth", c.penalty_growth, "must be > 1");
  RequireValue(c.relative_cost_tolerance > 0.0, "relative_cost_tolerance",
               c.relative_cost_tolerance, "must be > 0");
  RequireValue(c.output_step_s > 0.0, "output_step", c.output_step_s, "must be > 0");
  RequireValue(c.warm_start_goal_tolerance_m >= 0.0, "warm_start_goal_tolerance",
               c.warm_start_goal_tolerance_m, "must be >= 0");
}

TrajectoryOptimizer::TrajectoryOptimizer(const TrajectoryOptimizerConfig& config)
    : config_(config) {
  ValidateTrajectoryOptimizerConfig(config_);
}

OptimizedTrajectory TrajectoryOptimizer::Optimize(const CostField& field,
                                                  const TrajectoryRequest& request) {
  const common::Stopwatch clock_start;
  TrajectoryCostSetup setup;
  setup.limits = config_.limits;
  setup.weights = config_.weights;
  setup.body_points_B =
      BodyPoints_B(config_.footprint, field.geometry().resolution_m, config_.clearance_m);
  setup.body_reach_m = config_.footprint.CircumscribedRadius();
  // DDR-opt's rule for ends near lethal cells: the clearance shrinks to 85 % of the smaller gap
  // of the start and the goal, so that neither end violates it (the goal's yaw is free: its gap
  // is the inscribed disc's). A start whose footprint overlaps a lethal cell (a face's points
  // spread by the sensor's range noise into the cell beside the robot) has a gap below zero: the
  // clearance is then that gap less 15 % of its size, which the way out keeps; clamped at zero, no
  // way from the start was feasible, and the robot stood until the run ended (`suite/forest` at
  // terrain seed 108). A goal inside lethal cells stays infeasible.
  const double start_m =
      FootprintDistance(field, request.start.position_W, request.start.yaw, setup.body_points_B);
  const double goal_m = field.Distance(request.goal_W).value - config_.footprint.InscribedRadius();
  setup.clearance_m = std::min(
      {config_.clearance_m, std::max(0.85 * goal_m, 0.0), start_m - 0.15 * std::abs(start_m)});
  setup.robot_radius_m = config_.robot_radius_m;
  setup.obstacle_clearance_m = config_.obstacle_clearance_m;
  setup.clearance_growth_m_s = config_.clearance_growth_m_s;
  setup.samples_per_piece = config_.samples_per_piece;
  setup.start_time_s = request.start.t_s;
  setup.start_W = request.start.position_W;
  setup.head << request.start.yaw, 0.0, request.start.omega, request.start.v, 0.0,
      request.start.acceleration;
  setup.goal_W = request.goal_W;
  setup.obstacles = request.obstacles;

  // a warm start keeps the previous plan's way round obstacles; when that way is no longer
  // feasible on the new map, the guide path decides
  std::optional<Guess> warm;
  if (config_.warm_start && previous_ &&
      (previous_->goal_W - request.goal_W).norm() <= config_.warm_start_goal_tolerance_m) {
    warm = WarmGuess(previous_->polynomial, request.start.t_s - previous_->start_time_s,
                     request.start.yaw, previous_->lambda);
  }
  Solution solution{request.start.t_s, request.goal_W, {}, Eigen::Vector2d::Zero()};
  OptimizedTrajectory out;
  int iterations = 0, evaluations = 0;
  if (warm) {
    out = Solve(config_, field, request, setup, *warm, &solution.polynomial, &solution.lambda);
    out.diagnostics.warm_started = true;
    iterations = out.diagnostics.iterations;
    evaluations = out.diagnostics.evaluations;
  }
  auto solve_cold = [&] {
    out = Solve(config_, field, request, setup, ColdGuess(config_, request), &solution.polynomial,
                &solution.lambda);
    out.diagnostics.iterations += iterations;
    out.diagnostics.evaluations += evaluations;
    iterations = out.diagnostics.iterations;
    evaluations = out.diagnostics.evaluations;
  };
  if (!warm || out.status == OptimizationStatus::kInfeasible) solve_cold();
  if (out.status == OptimizationStatus::kInfeasible &&
      setup.clearance_m > config_.min_clearance_m) {
    setup.clearance_m = config_.min_clearance_m;
    solve_cold();
  }
  previous_ = std::move(solution);
  out.diagnostics.solve_time_s = clock_start.ElapsedSeconds();
  return out;
}

}  // namespace trav::planner
