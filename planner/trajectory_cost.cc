#include "planner/trajectory_cost.h"

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace trav::planner {
namespace {

// Yaw and arc length with their first three derivatives at one time of one piece.
struct FlatState {
  double theta{0.0}, dtheta{0.0}, ddtheta{0.0}, dddtheta{0.0};
  double ds{0.0}, dds{0.0}, ddds{0.0};
};

// Basis rows d^n/dt^n t^k, k = 0..5, for n = 0..3.
struct Bases {
  Eigen::Matrix<double, 1, 6> b0, b1, b2, b3;
  explicit Bases(double t) {
    const double t2 = t * t, t3 = t2 * t, t4 = t3 * t, t5 = t4 * t;
    b0 << 1.0, t, t2, t3, t4, t5;
    b1 << 0.0, 1.0, 2.0 * t, 3.0 * t2, 4.0 * t3, 5.0 * t4;
    b2 << 0.0, 0.0, 2.0, 6.0 * t, 12.0 * t2, 20.0 * t3;
    b3 << 0.0, 0.0, 0.0, 6.0, 24.0 * t, 60.0 * t2;
  }
};

FlatState StateAt(const Eigen::Matrix<double, 6, 2>& c, const Bases& b) {
  FlatState s;
  s.theta = b.b0.dot(c.col(0));
  s.dtheta = b.b1.dot(c.col(0));
  s.ddtheta = b.b2.dot(c.col(0));
  s.dddtheta = b.b3.dot(c.col(0));
  s.ds = b.b1.dot(c.col(1));
  s.dds = b.b2.dot(c.col(1));
  s.ddds = b.b3.dot(c.col(1));
  return s;
}

// Planar velocity v (cos theta, sin theta).
Eigen::Vector2d Velocity(const FlatState& s) {
  return s.ds * Eigen::Vector2d(std::cos(s.theta), std::sin(s.theta));
}

// Partial derivatives of a penalty integrand with respect to what it depends on.
struct Partials {
  double theta{0.0}, dtheta{0.0}, ddtheta{0.0}, ds{0.0}, dds{0.0};
  Eigen::Vector2d position{Eigen::Vector2d::Zero()};
  double time{0.0};
};

// The dynamic-limit penalty at one node (speed, yaw rate, accelerations, centripetal
// acceleration), times `weight`, with its partials added to `p`.
double LimitsPenalty(const FlatState& state, const DynamicLimits& lim, double weight, double mu,
                     Partials* partials) {
  Partials& p = *partials;
  double slope = 0.0;
  const double v = state.ds, omega = state.dtheta;
  double limits = 0.0;
  limits += SmoothedL1(v * v - lim.max_speed_m_s * lim.max_speed_m_s, mu, &slope);
  p.ds += slope * 2.0 * v;
  limits += SmoothedL1(omega * omega - lim.max_yaw_rate_rad_s * lim.max_yaw_rate_rad_s, mu, &slope);
  p.dtheta += slope * 2.0 * omega;
  limits += SmoothedL1(
      state.dds * state.dds - lim.max_acceleration_m_s2 * lim.max_acceleration_m_s2, mu, &slope);
  p.dds += slope * 2.0 * state.dds;
  limits += SmoothedL1(state.ddtheta * state.ddtheta -
                           lim.max_yaw_acceleration_rad_s2 * lim.max_yaw_acceleration_rad_s2,
                       mu, &slope);
  p.ddtheta += slope * 2.0 * state.ddtheta;
  const double a_c = lim.max_centripetal_acceleration_m_s2;
  limits += SmoothedL1(omega * omega * v * v - a_c * a_c, mu, &slope);
  p.dtheta += slope * 2.0 * omega * v * v;
  p.ds += slope * 2.0 * v * omega * omega;
  limits *= weight;
  p.ds *= weight;
  p.dtheta *= weight;
  p.dds *= weight;
  p.ddtheta *= weight;
  return limits;
}

// The penalties read from the map's fields at one node, with their partials added to `p`.
struct FieldTerms {
  double clearance;       // the distance to lethal cells below the clearance
  double traversability;  // the cost integrated over the distance driven
  double speed;           // the speed above the terrain's limit (a limits term)
  double tilt;            // pitch and roll beyond the slope limits (a limits term)
  double step;            // the heading beyond the steps' square (a limits term)
};

// The pitch and roll penalty at one node: the ground's slope (its tangent g, the gradient of
// CostField::Elevation, which near lethal cells is the surrounding ground's) along the heading h
// and across it n within the limits' tangents, with its partials added to `p`.
double TiltPenalty(const CostField& field, const Eigen::Vector2d& position, double cos_t,
                   double sin_t, double weight, double mu, Partials* partials) {
  const FieldSample ground = field.Elevation(position);
  const Eigen::Vector2d& limit = field.max_pitch_roll_tangents();
  // no heading can exceed a limit where the whole slope is within both (most nodes)
  if (!std::isfinite(ground.value) ||
      ground.gradient_W.squaredNorm() <= limit.cwiseAbs2().minCoeff())
    return 0.0;
  const Eigen::Vector2d h(cos_t, sin_t), n(-sin_t, cos_t);
  const Eigen::Vector2d& g = ground.gradient_W;
  const double pitch = g.dot(h), roll = g.dot(n);
  double slope_pitch = 0.0, slope_roll = 0.0;
  const double tilt = SmoothedL1(pitch * pitch - limit.x() * limit.x(), mu, &slope_pitch) +
                      SmoothedL1(roll * roll - limit.y() * limit.y(), mu, &slope_roll);
  // dg/dp is the bilinear field's Hessian [[0, c], [c, 0]]; dh/dtheta = n, dn/dtheta = -h
  const double c = ground.cross_derivative;
  partials->position += weight * 2.0 * c *
                        (slope_pitch * pitch * Eigen::Vector2d(h.y(), h.x()) +
                         slope_roll * roll * Eigen::Vector2d(n.y(), n.x()));
  partials->theta += weight * 2.0 * pitch * roll * (slope_pitch - slope_roll);
  return weight * tilt;
}

// The step-crossing penalty at one node: with the weight w of the steps the footprint reaches and
// their normal phi (CostField::StepWeight, StepAxis, the axis a = w (cos 2 phi, sin 2 phi)), the
// heading theta's excess over the largest angle alpha from square,
// e = (w cos 2 alpha - (cos 2 theta, sin 2 theta) . a) / 2 = w (cos 2 alpha - cos 2 (theta - phi))
// / 2, positive beyond alpha either way; its partials added to `partials`.
double StepPenalty(const CostField& field, const Eigen::Vector2d& position, double theta,
                   double weight, double mu, Partials* partials) {
  if (!field.HasSteps()) return 0.0;
  const FieldSample w = field.StepWeight(position);
  // the weights are never negative: 0 here means that every cell round the position is 0
  if (!(w.value > 0.0)) return 0.0;
  const auto [ax, ay] = field.StepAxis(position);
  const double c2 = std::cos(2.0 * theta), s2 = std::sin(2.0 * theta);
  const double limit = field.step_cos_twice_max_angle();
  const double excess = 0.5 * (w.value * limit - (c2 * ax.value + s2 * ay.value));
  double slope = 0.0;
  const double penalty = SmoothedL1(excess, mu, &slope);
  if (slope == 0.0) return weight * penalty;
  partials->theta += weight * slope * (s2 * ax.value - c2 * ay.value);
  partials->position +=
      weight * slope * 0.5 * (limit * w.gradient_W - c2 * ax.gradient_W - s2 * ay.gradient_W);
  return weight * penalty;
}

FieldTerms FieldPenalties(const CostField& field, const TrajectoryCostSetup& s,
                          const Eigen::Vector2d& position, double theta, double v,
                          Partials* partials) {
  Partials& p = *partials;
  const TrajectoryCostWeights& w = s.weights;
  const double mu = s.smoothing;
  double slope = 0.0;
  // every point of the body's boundary keeps the clearance: q = position + R(theta) b
  const double cos_t = std::cos(theta), sin_t = std::sin(theta);
  double clearance = 0.0;
  const bool all_clear =
      s.body_reach_m > 0.0 &&
      field.Distance(position).value - std::sqrt(2.0) * s.body_reach_m >= s.clearance_m;
  for (std::size_t k = 0; !all_clear && k < s.body_points_B.size(); ++k) {
    const Eigen::Vector2d& b = s.body_points_B[k];
    const Eigen::Vector2d rotated(cos_t * b.x() - sin_t * b.y(), sin_t * b.x() + cos_t * b.y());
    const FieldSample distance = field.Distance(position + rotated);
    if (distance.value >= s.clearance_m) continue;  // SmoothedL1 and its slope are 0 here
    clearance += w.clearance * SmoothedL1(s.clearance_m - distance.value, mu, &slope);
    p.position -= w.clearance * slope * distance.gradient_W;
    // d rotated / d theta = (-rotated.y, rotated.x)
    p.theta -= w.clearance * slope *
               (distance.gradient_W.y() * rotated.x() - distance.gradient_W.x() * rotated.y());
  }

  // int c |v| dt with |v| smoothed as sqrt(v^2 + e^2) - e
  constexpr double kSpeedSmoothing = 0.05;
  const FieldSample cost = field.Cost(position);
  const double speed = std::sqrt(v * v + kSpeedSmoothing * kSpeedSmoothing);
  const double traversability = w.traversability * cost.value * (speed - kSpeedSmoothing);
  p.position += w.traversability * (speed - kSpeedSmoothing) * cost.gradient_W;
  p.ds += w.traversability * cost.value * v / speed;

  // v^2 <= limit(position)^2 where the terrain limits the speed below the open speed
  double over_limit = 0.0;
  const FieldSample limit = field.SpeedLimit(position);
  if (limit.value < field.open_speed_m_s()) {
    over_limit = w.limits * SmoothedL1(v * v - limit.value * limit.value, mu, &slope);
    p.ds += w.limits * slope * 2.0 * v;
    p.position -= w.limits * slope * 2.0 * limit.value * limit.gradient_W;
  }
  const double tilt = TiltPenalty(field, position, cos_t, sin_t, w.limits, mu, partials);
  const double step = StepPenalty(field, position, theta, w.limits, mu, partials);
  return {clearance, traversability, over_limit, tilt, step};
}

// The moving-obstacle penalty at one node (position_W at absolute time t_abs), with its partials
// added to `p`: a gap that grows with the time ahead of the start must stay clear of each
// obstacle's prediction.
double ObstaclesPenalty(const TrajectoryCostSetup& s, const Eigen::Vector2d& position, double t_abs,
                        Partials* partials) {
  Partials& p = *partials;
  const double w = s.weights.moving_obstacles;
  const double mu = s.smoothing;
  double slope = 0.0;
  double obstacles = 0.0;
  for (const MovingObstacle& o : s.obstacles) {
    const double ahead = t_abs - s.start_time_s;
    const double gap =
        s.robot_radius_m + o.radius_m + s.obstacle_clearance_m + s.clearance_growth_m_s * ahead;
    const Eigen::Vector2d r = position - o.PositionAt(t_abs);
    const double violation = gap * gap - r.squaredNorm();
    if (violation <= 0.0) continue;
    obstacles += w * SmoothedL1(violation, mu, &slope);
    p.position -= w * slope * 2.0 * r;
    p.time += w * slope * (2.0 * gap * s.clearance_growth_m_s + 2.0 * r.dot(o.velocity_W));
  }
  return obstacles;
}

// The backward pass through the integration of the position and the nodes' absolute times: adds
// to dK/dc and dK/dT what the penalties' position and time partials at the nodes contribute.
void AddIntegrationGradient(const Eigen::VectorXd& durations, const Eigen::MatrixXd& coefficients,
                            int k_max, const std::vector<Eigen::Vector2d>& node_position_gradient,
                            const std::vector<double>& node_time_gradient,
                            const std::vector<Eigen::Vector2d>& step_increment,
                            Eigen::MatrixXd* dK_dc_out, Eigen::VectorXd* dK_dT_out) {
  Eigen::MatrixXd& dK_dc = *dK_dc_out;
  Eigen::VectorXd& dK_dT = *dK_dT_out;
  const auto n = static_cast<int>(durations.size());
  const int nodes_per_piece = k_max + 1;
  // backward pass through the integration: `adjoint` sums dK/dp over every node after the step
  Eigen::Vector2d adjoint = Eigen::Vector2d::Zero();
  for (int i = n - 1; i >= 0; --i) {
    const double duration = durations(i);
    const double h = duration / k_max;
    const Eigen::Matrix<double, 6, 2> c = coefficients.middleRows<6>(6 * i);
    for (int k = k_max; k >= 1; --k) {
      adjoint += node_position_gradient[i * nodes_per_piece + k];
      // Simpson step from node k - 1 to k: h/6 (f(t_a) + 4 f(t_m) + f(t_b))
      const double times[3] = {(k - 1) * h, (k - 0.5) * h, k * h};
      const double factors[3] = {h / 6.0, 4.0 * h / 6.0, h / 6.0};
      for (int e = 0; e < 3; ++e) {
        const Bases bases(times[e]);
        const FlatState state = StateAt(c, bases);
        const double cos_t = std::cos(state.theta), sin_t = std::sin(state.theta);
        const double by_speed = adjoint.x() * cos_t + adjoint.y() * sin_t;
        const double by_yaw = state.ds * (-adjoint.x() * sin_t + adjoint.y() * cos_t);
        dK_dc.block<6, 1>(6 * i, 0) += factors[e] * by_yaw * bases.b0.transpose();
        dK_dc.block<6, 1>(6 * i, 1) += factors[e] * by_speed * bases.b1.transpose();
        dK_dT(i) +=
            factors[e] * (by_yaw * state.dtheta + by_speed * state.dds) * (times[e] / duration);
      }
      dK_dT(i) += adjoint.dot(step_increment[i * k_max + k - 1]) / duration;
    }
    adjoint += node_position_gradient[i * nodes_per_piece];
  }
  // absolute node times: t = start + sum_{l < i} T_l + k/K T_i
  double later = 0.0;
  for (int i = n - 1; i >= 0; --i) {
    double own = 0.0, total = 0.0;
    for (int k = 0; k <= k_max; ++k) {
      const double g = node_time_gradient[i * nodes_per_piece + k];
      own += g * static_cast<double>(k) / k_max;
      total += g;
    }
    dK_dT(i) += later + own;
    later += total;
  }
}

// What the forward pass records for the backward pass through the integration: dK/dp and dK/dt
// at each node (times its trapezoidal weight) and each Simpson step's position increment.
struct IntegrationTape {
  IntegrationTape(int n, int k_max)
      : node_position_gradient(n * (k_max + 1), Eigen::Vector2d::Zero()),
        node_time_gradient(n * (k_max + 1), 0.0),
        step_increment(n * k_max) {}

  std::vector<Eigen::Vector2d> node_position_gradient;
  std::vector<double> node_time_gradient;
  std::vector<Eigen::Vector2d> step_increment;
};

// The penalty integrand's terms at one node (position_W at absolute time t_abs), with their
// partials added to `partials`.
CostTerms NodePenalties(const CostField& field, const TrajectoryCostSetup& s,
                        const FlatState& state, const Eigen::Vector2d& position, double t_abs,
                        Partials* partials) {
  CostTerms g;
  g.limits = LimitsPenalty(state, s.limits, s.weights.limits, s.smoothing, partials);
  const FieldTerms field_terms =
      FieldPenalties(field, s, position, state.theta, state.ds, partials);
  g.limits += field_terms.speed + field_terms.tilt + field_terms.step;
  g.clearance = field_terms.clearance;
  g.traversability = field_terms.traversability;
  g.moving_obstacles = ObstaclesPenalty(s, position, t_abs, partials);
  return g;
}

// The forward pass: integrates the position from the start and the penalties at the interval ends
// into `terms`, adds their partials over c and T to dK/dc and dK/dT, and fills `tape`. Returns the
// end position [m].
Eigen::Vector2d IntegratePenalties(const CostField& field, const TrajectoryCostSetup& s,
                                   const Eigen::VectorXd& durations,
                                   const Eigen::MatrixXd& coefficients, CostTerms* terms,
                                   Eigen::MatrixXd* dK_dc_out, Eigen::VectorXd* dK_dT_out,
                                   IntegrationTape* tape) {
  CostTerms& local = *terms;
  Eigen::MatrixXd& dK_dc = *dK_dc_out;
  Eigen::VectorXd& dK_dT = *dK_dT_out;
  const auto n = static_cast<int>(durations.size());
  const int k_max = s.samples_per_piece;
  const int nodes_per_piece = k_max + 1;
  Eigen::Vector2d position = s.start_W;
  double piece_start_s = s.start_time_s;
  for (int i = 0; i < n; ++i) {
    const double duration = durations(i);
    const double h = duration / k_max;
    const Eigen::Matrix<double, 6, 2> c = coefficients.middleRows<6>(6 * i);
    FlatState previous;
    for (int k = 0; k <= k_max; ++k) {
      const double t = k * h;
      const Bases bases(t);
      const FlatState state = StateAt(c, bases);
      if (k > 0) {
        const FlatState middle = StateAt(c, Bases(t - 0.5 * h));
        const Eigen::Vector2d increment =
            h / 6.0 * (Velocity(previous) + 4.0 * Velocity(middle) + Velocity(state));
        tape->step_increment[i * k_max + k - 1] = increment;
        position += increment;
      }
      previous = state;

      // penalty integrand g and its partial derivatives
      Partials p;
      const CostTerms node = NodePenalties(field, s, state, position, piece_start_s + t, &p);

      // trapezoidal weight of the node: the integral is sum weight * g
      const double weight = (k == 0 || k == k_max ? 0.5 : 1.0) * h;
      const double g = node.limits + node.clearance + node.traversability + node.moving_obstacles;
      local.limits += weight * node.limits;
      local.clearance += weight * node.clearance;
      local.traversability += weight * node.traversability;
      local.moving_obstacles += weight * node.moving_obstacles;
      dK_dc.block<6, 1>(6 * i, 0) +=
          weight * (p.theta * bases.b0 + p.dtheta * bases.b1 + p.ddtheta * bases.b2).transpose();
      dK_dc.block<6, 1>(6 * i, 1) += weight * (p.ds * bases.b1 + p.dds * bases.b2).transpose();
      // the node's time k/K T_i and its weight (T_i / K) move with T_i
      const double fraction = static_cast<double>(k) / k_max;
      dK_dT(i) += weight * fraction *
                      (p.theta * state.dtheta + p.dtheta * state.ddtheta +
                       p.ddtheta * state.dddtheta + p.ds * state.dds + p.dds * state.ddds) +
                  weight / duration * g;
      tape->node_position_gradient[i * nodes_per_piece + k] = weight * p.position;
      tape->node_time_gradient[i * nodes_per_piece + k] = weight * p.time;
    }
    piece_start_s += duration;
  }
  return position;
}

}  // namespace

double SmoothedL1(double x, double mu, double* slope) {
  if (x <= 0.0) {
    *slope = 0.0;
    return 0.0;
  }
  if (x >= mu) {
    *slope = 1.0;
    return x - 0.5 * mu;
  }
  const double r = x / mu;
  *slope = r * r * (3.0 - 2.0 * r);
  return x * r * r * (1.0 - 0.5 * r);
}

double TrajectoryCost::DurationFromVirtual(double tau) {
  return tau > 0.0 ? (0.5 * tau + 1.0) * tau + 1.0 : 1.0 / ((0.5 * tau - 1.0) * tau + 1.0);
}

double TrajectoryCost::VirtualFromDuration(double duration_s) {
  return duration_s > 1.0 ? std::sqrt(2.0 * duration_s - 1.0) - 1.0
                          : 1.0 - std::sqrt(2.0 / duration_s - 1.0);
}

double TrajectoryCost::DurationGradient(double tau) {
  if (tau > 0.0) return tau + 1.0;
  const double den = (0.5 * tau - 1.0) * tau + 1.0;
  return (1.0 - tau) / (den * den);
}

TrajectoryCost::TrajectoryCost(const CostField& field, TrajectoryCostSetup setup, int num_pieces)
    : field_(&field), setup_(std::move(setup)), num_pieces_(num_pieces) {
  if (num_pieces < 1) {
    throw std::invalid_argument("TrajectoryCost: num_pieces must be >= 1, got " +
                                std::to_string(num_pieces));
  }
  if (setup_.samples_per_piece < 2 || setup_.samples_per_piece % 2 != 0) {
    throw std::invalid_argument("TrajectoryCost: samples_per_piece must be even and >= 2, got " +
                                std::to_string(setup_.samples_per_piece));
  }
  polynomial_.SetBoundary(setup_.head, Eigen::MatrixXd::Zero(3, 2), num_pieces);
}

void TrajectoryCost::SetTerminalMultiplier(const Eigen::Vector2d& lambda, double rho) {
  lambda_ = lambda;
  rho_ = rho;
}

void TrajectoryCost::Decode(const Eigen::VectorXd& z) {
  const int n = num_pieces_;
  if (z.size() != num_variables()) {
    throw std::invalid_argument("TrajectoryCost: expected " + std::to_string(num_variables()) +
                                " variables, got " + std::to_string(z.size()));
  }
  Eigen::MatrixXd inner(n - 1, 2);
  inner.col(0) = z.segment(0, n - 1);
  inner.col(1) = z.segment(n - 1, n - 1);
  Eigen::MatrixXd tail = Eigen::MatrixXd::Zero(3, 2);
  tail(0, 0) = z(2 * n - 2);
  tail(0, 1) = z(2 * n - 1);
  Eigen::VectorXd durations(n);
  for (int i = 0; i < n; ++i) durations(i) = DurationFromVirtual(z(2 * n + i));
  polynomial_.SetTail(tail);
  polynomial_.SetParameters(inner, durations);
}

double TrajectoryCost::Evaluate(const Eigen::VectorXd& z, Eigen::VectorXd* gradient,
                                CostTerms* terms) {
  Decode(z);
  const int n = num_pieces_;
  const int k_max = setup_.samples_per_piece;
  const TrajectoryCostSetup& s = setup_;
  const TrajectoryCostWeights& w = s.weights;
  const Eigen::VectorXd& durations = polynomial_.durations();
  const Eigen::MatrixXd& coefficients = polynomial_.coefficients();
  const Eigen::Vector2d energy_weights(w.yaw_jerk, w.arc_length_jerk);

  CostTerms local;
  Eigen::MatrixXd dK_dc = Eigen::MatrixXd::Zero(6 * n, 2);
  Eigen::VectorXd dK_dT = Eigen::VectorXd::Zero(n);
  local.energy = polynomial_.Energy(energy_weights);
  polynomial_.AddEnergyGradient(energy_weights, &dK_dc, &dK_dT);
  local.time = w.time * durations.sum();
  dK_dT.array() += w.time;

  // forward pass: integrate the position and evaluate the penalties at the interval ends
  IntegrationTape tape(n, k_max);
  end_W_ = IntegratePenalties(*field_, s, durations, coefficients, &local, &dK_dc, &dK_dT, &tape);

  // the end position by augmented Lagrangian
  const Eigen::Vector2d shifted = end_W_ - s.goal_W + lambda_ / rho_;
  local.terminal = 0.5 * rho_ * shifted.squaredNorm();
  tape.node_position_gradient.back() += rho_ * shifted;

  if (gradient != nullptr) {
    AddIntegrationGradient(durations, coefficients, k_max, tape.node_position_gradient,
                           tape.node_time_gradient, tape.step_increment, &dK_dc, &dK_dT);
    ChainToVariables(z, dK_dc, dK_dT, gradient);
  }
  if (terms != nullptr) *terms = local;
  return local.Total();
}

void TrajectoryCost::ChainToVariables(const Eigen::VectorXd& z, const Eigen::MatrixXd& dK_dc,
                                      const Eigen::VectorXd& dK_dT,
                                      Eigen::VectorXd* gradient) const {
  const int n = num_pieces_;
  Eigen::MatrixXd dK_dq, dK_dtail;
  Eigen::VectorXd dK_dT_total;
  polynomial_.PropagateGradient(dK_dc, dK_dT, &dK_dq, &dK_dT_total, nullptr, &dK_dtail);
  gradient->resize(num_variables());
  gradient->segment(0, n - 1) = dK_dq.col(0);
  gradient->segment(n - 1, n - 1) = dK_dq.col(1);
  (*gradient)(2 * n - 2) = dK_dtail(0, 0);
  (*gradient)(2 * n - 1) = dK_dtail(0, 1);
  for (int i = 0; i < n; ++i) {
    (*gradient)(2 * n + i) = dK_dT_total(i) * DurationGradient(z(2 * n + i));
  }
}

}  // namespace trav::planner
