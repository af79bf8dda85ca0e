#include "dlo/core/direct_aligner.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace dlo {

namespace {

/// Variance given to directions the registration could not observe.
constexpr double kUnobservedVariance = 1e6;

/// Indices of the estimated twist components in (tx, ty, tz, wx, wy, wz).
constexpr int kIndex3[3] = {0, 1, 5};

/// Normal equations of one Gauss-Newton iteration over N parameters.
template <int N>
struct NormalEquations {
  Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();
  Eigen::Matrix<double, N, 1> b = Eigen::Matrix<double, N, 1>::Zero();
  double weighted_sq = 0.0;  ///< sum of w e^2
  double sq = 0.0;           ///< sum of e^2
  int n = 0;                 ///< residuals used
};

/// Linearises the height difference error e = H_ref(q_xy) - q_z, q = T p, for every selected
/// cell. Jacobian of a left perturbation T <- exp(xi) T:
///   de/dxi = [gx, gy, -1] [I | -[q]x]
///          = [gx, gy, -1, -gy qz - qy, gx qz + qx, -gx qy + gy qx].
/// The 3-DoF case keeps the (tx, ty, wz) columns.
template <int N>
NormalEquations<N> linearise(const HeightSampler& sampler, const std::vector<SelectedCell>& cells,
                             const Eigen::Isometry3d& T, double huber_delta,
                             double max_residual) {
  // Accumulate per cell in float (cheap), in blocks, then in double for precision.
  NormalEquations<N> eq;
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  const float delta = static_cast<float>(huber_delta);
  const float max_e = static_cast<float>(max_residual);
  Eigen::Matrix<float, N, N> Hf = Eigen::Matrix<float, N, N>::Zero();
  Eigen::Matrix<float, N, 1> bf = Eigen::Matrix<float, N, 1>::Zero();
  int in_block = 0;
  HeightSample s;
  for (const SelectedCell& c : cells) {
    const Eigen::Vector3f q = R * Eigen::Vector3f(c.x, c.y, c.h) + t;
    if (!sampler.sample(q.x(), q.y(), s)) continue;
    const float e = s.h - q.z();
    const float ae = std::fabs(e);
    if (ae > max_e) continue;
    const float w = ae <= delta ? 1.0f : delta / ae;  // Huber
    Eigen::Matrix<float, N, 1> J;
    if constexpr (N == 6) {
      J << s.gx, s.gy, -1.0f, -s.gy * q.z() - q.y(), s.gx * q.z() + q.x(),
          -s.gx * q.y() + s.gy * q.x();
    } else {
      J << s.gx, s.gy, -s.gx * q.y() + s.gy * q.x();
    }
    Hf.template selfadjointView<Eigen::Upper>().rankUpdate(J, w);
    bf.noalias() += (w * e) * J;
    eq.weighted_sq += static_cast<double>(w * e * e);
    eq.sq += static_cast<double>(e * e);
    ++eq.n;
    if (++in_block == 256) {
      eq.H += Hf.template cast<double>();
      eq.b += bf.template cast<double>();
      Hf.setZero();
      bf.setZero();
      in_block = 0;
    }
  }
  eq.H += Hf.template cast<double>();
  eq.b += bf.template cast<double>();
  eq.H = eq.H.template selfadjointView<Eigen::Upper>();
  return eq;
}

/// Solution of the normal equations restricted to the well-conditioned directions.
template <int N>
struct ConditionedSolve {
  Eigen::Matrix<double, N, 1> step = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, N, N> covariance = Eigen::Matrix<double, N, N>::Zero();
  bool degenerate = false;
};

/// Solves H dx = -b in a basis where rotations are scaled to metres (times rotation_scale), so
/// that eigenvalues of translations and rotations are comparable. Directions whose eigenvalue is
/// below degeneracy_eigen_ratio * max get no update (the motion prior is kept there) and a huge
/// variance, instead of a confident wrong answer.
template <int N>
ConditionedSolve<N> solveConditioned(const NormalEquations<N>& eq, const SolverParams& p,
                                     int dof_rot_first) {
  ConditionedSolve<N> out;
  Eigen::Matrix<double, N, 1> s = Eigen::Matrix<double, N, 1>::Ones();
  for (int i = dof_rot_first; i < N; ++i) s(i) = 1.0 / p.rotation_scale;
  const Eigen::Matrix<double, N, N> Hs = s.asDiagonal() * eq.H * s.asDiagonal();
  const Eigen::Matrix<double, N, 1> bs = s.asDiagonal() * eq.b;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> es(Hs);
  const auto& lambda = es.eigenvalues();  // ascending
  const auto& V = es.eigenvectors();
  const double lmax = lambda(N - 1);
  const double sigma2 = eq.n > N ? eq.weighted_sq / (eq.n - N) : 1.0;
  Eigen::Matrix<double, N, 1> dy = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, N, N> cov_y = Eigen::Matrix<double, N, N>::Zero();
  out.degenerate = eq.n < p.min_cells || !(lmax > 0.0);
  for (int i = 0; i < N; ++i) {
    const auto v = V.col(i);
    if (lmax > 0.0 && lambda(i) > p.degeneracy_eigen_ratio * lmax && eq.n >= p.min_cells) {
      dy -= (v.dot(bs) / lambda(i)) * v;
      cov_y += (sigma2 / lambda(i)) * v * v.transpose();
    } else {
      out.degenerate = true;
      cov_y += kUnobservedVariance * v * v.transpose();
    }
  }
  out.step = s.asDiagonal() * dy;
  out.covariance = s.asDiagonal() * cov_y * s.asDiagonal();
  return out;
}

template <int N>
Vector6d toTwist(const Eigen::Matrix<double, N, 1>& x) {
  if constexpr (N == 6) {
    return x;
  } else {
    Vector6d xi = Vector6d::Zero();
    for (int i = 0; i < 3; ++i) xi(kIndex3[i]) = x(i);
    return xi;
  }
}

template <int N>
Matrix6d toTwistCovariance(const Eigen::Matrix<double, N, N>& c) {
  if constexpr (N == 6) {
    return c;
  } else {
    Matrix6d out = Matrix6d::Zero();
    out.diagonal().setConstant(kUnobservedVariance);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out(kIndex3[i], kIndex3[j]) = c(i, j);
    return out;
  }
}

template <int N>
AlignmentResult alignImpl(const SolverParams& p, const HeightFrame& reference,
                          const HeightFrame& current, const Eigen::Isometry3d& initial_guess) {
  Stopwatch sw;
  AlignmentResult res;
  Eigen::Isometry3d T = initial_guess;
  const int rot_first = N == 6 ? 3 : 2;
  const int levels = static_cast<int>(
      std::min(reference.levels().size(), current.levels().size()));
  for (int level = levels - 1; level >= 0; --level) {
    const HeightSampler& sampler = reference.levels()[level].sampler;
    const std::vector<SelectedCell>& cells = current.levels()[level].cells;
    // Coarse cells average more terrain: widen the robust kernel with the cell size.
    const double delta = p.huber_delta * (1 << level);
    bool converged = false;
    for (int it = 0; it < p.max_iterations && !converged; ++it) {
      const NormalEquations<N> eq = linearise<N>(sampler, cells, T, delta, p.max_residual);
      const ConditionedSolve<N> sol = solveConditioned<N>(eq, p, rot_first);
      const Vector6d xi = toTwist<N>(sol.step);
      T = expSE3(xi) * T;
      ++res.iterations;
      converged = xi.head<3>().norm() < p.min_step_translation &&
                  xi.tail<3>().norm() < p.min_step_rotation;
    }
    if (level == 0) res.converged = converged;
  }
  // Statistics and covariance at the solution, on the finest level.
  if (levels > 0) {
    const NormalEquations<N> eq = linearise<N>(reference.levels()[0].sampler,
                                               current.levels()[0].cells, T, p.huber_delta,
                                               p.max_residual);
    const ConditionedSolve<N> sol = solveConditioned<N>(eq, p, rot_first);
    res.cells = eq.n;
    res.rms_height_error = eq.n > 0 ? std::sqrt(eq.sq / eq.n) : 0.0;
    res.degenerate = sol.degenerate;
    res.covariance = toTwistCovariance<N>(sol.covariance);
  } else {
    res.degenerate = true;
    res.covariance = Matrix6d::Identity() * kUnobservedVariance;
  }
  T.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  res.pose = T;
  res.times.solve_ms = sw.elapsedMs();
  return res;
}

}  // namespace

DirectAligner::DirectAligner(const SolverParams& params) : params_(params) {}

AlignmentResult DirectAligner::align(const HeightFrame& reference, const HeightFrame& current,
                                     const Eigen::Isometry3d& initial_guess) const {
  if (params_.dof == 6) return alignImpl<6>(params_, reference, current, initial_guess);
  return alignImpl<3>(params_, reference, current, initial_guess);
}

}  // namespace dlo
