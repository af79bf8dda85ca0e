#include "dlo/core/direct_aligner.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "dlo/core/height_residual.h"
#include "simd/place_cells_kernels.h"
#include "simd/sample_cells_kernels.h"

namespace dlo {

namespace {

/// Variance given to directions the registration could not observe.
constexpr double kUnobservedVariance = 1e6;

/// Residuals a level needs to be solved at all: a few times more than unknowns. The min_cells
/// rule only decides the final degeneracy flag, since coarse levels legitimately have few cells.
template <int N>
constexpr int kMinResiduals = 3 * N;

/// Indices of the 3-DoF parameters in the twist (tx, ty, tz, wx, wy, wz).
constexpr int kIndex3[3] = {0, 1, 5};

/// Normal equations and robust cost of the selected cells at one pose.
template <int N>
struct NormalEquations {
  Eigen::Matrix<double, N, N> H = Eigen::Matrix<double, N, N>::Zero();
  Eigen::Matrix<double, N, 1> b = Eigen::Matrix<double, N, 1>::Zero();
  double cost = 0.0;         ///< Huber cost over all cells; a lost cell costs like an outlier
  double weighted_sq = 0.0;  ///< sum of w e^2 over inliers
  double sq = 0.0;           ///< sum of e^2 over inliers
  int n = 0;                 ///< inlier residuals
};

using simd::CellSample;

/// cellInReference() and HeightSampler::sample() of every cell, into out[0, cells.size()):
/// vectorised where it can be (simd/sample_cells_kernels.h), with the same results bit for bit.
void sampleCells(const HeightSampler& sampler, const std::vector<SelectedCell>& cells,
                 const Eigen::Matrix3f& R, const Eigen::Vector3f& t, CellSample* out) {
  size_t k = 0;
#ifdef __SSE2__
  k = simd::sampleCellsSse2(sampler, cells.data(), k, cells.size(), R, t, out);
#endif
  simd::sampleCellsScalar(sampler, cells.data(), k, cells.size(), R, t, out);
}

/// Cells whose H and b are summed in float before being added to the double sums.
constexpr int kSumBlock = 256;

template <int N>
NormalEquations<N> linearise(const HeightSampler& sampler, const std::vector<SelectedCell>& cells,
                             const Eigen::Isometry3d& T, double huber_delta, double max_residual) {
  NormalEquations<N> eq;
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  const float delta = static_cast<float>(huber_delta);
  const float max_e = static_cast<float>(max_residual);
  // A cell that leaves the reference or becomes an outlier pays the cost of the largest inlier,
  // so that the cost cannot drop by pushing cells out of view.
  const float outlier_cost = delta * (max_e - 0.5f * delta);
  int lost = 0;
  float e = 0.0f;
  Eigen::Matrix<float, N, 1> J;
  const size_t n = cells.size();
  // Scratch kept across calls, used through a plain pointer (see cell_selection.cpp).
  thread_local std::vector<CellSample> sample_scratch;
  sample_scratch.resize(n);
  CellSample* const samples = sample_scratch.data();
  sampleCells(sampler, cells, R, t, samples);
  size_t k = 0;
  bool more = true;
  // H (its upper triangle, column by column) and b are summed in float over blocks of
  // kSumBlock inlier cells (fast), and the blocks in double into `eq` (precise). The products
  // are Eigen's rankUpdate(J, w) and (w e) J, in the same order, without the call. The block's
  // sums are local arrays indexed by constants, which the compiler keeps in registers (as
  // members of a helper object they were added to in memory, a store-to-load chain per cell).
  // A full block is added at once and the rest (possibly nothing) at the end.
  while (more) {
    float H[N * (N + 1) / 2] = {};
    float b[N] = {};
    int added = 0;
    for (; k < n && added < kSumBlock; ++k) {
      const CellSample& cs = samples[k];
      if (cs.s.ok != 0.0f) residualAt<N>(cells[k], cs.q, cs.s.h, cs.s.gx, cs.s.gy, e, J);
      const float ae = cs.s.ok != 0.0f ? std::fabs(e) : max_e + 1.0f;
      if (ae > max_e) {
        ++lost;
        continue;
      }
      const bool inner = ae <= delta;
      const float w = inner ? 1.0f : delta / ae;  // Huber
      eq.cost += inner ? 0.5 * static_cast<double>(e * e)
                       : static_cast<double>(delta * (ae - 0.5f * delta));
      int h = 0;
      for (int j = 0; j < N; ++j) {
        const float wj = w * J(j);
        for (int i = 0; i <= j; ++i) H[h++] += wj * J(i);
      }
      const float we = w * e;
      for (int i = 0; i < N; ++i) b[i] += we * J(i);
      ++added;
      eq.weighted_sq += static_cast<double>(w * e * e);
      eq.sq += static_cast<double>(e * e);
      ++eq.n;
    }
    int h = 0;
    for (int j = 0; j < N; ++j)
      for (int i = 0; i <= j; ++i) eq.H(i, j) += static_cast<double>(H[h++]);
    for (int i = 0; i < N; ++i) eq.b(i) += static_cast<double>(b[i]);
    more = added == kSumBlock;
  }
  eq.cost += static_cast<double>(lost) * outlier_cost;
  eq.H = eq.H.template selfadjointView<Eigen::Upper>();
  return eq;
}

/// The normal equations in a basis where rotations are scaled to metres (times
/// rotation_scale), so that translation and rotation eigenvalues are comparable, decomposed once
/// and solved for any damping.
template <int N>
class ConditionedSystem {
 public:
  using Vec = Eigen::Matrix<double, N, 1>;
  using Mat = Eigen::Matrix<double, N, N>;

