// The scalar reference of the linearisation's sampling (simd/sample_cells_kernels.h).
#include "dlo/core/height_residual.h"
#include "simd/sample_cells_kernels.h"

namespace dlo::simd {

size_t sampleCellsScalar(const HeightSampler& sampler, const SelectedCell* cells, size_t from,
                         size_t n, const Eigen::Matrix3f& R, const Eigen::Vector3f& t,
                         CellSample* out) {
  for (size_t k = from; k < n; ++k) {
    const Eigen::Vector3f q = cellInReference(cells[k], R, t);
    HeightSample s;
    const bool ok = sampler.sample(static_cast<double>(q.x()), static_cast<double>(q.y()), s);
    out[k].s = GradientCell{s.h, s.gx, s.gy, ok ? 1.0f : 0.0f};
    out[k].q = q;
  }
  return n;
}

}  // namespace dlo::simd
