/// \file height_residual.h
/// \brief The height difference error (HDE) of one selected cell and its Jacobian.
#pragma once

#include <Eigen/Core>

#include "dlo/core/cell_selection.h"
#include "dlo/core/height_sampler.h"

namespace dlo {

/// Where a current-frame cell p = (x, y, h) lands in the reference under the pose T = [R | t]
/// (current in reference): q = R p + t.
template <typename Scalar>
inline Eigen::Matrix<Scalar, 3, 1> cellInReference(const SelectedCell& cell,
                                                   const Eigen::Matrix<Scalar, 3, 3>& R,
                                                   const Eigen::Matrix<Scalar, 3, 1>& t) {
  return R * Eigen::Matrix<Scalar, 3, 1>(Scalar(cell.x), Scalar(cell.y), Scalar(cell.h)) + t;
}

/// The residual and Jacobian of heightResidual() from a cell's position q in the reference and
/// the reference's sample there (h, gx, gy).
template <int N, typename Scalar>
inline void residualAt(const SelectedCell& cell, const Eigen::Matrix<Scalar, 3, 1>& q, float h,
                       float gx_ref, float gy_ref, Scalar& e, Eigen::Matrix<Scalar, N, 1>& J) {
  static_assert(N == 3 || N == 6, "3 or 6 degrees of freedom");
  // A ground cell's gradient is sub-threshold noise: it observes height only.
  const Scalar gx = cell.ground ? Scalar(0) : Scalar(gx_ref);
  const Scalar gy = cell.ground ? Scalar(0) : Scalar(gy_ref);
  e = Scalar(h) - q.z();
  if constexpr (N == 6) {
    J << gx, gy, Scalar(-1), -gy * q.z() - q.y(), gx * q.z() + q.x(), -gx * q.y() + gy * q.x();
  } else {
    J << gx, gy, -gx * q.y() + gy * q.x();
  }
}

/// Residual of a current-frame cell p = (x, y, h) under the pose T (current in reference):
/// with q = R p + t,
///   e = H_ref(q_x, q_y) - q_z.
/// The grid is an orthographic projection (u = x/res + cx), not a pinhole camera, so unlike the
/// paper's equation 17 nothing divides by depth. For a left perturbation T <- exp(xi) T with
/// xi = (tx, ty, tz, wx, wy, wz), dq/dxi = [I | -[q]x], hence
///   de/dxi = [gx, gy, -1] [I | -[q]x]
///          = [gx, gy, -1, -gy qz - qy, gx qz + qx, -gx qy + gy qx],
/// with (gx, gy) the reference gradient at q (zero for ground-lattice cells). The 3-DoF Jacobian
/// keeps (tx, ty, wz):
///   [gx, gy, -gx qy + gy qx].
/// \tparam N 3 or 6 parameters.
/// \return false if q falls where the reference has no valid height or gradient.
template <int N, typename Scalar>
inline bool heightResidual(const HeightSampler& reference, const SelectedCell& cell,
                           const Eigen::Matrix<Scalar, 3, 3>& R,
                           const Eigen::Matrix<Scalar, 3, 1>& t, Scalar& e,
                           Eigen::Matrix<Scalar, N, 1>& J) {
  const Eigen::Matrix<Scalar, 3, 1> q = cellInReference(cell, R, t);
  HeightSample s;
  if (!reference.sample(static_cast<double>(q.x()), static_cast<double>(q.y()), s)) return false;
  residualAt<N>(cell, q, s.h, s.gx, s.gy, e, J);
  return true;
}

}  // namespace dlo
