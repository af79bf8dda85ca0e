#include "dlo/sim/route.h"

#include <algorithm>
#include <cmath>

namespace dlo::sim {

Route Route::roundedRectangle(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi, double radius,
                              const SpeedLimits& limits) {
  Route r;
  const double R = radius;
  const double cx = 0.5 * (lo.x() + hi.x());
  const auto line = [&](Eigen::Vector2d a, Eigen::Vector2d b) {
    Piece p;
    p.start = a;
    p.heading0 = std::atan2(b.y() - a.y(), b.x() - a.x());
    p.length = (b - a).norm();
    r.pieces_.push_back(p);
  };
  const auto arc = [&](Eigen::Vector2d centre, double heading0) {
    Piece p;
    p.start = centre;
    p.heading0 = heading0;
    p.curvature = 1.0 / R;
    p.length = 0.5 * M_PI * R;
    r.pieces_.push_back(p);
  };
  line({cx, lo.y()}, {hi.x() - R, lo.y()});
  arc({hi.x() - R, lo.y() + R}, 0.0);
  line({hi.x(), lo.y() + R}, {hi.x(), hi.y() - R});
  arc({hi.x() - R, hi.y() - R}, 0.5 * M_PI);
  line({hi.x() - R, hi.y()}, {lo.x() + R, hi.y()});
  arc({lo.x() + R, hi.y() - R}, M_PI);
  line({lo.x(), hi.y() - R}, {lo.x(), lo.y() + R});
  arc({lo.x() + R, lo.y() + R}, 1.5 * M_PI);
  line({lo.x() + R, lo.y()}, {cx, lo.y()});
  for (auto& p : r.pieces_) {
    p.s0 = r.length_;
    r.length_ += p.length;
  }
  r.buildSpeedProfile(limits);
  return r;
}

void Route::geometryAt(double s, Eigen::Vector2d& position, double& heading,
                       double& curvature) const {
  s = std::fmod(s, length_);
  if (s < 0.0) s += length_;
  const Piece* piece = &pieces_.back();
  for (const auto& p : pieces_) {
    if (s < p.s0 + p.length) {
      piece = &p;
      break;
    }
  }
  const double u = s - piece->s0;
  curvature = piece->curvature;
  if (piece->curvature == 0.0) {
    heading = piece->heading0;
    position = piece->start + u * Eigen::Vector2d(std::cos(heading), std::sin(heading));
  } else {
    const double R = 1.0 / piece->curvature;
    heading = piece->heading0 + u / R;
    // Left turn: the centre is to the left of the heading.
    position = piece->start + R * Eigen::Vector2d(std::sin(heading), -std::cos(heading));
  }
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

RouteState Route::stateAt(double t) const {
  const double lapT = times_.back();
  const double laps = std::floor(t / lapT);
  const double tau = t - laps * lapT;
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
