/// \file ground_alignment.h
/// \brief z, roll and pitch of a registration from the ground: the current scan's ground cells
/// laid on the reference's measured ground, x, y and yaw held.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "dlo/core/ground_surface.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/height_grid.h"

namespace dlo {

/// Outcome of alignToGround().
struct GroundAlignment {
  /// z, roll and pitch were measured; otherwise `pose` is the guess.
  bool aligned = false;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< current in reference
  int cells = 0;     ///< ground cells that found the reference's ground, at the end
  double rms = 0.0;  ///< RMS height error of those cells, metres
  /// Covariance of `pose` (aligned only) as a left perturbation in the reference frame, order
  /// (x, y, z, wx, wy, wz) as AlignmentResult::covariance: what the ground measures (height,
  /// roll, pitch about the vehicle: rms^2 times the inverse of the Gauss-Newton normal matrix),
  /// 1e6 along what it cannot observe, zero for x, y and yaw, which it holds.
  Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
};

/// Corrects the height, roll and pitch of `guess` (the current grid frame in the reference
/// grid's frame) so that the current scan's ground `cells` lie on the ground that `reference`
/// measured there: Gauss-Newton on e = H_ref(q_x, q_y) - q_z, q = T p, over (tz, wx, wy) about
/// the vehicle's position, with x, y and the heading held. H_ref is read only between measured
/// reference cells (a cell filled from a coarser level may average a wall into the ground)
/// where the reference is no steeper than a road (kerbs, walls and cars are left out), with a
/// Huber kernel. The reference's ground at the vehicle's registered position is what makes the
/// trajectory climb on a constant grade, on which every scan sees the same ground relative to
/// itself.
/// `rotation_scale` (metres) weighs rotations against heights when judging conditioning, as
/// SolverParams::rotation_scale. Where too few cells find the reference, the system is
/// ill-conditioned (a strip of ground constrains no roll across it: that direction keeps the
/// guess) or the correction is implausibly large, what is not measured stays at the guess.
/// The level of `frame` whose cells are closest to 0.4 m, where the ground is fitted and aligned:
/// wide enough that a cell 20 m away holds a few ground points, fine enough that few cells mix
/// ground and obstacles. 0 for a frame without levels.
size_t groundLevel(const HeightFrame& frame);

GroundAlignment alignToGround(const HeightGrid& reference, const std::vector<GroundCell>& cells,
                              const Eigen::Isometry3d& guess, double rotation_scale);

}  // namespace dlo
