/// \file direct_aligner.h
/// \brief DirectAligner: Gauss-Newton on the height difference error between two HeightFrames.
#pragma once

#include <Eigen/Geometry>

#include "dlo/core/height_frame.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/stage_times.h"

namespace dlo {

/// Solver parameters (INI section [solver]).
struct SolverParams {
  int dof = 3;                         ///< 3 or 6
  int max_iterations = 30;             ///< per pyramid level
  double huber_delta = 0.10;           ///< robust kernel width on the height error, metres
  double max_residual = 2.0;           ///< residuals beyond this (m) are outliers, weight 0
  double min_step_translation = 1e-4;  ///< convergence: translation update below this (m)
  double min_step_rotation = 1e-5;     ///< convergence: rotation update below this (rad)
  /// Convergence of the coarse levels: a translation update below this fraction of the level's
  /// cell size (a rotation update below it over rotation_scale); 0 = the min_step criteria
  /// scaled with the cell, as on the finest level. A coarse level only has to bring the next one
  /// into its basin, so stopping early saves iterations on dense scans; on sparse scans the
  /// coarse levels carry more of the estimate, and the sparse sensor profile sets 0
  /// (measurements: docs/benchmarks.md).
  double coarse_step = 0.01;
  int min_cells = 30;  ///< fewer usable cells than this: degenerate
  /// eig_min/eig_max of the scaled Hessian below this, on the finest level or the next coarser
  /// one: degenerate
  double degeneracy_eigen_ratio = 0.02;
  double rotation_scale = 10.0;  ///< metres; scales rotations against translations
                                 ///< when judging conditioning
};

/// Outcome of one registration.
struct AlignmentResult {
  /// Pose of the current frame in the reference frame: a point p of the current scan lies at
  /// pose * p in the reference.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  /// Covariance of the pose, order (x, y, z, wx, wy, wz) with a left perturbation
  /// pose = exp(xi) * estimate; unestimated directions carry the initial guess variance 1e6.
  Matrix6d covariance = Matrix6d::Identity();
  int iterations = 0;             ///< Gauss-Newton iterations over all levels
  int cells = 0;                  ///< cells with a valid residual at the last iteration
  double rms_height_error = 0.0;  ///< RMS of the height error at the end, metres
  /// Mean robust (Huber) cost per selected cell of the finest level at `pose`, a cell that
  /// found no reference or is an outlier counted at the cost of the largest inlier: lower is a
  /// better fit. Comparable between registrations of the same current frame against the same
  /// reference (DirectAligner::cost() gives it for any pose), which is how results from
  /// different starts are told apart.
  double cost = 0.0;
  bool converged = false;  ///< the finest level met the step criteria
  /// The Hessian of the finest level or of the next coarser one was ill-conditioned, or there
  /// were too few cells: the covariance is 1e6 along what either cannot observe, and along
  /// what the next coarser level cannot observe `pose` is the initial guess.
  bool degenerate = false;
  /// Smallest over largest eigenvalue of the Hessian (rotations scaled by rotation_scale), the
  /// lower of the finest level and the next coarser one: 1 is isotropic information, 0 an
  /// unobservable direction.
  double information_ratio = 0.0;
  StageTimes times;  ///< solve_ms only (frame build times are the frames')
};

/// Registers a current HeightFrame against a reference HeightFrame, coarse to fine.
/// Stateless apart from its parameters: one aligner can serve many pairs.
class DirectAligner {
 public:
  explicit DirectAligner(const SolverParams& params = SolverParams());

  /// Pose of `current` in `reference`, starting from `initial_guess`. Throws
  /// std::invalid_argument if `reference` was built FrameUse::kCurrentOnly or `current`
  /// FrameUse::kReferenceOnly.
  /// \param max_levels at most this many pyramid levels, from the finest (0 or less: every
  ///        level both frames have). A guess known to a few decimetres needs no coarser level,
  ///        whose wider basin only adds wrong minima.
  AlignmentResult align(const HeightFrame& reference, const HeightFrame& current,
                        const Eigen::Isometry3d& initial_guess, int max_levels = 0) const;

  /// AlignmentResult::cost of `current` placed at `pose` in `reference`, without iterating.
  /// \param level the pyramid level whose cells are compared (0: the finest, as
  ///        AlignmentResult::cost); a level that either frame lacks gives 0.
  double cost(const HeightFrame& reference, const HeightFrame& current,
              const Eigen::Isometry3d& pose, int level = 0) const;

  const SolverParams& params() const { return params_; }

 private:
  SolverParams params_;
};

}  // namespace dlo
