// The scalar reference of placing cells against the reference's centroid offsets
// (simd/place_cells_kernels.h).
#include <algorithm>

#include "simd/place_cells_kernels.h"

namespace dlo::simd {

size_t placeCellsScalar(const OffsetLattice& lattice, const SelectedCell* cells,
                        const Eigen::Vector2f* cell_offsets, size_t from, size_t n,
                        const Eigen::Matrix3f& R, const Eigen::Vector3f& t, bool warm_start,
                        Eigen::Vector2f* warm, SelectedCell* out) {
  const int cols = lattice.cols, rows = lattice.rows;
  const float inv_res = lattice.inv_res, x_c = lattice.x_c, y_c = lattice.y_c;
  // Beyond the lattice every offset is zero; clamped there, floors stay in int range.
  const float u_max = static_cast<float>(cols + 1), v_max = static_cast<float>(rows + 1);
  const auto floorInt = [](float x) {
    const int i = static_cast<int>(x);
    return i - (x < static_cast<float>(i) ? 1 : 0);
  };
  const int steps = warm_start ? kWarmNewtonSteps : kColdNewtonSteps;
  for (size_t i = from; i < n; ++i) {
    SelectedCell c = cells[i];
    c.x += cell_offsets[i].x();
    c.y += cell_offsets[i].y();
    const Eigen::Vector3f q = R * Eigen::Vector3f(c.x, c.y, c.h) + t;
    // The reference's cells stand at their centroids, centre + offset: the lattice of centres
    // deformed by the offsets, interpolated bilinearly. The place p of the regular lattice that
    // this deformation takes to q, p + offset(p) = q, by Newton's method (the bilinear
    // interpolant of heights at p is then the deformed lattice's at q).
    const Eigen::Vector2f target = q.head<2>();
    Eigen::Vector2f at = warm_start ? Eigen::Vector2f(target - warm[i]) : target;
    for (int it = 0; it < steps; ++it) {
      const float u = std::clamp((at.x() - x_c) * inv_res, -2.0f, u_max);
      const float v = std::clamp((at.y() - y_c) * inv_res, -2.0f, v_max);
      const int c0 = floorInt(u), r0 = floorInt(v);
      const float fu = u - static_cast<float>(c0), fv = v - static_cast<float>(r0);
      Eigen::Vector2f d00, d10, d01, d11;
      cornerOffsets(lattice, r0, c0, d00, d10, d01, d11);
      const Eigen::Vector2f d =
          (1 - fv) * ((1 - fu) * d00 + fu * d10) + fv * ((1 - fu) * d01 + fu * d11);
      const Eigen::Vector2f e = at + d - target;
      if (e.squaredNorm() < 1e-10f) break;
      Eigen::Matrix2f J = Eigen::Matrix2f::Identity();
      J.col(0) += ((1 - fv) * (d10 - d00) + fv * (d11 - d01)) * inv_res;
      J.col(1) += ((1 - fu) * (d01 - d00) + fu * (d11 - d10)) * inv_res;
      if (J.determinant() < 0.1f) break;  // centroids (nearly) folded over: no inverse
      Eigen::Vector2f step = J.inverse() * e;
      if (step.norm() > lattice.limit) step *= lattice.limit / step.norm();
      at -= step;
    }
    const Eigen::Vector2f d = target - at;
    if (warm != nullptr) warm[i] = d;
    // Moved by -d in the reference: by -R^T d in the scan.
    const Eigen::Vector3f back = R.transpose() * Eigen::Vector3f(d.x(), d.y(), 0.0f);
    c.x -= back.x();
    c.y -= back.y();
    out[i] = c;
  }
  return n;
}

}  // namespace dlo::simd
