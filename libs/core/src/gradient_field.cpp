#include "dlo/core/gradient_field.h"

#include <algorithm>

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
  // Every interior cell is written below: only the border is zeroed (assigning zeros to the
  // whole field first wrote its megabytes twice).
  const GradientCell none{0.0f, 0.0f, 0.0f, 0.0f};
  f.cells.resize(static_cast<size_t>(cols) * f.rows);
  if (f.cells.empty()) return;
  std::fill_n(f.cells.begin(), cols, none);
  std::fill_n(f.cells.end() - cols, cols, none);
  for (int r = 1; r + 1 < f.rows; ++r) {
    f.cells[static_cast<size_t>(r) * cols] = none;
    f.cells[static_cast<size_t>(r) * cols + cols - 1] = none;
  }
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
