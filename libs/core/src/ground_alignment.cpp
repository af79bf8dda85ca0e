#include "dlo/core/ground_alignment.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "dlo/core/rigid_transform.h"

namespace dlo {

namespace {

constexpr double kHuberDelta = 0.05;  ///< metres: ground cells agree to a few centimetres
constexpr double kMaxResidual = 0.3;  ///< metres: beyond, a car or a bush took the ground's place
/// Metres: the cut of the first iterations, which a guess tilted by a few degrees needs (5 deg
/// put the ground 20 m away 1.7 m off); a car's roof (1.5 m) stays out.
constexpr double kFirstMaxResidual = 1.0;
constexpr int kFirstIterations = 2;
/// m/m: a steeper reference is a kerb, a wall or a car, not the road (grades up to 20 % and
/// more pass).
constexpr double kMaxGroundGradient = 0.35;
constexpr int kMinCells = 30;
constexpr int kIterations = 6;
/// Converged: a step below these (the scan-to-scan noise of levelled poses is about 1 mm and
/// 0.01-0.02 deg).
constexpr double kMinStepHeight = 5e-4;  ///< metres
constexpr double kMinStepTilt = 5e-5;    ///< radians
/// Smallest over largest eigenvalue (rotations at rotation_scale) of a direction still measured.
constexpr double kObservableRatio = 0.02;
/// A correction beyond these is no measurement of the ground (a reference whose ground is
/// hidden, a wrong basin): the guess stands.
constexpr double kMaxHeightChange = 1.0;  ///< metres
constexpr double kMaxTiltChange = 0.1;    ///< radians

/// The reference's height and gradient at (x, y), bilinear between four measured cells.
bool sampleMeasured(const HeightGrid& grid, double x, double y, double& h, double& gx, double& gy) {
  const GridGeometry& g = grid.geometry();
  const double u = g.u(x) - 0.5, v = g.v(y) - 0.5;
  if (!(u >= 0.0 && v >= 0.0 && u < g.cols - 1 && v < g.rows - 1)) return false;
  const int c = static_cast<int>(u), r = static_cast<int>(v);
  if (!grid.isValid(r, c) || !grid.isValid(r, c + 1) || !grid.isValid(r + 1, c) ||
      !grid.isValid(r + 1, c + 1)) {
    return false;
  }
  const double a = u - c, b = v - r;
  const double h00 = grid.height(r, c), h01 = grid.height(r, c + 1);
  const double h10 = grid.height(r + 1, c), h11 = grid.height(r + 1, c + 1);
  h = (1 - b) * ((1 - a) * h00 + a * h01) + b * ((1 - a) * h10 + a * h11);
  gx = ((1 - b) * (h01 - h00) + b * (h11 - h10)) / g.resolution;
  gy = ((1 - a) * (h10 - h00) + a * (h11 - h01)) / g.resolution;
  return true;
}

/// A perturbation (tz, wx, wy) applied about `centre` (reference frame) on the left of T.
Eigen::Isometry3d perturbed(const Eigen::Isometry3d& T, const Eigen::Vector3d& centre,
                            const Eigen::Vector3d& d) {
  Vector6d xi = Vector6d::Zero();
  xi(2) = d(0);
  xi(3) = d(1);
  xi(4) = d(2);
  const Eigen::Translation3d to(centre);
  return to * expSE3(xi) * to.inverse() * T;
}

}  // namespace

size_t groundLevel(const HeightFrame& frame) {
  constexpr double kGroundCell = 0.4;  // metres
  const std::vector<FrameLevel>& levels = frame.levels();
  const auto off = [&](size_t i) {
    return std::abs(std::log(levels[i].grid.resolution() / kGroundCell));
  };
  size_t best = 0;
  for (size_t k = 1; k < levels.size(); ++k) {
    if (off(k) < off(best)) best = k;
  }
  return best;
}

GroundAlignment alignToGround(const HeightGrid& reference, const std::vector<GroundCell>& cells,
                              const Eigen::Isometry3d& guess, double rotation_scale) {
  GroundAlignment out;
  out.pose = guess;
  if (static_cast<int>(cells.size()) < kMinCells || reference.cols() < 2) return out;
  Eigen::Isometry3d T = guess;
  // Tilts turn about the vehicle's position (T's translation, which they then keep): about the
  // reference's origin they would move the vehicle sideways by their lever arm.
  Eigen::Vector3d centre = guess.translation();
  // Scratch kept across calls, used through a plain pointer: a thread_local name in the loop
  // costs a __tls_get_addr call at every cell (see cell_selection.cpp).
  thread_local std::vector<double> residual_scratch;
  residual_scratch.resize(cells.size());
  double* const residuals = residual_scratch.data();
  // The residual of each cell at T, or false where the reference has no ground there.
  const auto residual = [&](const GroundCell& cell, const Eigen::Isometry3d& at, double& e,
                            Eigen::Vector3d& J) {
    const Eigen::Vector3d q = at * Eigen::Vector3d(cell.x, cell.y, cell.h);
    double h, gx, gy;
    if (!sampleMeasured(reference, q.x(), q.y(), h, gx, gy)) return false;
    if (gx * gx + gy * gy > kMaxGroundGradient * kMaxGroundGradient) return false;
    e = h - q.z();
    // de/d(tz, wx, wy) of a left perturbation about `centre`: dq = (wy r_z, -wx r_z,
    // wx r_y - wy r_x + tz) with r = q - centre, and de = gx dq_x + gy dq_y - dq_z.
    const Eigen::Vector3d r = q - centre;
    J << -1.0, -gy * r.z() - r.y(), gx * r.z() + r.x();
    return true;
  };
  // A robust start: the median height error, which a guess a few decimetres off (longer than
  // the kernel) would otherwise leave to the outlier cut.
  double e;
  Eigen::Vector3d J;
  size_t found = 0;
  for (const GroundCell& cell : cells) {
    if (residual(cell, T, e, J)) residuals[found++] = e;
  }
  if (static_cast<int>(found) < kMinCells) return out;
  double* const mid = residuals + found / 2;
  std::nth_element(residuals, mid, residuals + found);
  T.translation().z() += *mid;
  centre = T.translation();

  const Eigen::Vector3d scale(1.0, 1.0 / rotation_scale, 1.0 / rotation_scale);
  Eigen::Matrix3d unobserved = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d information = Eigen::Matrix3d::Zero();  // the last iteration's, scaled
  for (int it = 0; it < kIterations; ++it) {
    Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    double sq = 0.0;
    int n = 0;
    for (const GroundCell& cell : cells) {
      if (!residual(cell, T, e, J)) continue;
      const double ae = std::abs(e);
      if (ae > (it < kFirstIterations ? kFirstMaxResidual : kMaxResidual)) continue;
      const double w = ae <= kHuberDelta ? 1.0 : kHuberDelta / ae;
      for (int i = 0; i < 3; ++i) {
        for (int j = i; j < 3; ++j) H(i, j) += w * J(i) * J(j);
        b(i) += w * e * J(i);
      }
      sq += e * e;
      ++n;
    }
    out.cells = n;
    out.rms = n > 0 ? std::sqrt(sq / n) : 0.0;
    if (n < kMinCells) return GroundAlignment{false, guess, n, out.rms};
    H = H.selfadjointView<Eigen::Upper>();
    // Conditioning with rotations at rotation_scale; the step only along what is measured.
    const Eigen::Matrix3d Hs = scale.asDiagonal() * H * scale.asDiagonal();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(Hs);
    const Eigen::Vector3d lambda = es.eigenvalues();
    const Eigen::Vector3d bs = scale.asDiagonal() * b;
    information = Hs;
    Eigen::Vector3d dy = Eigen::Vector3d::Zero();
    unobserved.setZero();
    for (int i = 0; i < 3; ++i) {
      const auto v = es.eigenvectors().col(i);
      if (lambda(i) > kObservableRatio * lambda(2)) {
        dy -= (v.dot(bs) / lambda(i)) * v;
      } else {
        unobserved += v * v.transpose();
      }
    }
    const Eigen::Vector3d d = scale.asDiagonal() * dy;
    T = perturbed(T, centre, d);
    centre = T.translation();
    if (std::abs(d(0)) < kMinStepHeight && d.tail<2>().norm() < kMinStepTilt) break;
  }
  // What the ground cannot observe returns to the guess.
  const Eigen::AngleAxisd turn(T.linear() * guess.linear().transpose());
  const Eigen::Vector3d w = turn.angle() * turn.axis();
  Eigen::Vector3d moved(T.translation().z() - guess.translation().z(), w.x(), w.y());
  if (unobserved.trace() > 0.5) {
    const Eigen::Vector3d ys = scale.cwiseInverse().asDiagonal() * moved;
    const Eigen::Vector3d kept = scale.asDiagonal() * (ys - unobserved * ys);
    T = perturbed(guess, guess.translation(), kept);
    moved = kept;
  }
  if (std::abs(moved(0)) > kMaxHeightChange || moved.tail<2>().norm() > kMaxTiltChange) {
    return GroundAlignment{false, guess, out.cells, out.rms};
  }
  T.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  // Covariance of (tz, wx, wy) about the vehicle, in the scaled coordinates of the solve: the
  // residual variance over the information along what is observed, 1e6 along the rest; then
  // as a left perturbation about the reference frame's origin: a turn w about the vehicle at c
  // is the turn w about the origin plus the translation c x w.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(information);
  Eigen::Matrix3d cov_scaled = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    const auto v = es.eigenvectors().col(i);
    const bool observed =
        es.eigenvalues()(i) > kObservableRatio * es.eigenvalues()(2) && es.eigenvalues()(i) > 0.0;
    cov_scaled += (observed ? out.rms * out.rms / es.eigenvalues()(i) : 1e6) * v * v.transpose();
  }
  const Eigen::Matrix3d cov = scale.asDiagonal() * cov_scaled * scale.asDiagonal();
  const Eigen::Vector3d c = T.translation();
  Eigen::Matrix<double, 6, 3> M = Eigen::Matrix<double, 6, 3>::Zero();  // (tz, wx, wy) -> xi
  M(0, 2) = -c.z();                                                     // (c x w).x
  M(1, 1) = c.z();                                                      // (c x w).y
  M(2, 0) = 1.0;
  M(2, 1) = -c.y();
  M(2, 2) = c.x();
  M(3, 1) = 1.0;
  M(4, 2) = 1.0;
  out.covariance = M * cov * M.transpose();
  out.pose = T;
  out.aligned = true;
  return out;
}

}  // namespace dlo
