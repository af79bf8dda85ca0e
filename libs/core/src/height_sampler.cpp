#include "dlo/core/height_sampler.h"

namespace dlo {

HeightSampler::HeightSampler(const HeightGrid& grid, const GradientField& gradients)
    : geometry_(grid.geometry()), inv_resolution_(1.0 / grid.resolution()) {
  const int n = geometry_.cellCount();
  cells_.resize(n);
  const std::vector<float>& h = grid.heights();
  for (int i = 0; i < n; ++i) {
    const bool ok = gradients.valid[i] != 0;  // implies the cell has a height
    cells_[i] = Cell{ok ? h[i] : 0.0f, gradients.gx[i], gradients.gy[i], ok ? 1.0f : 0.0f};
  }
}

}  // namespace dlo
