#include "dlo/sim/route.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dlo::sim {

namespace {

/// A piece of the route whose curvature is linear in arc length: a line (0 -> 0), a circular
/// arc (k -> k) or a clothoid (k0 -> k1). The heading is then a quadratic in arc length, which is
/// evaluated exactly; only the position needs numerical integration.
struct Segment {
  double s0 = 0.0, length = 0.0;
  double heading0 = 0.0;
  double curvature0 = 0.0, curvature1 = 0.0;

  double curvatureAt(double u) const {
    return length > 0.0 ? curvature0 + (curvature1 - curvature0) * u / length : curvature0;
  }
  double headingAt(double u) const {
    const double rate = length > 0.0 ? (curvature1 - curvature0) / length : 0.0;
    return heading0 + curvature0 * u + 0.5 * rate * u * u;
  }
  double headingChange() const { return 0.5 * (curvature0 + curvature1) * length; }

  /// Displacement from u0 to u1 (within this segment). Three-point Gauss-Legendre: for the short
  /// steps used here (<= 5 cm at curvatures ~0.1 /m) its error is at rounding level, so the
  /// corner displacement computed once and the table integrated on another grid agree to
  /// rounding and the lap closes.
  Eigen::Vector2d displacement(double u0, double u1) const {
    static constexpr double kNode = 0.7745966692414834;  // sqrt(3 / 5)
    static constexpr double kW[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    const double mid = 0.5 * (u0 + u1), half = 0.5 * (u1 - u0);
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    for (int i = 0; i < 3; ++i) {
      const double h = headingAt(mid + (i - 1) * kNode * half);
      d += kW[i] * Eigen::Vector2d(std::cos(h), std::sin(h));
    }
    return half * d;
  }
};

constexpr double kMaxStep = 0.05;  // Table and integration step [m].

/// Displacement along a whole segment, in steps of at most kMaxStep.
Eigen::Vector2d segmentDisplacement(const Segment& seg) {
  const int steps = std::max(1, static_cast<int>(std::ceil(seg.length / kMaxStep)));
  Eigen::Vector2d d = Eigen::Vector2d::Zero();
  for (int i = 0; i < steps; ++i)
    d += seg.displacement(seg.length * i / steps, seg.length * (i + 1) / steps);
  return d;
}

}  // namespace

Route Route::roundedRectangle(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double radius,
                              double transitionLength, const SpeedLimits& limits) {
  if (!(radius > 0.0 && std::isfinite(radius)))
    throw std::invalid_argument("Route: the corner radius must be positive");
  if (std::isnan(transitionLength))
    throw std::invalid_argument("Route: the transition length is not a number");
  const double R = radius;
  // Each clothoid turns by Lt / (2 R), so two of them turn by Lt / R; the arc makes up the rest
  // of the quarter turn and would need a negative length beyond Lt = R pi / 2.
  const double Lt = std::clamp(transitionLength, 0.0, 0.5 * M_PI * R);
  const double arcLength = 0.5 * M_PI * R - Lt;
  const double k = 1.0 / R;

  std::vector<Segment> segs;
  double heading = 0.0;
  const auto add = [&](double length, double k0, double k1) {
    if (length <= 0.0) return;  // Lt = 0 (circular corners) or Lt = R pi / 2 (no arc).
    Segment g;
    g.length = length;
    g.heading0 = heading;
    g.curvature0 = k0;
    g.curvature1 = k1;
    heading += g.headingChange();
    segs.push_back(g);
  };
  const auto corner = [&](int quarter) {
    add(Lt, 0.0, k);
    add(arcLength, k, k);
    add(Lt, k, 0.0);
    // Exactly a quarter turn per corner, whatever the rounding in the sum above.
    heading = quarter * 0.5 * M_PI;
  };

  // The corner's displacement from its start to its end, in the frame of its entry heading.
  // It is symmetric about the bisector, so it is (D, D): D is where the corner leaves the
  // rectangle's side, measured from the rectangle's vertex (D = R for a circular arc).
  corner(1);
  Eigen::Vector2d dCorner = Eigen::Vector2d::Zero();
  for (const auto& g : segs) dCorner += segmentDisplacement(g);
  const double D = 0.5 * (dCorner.x() + dCorner.y());
  segs.clear();
  heading = 0.0;

  const double halfW = 0.5 * (hi.x() - lo.x()), halfH = 0.5 * (hi.y() - lo.y());
  if (!(D <= halfW && D <= halfH))
    throw std::invalid_argument("Route: the corners do not fit in the rectangle");
  // Straights shortened by D at each vertex so that the route passes through the middle of
  // every side and closes at the start.
  add(halfW - D, 0.0, 0.0);
  corner(1);
  add(2.0 * (halfH - D), 0.0, 0.0);
  corner(2);
  add(2.0 * (halfW - D), 0.0, 0.0);
  corner(3);
  add(2.0 * (halfH - D), 0.0, 0.0);
  corner(4);
  add(halfW - D, 0.0, 0.0);

  Route r;
  for (auto& g : segs) {
    g.s0 = r.length_;
    r.length_ += g.length;
  }

  // Dense table on a uniform grid, so that geometryAt is a constant-time lookup (it runs for
  // every LiDAR firing). Each step is integrated piecewise, split where segments meet, so the
  // kinks in the curvature profile are integrated exactly.
  const int n = static_cast<int>(std::ceil(r.length_ / kMaxStep));
  r.step_ = r.length_ / n;
  r.table_.resize(n + 1);
  Eigen::Vector2d pos(0.5 * (lo.x() + hi.x()), lo.y());
  size_t j = 0;  // Segment holding s.
  double s = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double target = i == n ? r.length_ : i * r.step_;
    while (s < target) {
      while (j + 1 < segs.size() && s >= segs[j].s0 + segs[j].length) ++j;
      const Segment& g = segs[j];
      const double to = j + 1 == segs.size() ? target : std::min(target, g.s0 + g.length);
      pos += g.displacement(s - g.s0, to - g.s0);
      s = to;
    }
    while (j + 1 < segs.size() && s >= segs[j].s0 + segs[j].length) ++j;
    const Segment& g = segs[j];
    const double u = std::clamp(target - g.s0, 0.0, g.length);
    r.table_[i] = {pos, g.headingAt(u), g.curvatureAt(u)};
  }
  r.buildSpeedProfile(limits);
  return r;
}

