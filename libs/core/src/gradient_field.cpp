#include "dlo/core/gradient_field.h"

namespace dlo {

GradientField computeGradients(const HeightGrid& grid) {
  GradientField f;
  computeGradients(grid, f);
  return f;
}

void computeGradients(const HeightGrid& grid, GradientField& f) {
  f.cols = grid.cols();
  f.rows = grid.rows();
  const int cols = f.cols;
  f.cells.assign(static_cast<size_t>(cols) * f.rows, GradientCell{0.0f, 0.0f, 0.0f, 0.0f});
  const float k = static_cast<float>(0.5 / grid.resolution());
  const float* h = grid.heights().data();
  const std::uint8_t* ok = grid.supportMask().data();
  GradientCell* out = f.cells.data();
  // Branch-free over the interior: invalid cells get zeros, which the sampler rejects.
  for (int r = 1; r + 1 < f.rows; ++r) {
    for (int c = 1; c + 1 < cols; ++c) {
      const int i = r * cols + c;
      const float m =
          static_cast<float>(ok[i] & ok[i - 1] & ok[i + 1] & ok[i - cols] & ok[i + cols]);
      out[i] = GradientCell{m * h[i], m * (h[i + 1] - h[i - 1]) * k,
                            m * (h[i + cols] - h[i - cols]) * k, m};
    }
  }
}

}  // namespace dlo