  ConditionedSystem(const NormalEquations<N>& eq, const SolverParams& p, int min_cells) {
    const int rot_first = N == 6 ? 3 : 2;
    scale_.setOnes();
    for (int i = rot_first; i < N; ++i) scale_(i) = 1.0 / p.rotation_scale;
    const Mat Hs = scale_.asDiagonal() * eq.H * scale_.asDiagonal();
    bs_ = scale_.asDiagonal() * eq.b;
    Eigen::SelfAdjointEigenSolver<Mat> es(Hs);
    lambda_ = es.eigenvalues();  // ascending
    V_ = es.eigenvectors();
    lmax_ = lambda_(N - 1);
    const bool enough = eq.n >= min_cells && lmax_ > 0.0;
    for (int i = 0; i < N; ++i) {
      observable_[i] = enough && lambda_(i) > p.degeneracy_eigen_ratio * lmax_;
    }
    sigma2_ = eq.n > N ? eq.weighted_sq / (eq.n - N) : 1.0;
  }

  /// Levenberg-damped step, zero along unobservable directions: the motion prior is kept there
  /// instead of a confident wrong answer.
  Vec step(double damping) const {
    Vec dy = Vec::Zero();
    for (int i = 0; i < N; ++i) {
      if (!observable_[i]) continue;
      const auto v = V_.col(i);
      dy -= (v.dot(bs_) / (lambda_(i) + damping * lmax_)) * v;
    }
    return scale_.asDiagonal() * dy;
  }

  /// Orthogonal projector onto the unobservable eigenvectors (scaled coordinates).
  Mat unobservable() const {
    Mat U = Mat::Zero();
    for (int i = 0; i < N; ++i) {
      if (!observable_[i]) U += V_.col(i) * V_.col(i).transpose();
    }
    return U;
  }

  /// sigma^2 H^-1 on the directions outside `U` (a projector onto unobservable directions in
  /// scaled coordinates), kUnobservedVariance inside.
  Mat covariance(const Mat& U) const {
    const Mat keep = Mat::Identity() - U;
    Mat cov = kUnobservedVariance * U;
    for (int i = 0; i < N; ++i) {
      if (!observable_[i]) continue;
      const Vec v = keep * V_.col(i);
      cov += (sigma2_ / lambda_(i)) * v * v.transpose();
    }
    return scale_.asDiagonal() * cov * scale_.asDiagonal();
  }

  /// The update `x` (twist units) without its components inside `U`. In the Hessian's
  /// eigenbasis the quadratic cost separates, so dropping the unobservable components leaves the
  /// observable ones at their optimum.
  Vec withoutUnobservable(const Vec& x, const Mat& U) const {
    const Vec y = scale_.cwiseInverse().asDiagonal() * x;
    return scale_.asDiagonal() * (y - U * y);
  }

  double informationRatio() const { return lmax_ > 0.0 ? std::max(0.0, lambda_(0)) / lmax_ : 0.0; }