void Route::geometryAt(double s, Eigen::Vector2d& position, double& heading,
                       double& curvature) const {
  s = std::fmod(s, length_);
  if (s < 0.0) s += length_;
  const int last = static_cast<int>(table_.size()) - 2;
  const int k = std::clamp(static_cast<int>(s / step_), 0, last);
  const double f = std::clamp(s / step_ - k, 0.0, 1.0);
  const Sample& a = table_[k];
  const Sample& b = table_[k + 1];
  // Linear between samples 5 cm apart: the chord is within 0.1 mm of the curve, and the heading
  // (unwrapped in the table) stays consistent with the curvature, so yaw rate = curvature * speed.
  position = (1.0 - f) * a.position + f * b.position;
  heading = (1.0 - f) * a.heading + f * b.heading;
  curvature = (1.0 - f) * a.curvature + f * b.curvature;
}

void Route::buildSpeedProfile(const SpeedLimits& limits) {
  const int n = static_cast<int>(std::ceil(length_ / 0.25));
  ds_ = length_ / n;
  std::vector<double> vmax(n + 1);
  for (int k = 0; k <= n; ++k) {
    Eigen::Vector2d p;
    double h, c;
    // The tightest curvature within one step either side: a turn is slowed for before it.
    double cmax = 0.0;
    for (int d = -1; d <= 1; ++d) {
      geometryAt((k + d) * ds_, p, h, c);
      cmax = std::max(cmax, std::abs(c));
    }
    vmax[k] =
        cmax > 0.0 ? std::min(limits.cruise, std::sqrt(limits.lateralAccel / cmax)) : limits.cruise;
  }
  // Forward (acceleration) and backward (braking) passes; the loop is closed, so go around
  // twice for the limits to propagate across the seam.
  std::vector<double> v = vmax;
  const double a2 = 2.0 * limits.longitudinalAccel * ds_;
  for (int pass = 0; pass < 2; ++pass) {
    for (int k = 1; k <= 2 * n; ++k) {
      const int i = k % n, prev = (k - 1) % n;
      v[i] = std::min(v[i], std::sqrt(v[prev] * v[prev] + a2));
    }
    for (int k = 2 * n - 1; k >= 0; --k) {
      const int i = k % n, next = (k + 1) % n;
      v[i] = std::min(v[i], std::sqrt(v[next] * v[next] + a2));
    }
  }
  v[n] = v[0];
  speeds_ = v;
  times_.assign(n + 1, 0.0);
  for (int k = 0; k < n; ++k) times_[k + 1] = times_[k] + 2.0 * ds_ / (v[k] + v[k + 1]);
}

