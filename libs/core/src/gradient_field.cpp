#include "dlo/core/gradient_field.h"

#include <cmath>

namespace dlo {

float GradientField::magnitude(int row, int col) const {
  const int i = row * cols + col;
  return std::sqrt(gx[i] * gx[i] + gy[i] * gy[i]);
}

GradientField computeGradients(const HeightGrid& grid) {
  GradientField f;
  f.cols = grid.cols();
  f.rows = grid.rows();
  const int n = f.cols * f.rows;
  f.gx.assign(n, 0.0f);
  f.gy.assign(n, 0.0f);
  f.valid.assign(n, 0u);
  const float k = static_cast<float>(0.5 / grid.resolution());
  const std::vector<float>& h = grid.heights();
  const std::vector<std::uint8_t>& ok = grid.supportMask();
  const int cols = f.cols;
  for (int r = 1; r + 1 < f.rows; ++r) {
    for (int c = 1; c + 1 < cols; ++c) {
      const int i = r * cols + c;
      if (!(ok[i] & ok[i - 1] & ok[i + 1] & ok[i - cols] & ok[i + cols])) continue;
      f.gx[i] = (h[i + 1] - h[i - 1]) * k;
      f.gy[i] = (h[i + cols] - h[i - cols]) * k;
      f.valid[i] = 1u;
    }
  }
  return f;
}

}  // namespace dlo