 private:
  Vec scale_, bs_, lambda_;
  Mat V_;
  double lmax_ = 0.0;
  double sigma2_ = 1.0;
  bool observable_[N] = {};
};

/// Projector onto the directions that either system cannot observe. Unobservable directions
/// of the two that are within 60 degrees of each other count as one (the projector sum's
/// eigenvalue is then above 1.5 along their mean and below 0.5 across it).
template <int N>
Eigen::Matrix<double, N, N> unobservableOfEither(const ConditionedSystem<N>& a,
                                                 const ConditionedSystem<N>& b) {
  using Mat = Eigen::Matrix<double, N, N>;
  Eigen::SelfAdjointEigenSolver<Mat> es(a.unobservable() + b.unobservable());
  Mat U = Mat::Zero();
  for (int i = 0; i < N; ++i) {
    if (es.eigenvalues()(i) > 0.5) {
      U += es.eigenvectors().col(i) * es.eigenvectors().col(i).transpose();
    }
  }
  return U;
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
Eigen::Matrix<double, N, 1> fromTwist(const Vector6d& xi) {
  if constexpr (N == 6) {
    return xi;
  } else {
    return Eigen::Vector3d(xi(kIndex3[0]), xi(kIndex3[1]), xi(kIndex3[2]));
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

/// Gauss-Newton over the levels coarsest..finest. Updates T; returns whether the finest level
/// converged.
///
/// Plain Gauss-Newton can fall into a limit cycle when cells enter and leave the reference's
/// valid area from one iteration to the next. A cost-based acceptance test (Levenberg-Marquardt)
/// does not help here: the Jacobian uses smoothed gradients, not the derivative of the bilinear
/// interpolant, and on real scans the fixed point of those equations is the more accurate
/// estimate (measured: 2 mm against 14 mm on the KITTI split test). So steps are contracted
/// instead: whenever a step points back against the previous one, later steps are halved.
/// The current level's cells as they are compared with the reference: each at the centroid of
/// its points, and read in the reference where the reference's own cells' centroids put that
/// place (the offsets interpolated bilinearly there), when both frames have their offsets; at
/// their centroids, read where they fall, when only the current frame has them (a reference
/// whose heights stand at its cells' centres, such as dlo-localize's prior map); otherwise the
/// cells as selected, at their centres.
const std::vector<SelectedCell>& placed(const FrameLevel& ref, const FrameLevel& cur,
                                        const Eigen::Isometry3d& T,
                                        std::vector<Eigen::Vector2f>* warm = nullptr) {
  if (cur.cell_offsets.size() != cur.cells.size()) return cur.cells;
  thread_local std::vector<SelectedCell> scratch;
  if (ref.grid_offsets.empty()) {
    scratch = cur.cells;
    for (size_t i = 0; i < scratch.size(); ++i) {
      scratch[i].x += cur.cell_offsets[i].x();
      scratch[i].y += cur.cell_offsets[i].y();
    }
    return scratch;
  }
  scratch.resize(cur.cells.size());
  // The previous solutions, target - place, per cell: the pose moves little from one
  // Gauss-Newton iteration to the next, so that they start Newton's method where it nearly
  // ends (one evaluation instead of three or four).
  const bool warm_start = warm != nullptr && warm->size() == cur.cells.size();
  if (warm != nullptr && !warm_start) warm->resize(cur.cells.size());  // written, not read
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  const simd::OffsetLattice lattice =
      simd::offsetLattice(ref.grid.geometry(), ref.grid_offsets.data());
  const size_t n = cur.cells.size();
  Eigen::Vector2f* w = warm != nullptr ? warm->data() : nullptr;
  size_t k = 0;
#ifdef __SSE2__
  k = simd::placeCellsSse2(lattice, cur.cells.data(), cur.cell_offsets.data(), k, n, R, t,
                           warm_start, w, scratch.data());
#endif
  simd::placeCellsScalar(lattice, cur.cells.data(), cur.cell_offsets.data(), k, n, R, t, warm_start,
                         w, scratch.data());
  return scratch;
}

template <int N>
bool refine(const SolverParams& p, const HeightFrame& reference, const HeightFrame& current,
            int coarsest, int finest, Eigen::Isometry3d& T, int& iterations,
            std::vector<std::vector<Eigen::Vector2f>>& warm) {
  bool converged = false;
  for (int level = coarsest; level >= finest; --level) {
    const HeightSampler& sampler = reference.levels()[level].sampler;
    // Coarse cells average more terrain: widen the robust kernel and the step criterion with
    // the cell size.
    const double scale = static_cast<double>(1 << level);
    const double delta = p.huber_delta * scale;
    double min_dt = p.min_step_translation * scale;
    double min_dr = p.min_step_rotation * scale;
    if (level > finest) {
      const double cell = reference.levels()[level].grid.resolution();
      min_dt = std::max(min_dt, p.coarse_step * cell);
      min_dr = std::max(min_dr, p.coarse_step * cell / p.rotation_scale);
    }
    double gain = 1.0;
    Vector6d previous = Vector6d::Zero();
    converged = false;
    const FrameLevel& ref_level = reference.levels()[level];
    const FrameLevel& cur_level = current.levels()[level];
    // Against a reference whose heights stand at its cells' centres (dlo-localize's prior map)
    // the cells stand at their centroids whatever the pose: placed once per level, not at every
    // iteration.
    thread_local std::vector<SelectedCell> at_centroids;
    const bool pose_free = ref_level.grid_offsets.empty() && !cur_level.cells.empty() &&
                           cur_level.cell_offsets.size() == cur_level.cells.size();
    if (pose_free) at_centroids = placed(ref_level, cur_level, T);
    for (int it = 0; it < p.max_iterations && !converged; ++it) {
      // Where the cells stand in the reference follows the pose (placed()).
      const NormalEquations<N> eq = linearise<N>(
          sampler,
          pose_free ? at_centroids
                    : placed(ref_level, cur_level, T, &warm[static_cast<size_t>(level)]),
          T, delta, p.max_residual);
      const ConditionedSystem<N> sys(eq, p, kMinResiduals<N>);
      Vector6d xi = toTwist<N>(sys.step(0.0));
      // A step that turns back on the previous one is the signature of a limit cycle.
      if (xi.dot(previous) < 0.0) gain *= 0.5;
      previous = xi;
      xi *= gain;
      T = expSE3(xi) * T;
      ++iterations;
      converged = xi.head<3>().norm() < min_dt && xi.tail<3>().norm() < min_dr;
    }
  }
  return converged;
}

template <int N>
double meanCost(const NormalEquations<N>& eq, size_t cells) {
  return cells > 0 ? eq.cost / static_cast<double>(cells) : 0.0;
}

template <int N>
AlignmentResult alignImpl(const SolverParams& p, const HeightFrame& reference,
                          const HeightFrame& current, const Eigen::Isometry3d& initial_guess,
                          int max_levels) {
  Stopwatch sw;
  AlignmentResult res;
  Eigen::Isometry3d T = initial_guess;
  int levels = static_cast<int>(std::min(reference.levels().size(), current.levels().size()));
  if (max_levels > 0) levels = std::min(levels, max_levels);
  if (levels == 0) {
    res.degenerate = true;
    res.covariance = Matrix6d::Identity() * kUnobservedVariance;
    res.pose = T;
    return res;
  }
  {
    // The reference's reads are a cache miss each in grids of megabytes (reading the next scan
    // of a rawlog evicts them): ask for the lines of every level below the coarsest now, in
    // the order they will be used, while the coarsest iterates (the estimate moves by
    // centimetres, mostly within the same lines).
    const Eigen::Matrix3f R = T.linear().cast<float>();
    const Eigen::Vector3f t = T.translation().cast<float>();
    for (int level = levels - 2; level >= 0; --level) {
      const FrameLevel& ref = reference.levels()[level];
      // placed() reads the reference's centroid offsets around the same places.
      const Eigen::Vector2f* offsets = ref.grid_offsets.empty() ? nullptr : ref.grid_offsets.data();
      const GridGeometry& geo = ref.grid.geometry();
      const double inv_res = 1.0 / geo.resolution;
      for (const SelectedCell& c : current.levels()[level].cells) {
        const Eigen::Vector3f q = cellInReference(c, R, t);
        ref.sampler.prefetch(q.x(), q.y());
        if (offsets == nullptr) continue;
        const int col = static_cast<int>(std::floor((q.x() - geo.x_min) * inv_res - 0.5));
        const int row = static_cast<int>(std::floor((q.y() - geo.y_min) * inv_res - 0.5));
        if (row < 0 || col < 0 || row + 1 >= geo.rows || col + 1 >= geo.cols) continue;
        const Eigen::Vector2f* o = offsets + static_cast<size_t>(row * geo.cols + col);
        __builtin_prefetch(o);
        __builtin_prefetch(o + geo.cols);
      }
    }
  }
  // Per level, where the cells stood in the reference at the last pose (see placed()).
  thread_local std::vector<std::vector<Eigen::Vector2f>> warm;
  warm.resize(static_cast<size_t>(levels));
  for (std::vector<Eigen::Vector2f>& w : warm) w.clear();
  if constexpr (N == 6) {
    // Far from the solution, freeing z, roll and pitch lets walls be "explained" by tilting
    // the ground; settle x, y and yaw on the coarse levels first.
    if (levels > 1) refine<3>(p, reference, current, levels - 1, 1, T, res.iterations, warm);
  }
  res.converged = refine<N>(p, reference, current, levels - 1, 0, T, res.iterations, warm);
  // Statistics, observability and covariance at the solution. Which directions keep the prior
  // is judged on the next coarser level (0.2 m by default), because fine-scale texture (laser
  // rings and range noise on a wall seen at a grazing angle) changes from scan to scan yet looks
  // like information at 0.1 m: along a simulated corridor the finest level keeps an information
  // ratio of 0.04-0.07, the 0.2 m level 0.003-0.01, while every scan of the simulated town drive
  // stays above 0.05 on both. The reverse also happens: a sparse VLP-16 scan can be weak at
  // 0.1 m (ratio 0.015) and well observed at 0.2 m (0.035 and more); such a result is flagged
  // and its covariance inflated along what the finest level misses, but its estimate is kept.
  const NormalEquations<N> eq =
      linearise<N>(reference.levels()[0].sampler,
                   placed(reference.levels()[0], current.levels()[0], T, &warm[0]), T,
                   p.huber_delta, p.max_residual);
  const ConditionedSystem<N> sys(eq, p, p.min_cells);
  Eigen::Matrix<double, N, N> unobserved = sys.unobservable();  // to keep at the prior
  Eigen::Matrix<double, N, N> uncertain = unobserved;           // to flag, variance 1e6
  res.information_ratio = sys.informationRatio();
  if (levels > 1) {
    const NormalEquations<N> eq1 =
        linearise<N>(reference.levels()[1].sampler,
                     placed(reference.levels()[1], current.levels()[1], T, &warm[1]), T,
                     2.0 * p.huber_delta, p.max_residual);
    const ConditionedSystem<N> coarse(eq1, p, p.min_cells);
    unobserved = coarse.unobservable();
    uncertain = unobservableOfEither(sys, coarse);
    res.information_ratio = std::min(res.information_ratio, coarse.informationRatio());
  }
  res.degenerate = uncertain.trace() > 0.5;
  if (unobserved.trace() > 0.5) {
    // The coarse levels, or iterations whose Hessian still looked well conditioned, may have
    // moved the pose along what is not observed (with too few cells, along everything): those
    // directions return to the initial guess, the motion prior.
    const Vector6d moved = logSE3(T * initial_guess.inverse());
    T = expSE3(toTwist<N>(sys.withoutUnobservable(fromTwist<N>(moved), unobserved))) *
        initial_guess;
  }
  res.cells = eq.n;
  res.cost = meanCost(eq, current.levels()[0].cells.size());
  res.rms_height_error = eq.n > 0 ? std::sqrt(eq.sq / eq.n) : 0.0;
  res.covariance = toTwistCovariance<N>(sys.covariance(uncertain));
  T.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  res.pose = T;
  res.times.solve_ms = sw.elapsedMs();
  return res;
}

}  // namespace

double DirectAligner::cost(const HeightFrame& reference, const HeightFrame& current,
                           const Eigen::Isometry3d& pose, int level) const {
  const size_t l = static_cast<size_t>(level);
  if (level < 0 || l >= reference.levels().size() || l >= current.levels().size()) return 0.0;
  const std::vector<SelectedCell>& cells = placed(reference.levels()[l], current.levels()[l], pose);
  const HeightSampler& sampler = reference.levels()[l].sampler;
  const double d = params_.huber_delta, m = params_.max_residual;
  return params_.dof == 6 ? meanCost(linearise<6>(sampler, cells, pose, d, m), cells.size())
                          : meanCost(linearise<3>(sampler, cells, pose, d, m), cells.size());
}

DirectAligner::DirectAligner(const SolverParams& params) : params_(params) {}

AlignmentResult DirectAligner::align(const HeightFrame& reference, const HeightFrame& current,
                                     const Eigen::Isometry3d& initial_guess, int max_levels) const {
  if (!reference.canBeReference()) {
    throw std::invalid_argument(
        "DirectAligner::align: the reference frame was built FrameUse::kCurrentOnly");
  }
  if (!current.canBeCurrent()) {
    throw std::invalid_argument(
        "DirectAligner::align: the current frame was built FrameUse::kReferenceOnly");
  }
  if (params_.dof == 6) {
    return alignImpl<6>(params_, reference, current, initial_guess, max_levels);
  }
  return alignImpl<3>(params_, reference, current, initial_guess, max_levels);
}

}  // namespace dlo