Route Route::patrol(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double speed,
                    double yawRateDeg, double accel) {
  const auto positive = [](double v) { return v > 0.0 && std::isfinite(v); };
  if (!positive(speed) || !positive(yawRateDeg) || !positive(accel))
    throw std::invalid_argument("Route: patrol speed, yaw rate and acceleration must be positive");
  if (!(hi.x() - lo.x() >= 20.0 && hi.y() > lo.y()))
    throw std::invalid_argument("Route: the patrol's rectangle is too small");
  Route r;
  r.speed_ = speed;
  r.accel_ = accel;
  r.yawRate_ = yawRateDeg * M_PI / 180.0;
  Eigen::Vector2d at(0.5 * (lo.x() + hi.x()), lo.y());
  double heading = 0.0, t = 0.0, s = 0.0;
  // One piece from where the last one ended: a drive of `distance` or a turn of `angle`.
  const auto add = [&](double distance, double angle, double duration) {
    Piece p;
    p.t0 = t;
    p.start = at;
    p.heading = heading;
    p.distance = distance;
    p.turn = angle;
    p.s0 = s;
    p.duration = duration;
    r.pieces_.push_back(p);
    at += distance * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    heading += angle;
    t += duration;
    s += distance;
  };
  const auto drive = [&](double distance) {
    // Trapezoidal speed profile, or triangular when the drive is too short to reach the speed.
    const double ramp = speed * speed / accel;  // both ramps' distance
    add(distance, 0.0,
        distance >= ramp ? distance / speed + speed / accel : 2.0 * std::sqrt(distance / accel));
  };
  const auto turn = [&](double angle) { add(0.0, angle, std::fabs(angle) / r.yawRate_); };
  const double halfW = 0.5 * (hi.x() - lo.x()), height = hi.y() - lo.y();
  drive(10.0);
  turn(M_PI);
  drive(10.0);
  turn(M_PI);
  drive(halfW);
  turn(0.5 * M_PI);
  drive(height);
  turn(0.5 * M_PI);
  drive(2.0 * halfW);
  turn(0.5 * M_PI);
  drive(height);
  turn(0.5 * M_PI);
  drive(halfW);
  r.length_ = s;
  r.times_ = {0.0, t};
  return r;
}

RouteState Route::patrolStateAt(double tau) const {
  size_t k = 0;
  while (k + 1 < pieces_.size() && tau >= pieces_[k + 1].t0) ++k;
  const Piece& p = pieces_[k];
  const double u = std::clamp(tau - p.t0, 0.0, p.duration);
  RouteState st;
  st.heading = p.heading;
  st.position = p.start;
  st.distance = p.s0;
  if (p.turn != 0.0) {
    const double sign = p.turn > 0.0 ? 1.0 : -1.0;
    st.heading = p.heading + sign * yawRate_ * u;
    st.yawRate = u < p.duration ? sign * yawRate_ : 0.0;
    return st;
  }
  // Distance and speed along the trapezoid (or triangle) of the drive.
  const double top = std::min(speed_, std::sqrt(p.distance * accel_));
  const double rampT = top / accel_;
  double d, v;
  if (u < rampT) {
    v = accel_ * u;
    d = 0.5 * accel_ * u * u;
  } else if (u > p.duration - rampT) {
    const double w = p.duration - u;
    v = accel_ * w;
    d = p.distance - 0.5 * accel_ * w * w;
  } else {
    v = top;
    d = 0.5 * top * rampT + top * (u - rampT);
  }
  st.position = p.start + d * Eigen::Vector2d(std::cos(p.heading), std::sin(p.heading));
  st.speed = v;
  st.distance = p.s0 + d;
  return st;
}

void Route::setStops(const StopParams& params, double until) {
  stops_ = StopSchedule(params, until, [this](double tau) { return routeStateAt(tau).speed; });
}

RouteState Route::stateAt(double t) const {
  if (stops_.empty()) return routeStateAt(t);
  double rate;
  RouteState st = routeStateAt(stops_.routeTime(t, rate));
  st.speed *= rate;
  st.yawRate *= rate;
  return st;
}

RouteState Route::routeStateAt(double t) const {
  const double lapT = times_.back();
  const double laps = std::floor(t / lapT);
  const double tau = t - laps * lapT;
  if (!pieces_.empty()) {
    RouteState st = patrolStateAt(tau);
    st.distance += laps * length_;
    return st;
  }
  const int k = static_cast<int>(
      std::clamp<long>(std::upper_bound(times_.begin(), times_.end(), tau) - times_.begin() - 1, 0,
                       static_cast<long>(times_.size()) - 2));
  // Constant acceleration within a step, consistent with how times_ was integrated.
  const double v0 = speeds_[k], v1 = speeds_[k + 1];
  const double a = (v1 * v1 - v0 * v0) / (2.0 * ds_);
  const double dt = tau - times_[k];
  RouteState st;
  st.speed = v0 + a * dt;
  const double s = k * ds_ + v0 * dt + 0.5 * a * dt * dt;
  st.distance = laps * length_ + s;
  double curvature;
  geometryAt(s, st.position, st.heading, curvature);
  st.yawRate = curvature * st.speed;
  return st;
}

}  // namespace dlo::sim
