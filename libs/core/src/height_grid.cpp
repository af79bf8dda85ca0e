#include "dlo/core/height_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dlo {

HeightGrid HeightGrid::fromPoints(const PointCloud& points, const GridGeometry& geometry,
                                  int min_points, double min_z, double max_z) {
  HeightGrid g;
  g.geometry_ = geometry;
  g.min_points_ = min_points;
  const int n = geometry.cellCount();
  g.count_.assign(n, 0u);
  g.sum_z_.assign(n, 0.0f);
  const float inv_res = static_cast<float>(1.0 / geometry.resolution);
  const float x0 = static_cast<float>(geometry.x_min);
  const float y0 = static_cast<float>(geometry.y_min);
  const float cols = static_cast<float>(geometry.cols);
  const float rows = static_cast<float>(geometry.rows);
  const float zlo = static_cast<float>(min_z);
  const float zhi = static_cast<float>(max_z);
  std::uint32_t* count = g.count_.data();
  float* sum = g.sum_z_.data();
  for (const Eigen::Vector3f& p : points) {
    const float u = (p.x() - x0) * inv_res;
    const float v = (p.y() - y0) * inv_res;
    // Written so that NaN fails every comparison and is skipped.
    if (!(u >= 0.0f && u < cols && v >= 0.0f && v < rows && p.z() >= zlo && p.z() <= zhi)) {
      continue;
    }
    const int idx = static_cast<int>(v) * geometry.cols + static_cast<int>(u);
    ++count[idx];
    sum[idx] += p.z();
  }
  g.finalise();
  return g;
}

HeightGrid HeightGrid::fromCells(const GridGeometry& geometry,
                                 const std::vector<float>& mean_heights,
                                 const std::vector<std::uint32_t>& counts, int min_points) {
  HeightGrid g;
  g.geometry_ = geometry;
  g.min_points_ = min_points;
  const int n = geometry.cellCount();
  g.count_.assign(n, 0u);
  g.sum_z_.assign(n, 0.0f);
  for (int i = 0; i < n && i < static_cast<int>(mean_heights.size()) &&
                  i < static_cast<int>(counts.size());
       ++i) {
    if (!std::isfinite(mean_heights[i])) continue;
    g.count_[i] = counts[i];
    g.sum_z_[i] = mean_heights[i] * static_cast<float>(counts[i]);
  }
  g.finalise();
  return g;
}

HeightGrid HeightGrid::coarser() const {
  HeightGrid g;
  g.geometry_ = geometry_.coarser();
  g.min_points_ = min_points_;
  const int n = g.geometry_.cellCount();
  g.count_.assign(n, 0u);
  g.sum_z_.assign(n, 0.0f);
  const int cols = geometry_.cols;
  for (int r = 0; r < geometry_.rows; ++r) {
    const int cr = (r / 2) * g.geometry_.cols;
    const std::uint32_t* cnt = &count_[r * cols];
    const float* sum = &sum_z_[r * cols];
    for (int c = 0; c < cols; ++c) {
      g.count_[cr + c / 2] += cnt[c];
      g.sum_z_[cr + c / 2] += sum[c];
    }
  }
  g.finalise();
  return g;
}

void HeightGrid::finalise() {
  const int n = geometry_.cellCount();
  height_.resize(n);
  valid_.resize(n);
  const std::uint32_t need = static_cast<std::uint32_t>(min_points_ < 1 ? 1 : min_points_);
  int valid_cells = 0;
  for (int i = 0; i < n; ++i) {
    const bool ok = count_[i] >= need;
    height_[i] = ok ? sum_z_[i] / static_cast<float>(count_[i]) : 0.0f;
    valid_[i] = ok ? 1u : 0u;
    valid_cells += ok ? 1 : 0;
  }
  valid_cells_ = valid_cells;
  support_ = valid_;
}

void HeightGrid::fillHolesFrom(const HeightGrid& coarser) {
  // Coarse heights premultiplied by support, with a one-cell border of zeros, so the inner loop
  // is branch-free: height = sum(w*s*h) / sum(w*s) over the four surrounding coarse cells.
  const GridGeometry& cg = coarser.geometry_;
  if (cg.cols != (geometry_.cols + 1) / 2 || cg.rows != (geometry_.rows + 1) / 2 ||
      std::abs(cg.resolution - 2.0 * geometry_.resolution) > 1e-9 * cg.resolution ||
      std::abs(cg.x_min - geometry_.x_min) > 1e-6 || std::abs(cg.y_min - geometry_.y_min) > 1e-6) {
    throw std::invalid_argument("HeightGrid::fillHolesFrom needs the grid's own coarser() level");
  }
  const int pc = cg.cols + 2;
  std::vector<float> sh(static_cast<size_t>(pc) * (cg.rows + 2), 0.0f);
  std::vector<float> s(sh.size(), 0.0f);
  for (int r = 0; r < cg.rows; ++r) {
    for (int c = 0; c < cg.cols; ++c) {
      const int j = r * cg.cols + c;
      if (!coarser.support_[j]) continue;
      const int k = (r + 1) * pc + (c + 1);
      s[k] = 1.0f;
      sh[k] = coarser.height_[j];
    }
  }
  // A fine cell centre lies a quarter of a coarse cell from the coarse centres around it, so
  // the bilinear weights are 3/4 and 1/4; its padded coarse cell is (r+1)/2, (c+1)/2.
  // Per fine row: blend the two coarse rows around it (weights 3/4, 1/4), then blend
  // horizontally; even fine columns lie 3/4 of the way to padded coarse column c/2 + 1, odd
  // ones 1/4 of the way to it.
  std::vector<float> vs(static_cast<size_t>(pc)), vh(static_cast<size_t>(pc));
  for (int r = 0; r < geometry_.rows; ++r) {
    const int pr0 = (r + 1) / 2;  // padded coarse row of the lower neighbour
    const float b = (r % 2 == 0) ? 0.75f : 0.25f;
    const float* s0 = &s[pr0 * pc];
    const float* h0 = &sh[pr0 * pc];
    for (int j = 0; j < pc; ++j) {
      vs[j] = (1 - b) * s0[j] + b * s0[j + pc];
      vh[j] = (1 - b) * h0[j] + b * h0[j + pc];
    }
    float* hrow = &height_[r * geometry_.cols];
    const std::uint8_t* vrow = &valid_[r * geometry_.cols];
    std::uint8_t* srow = &support_[r * geometry_.cols];
    for (int c = 0; c < geometry_.cols; ++c) {
      const int j = (c + 1) / 2;
      const float a = (c % 2 == 0) ? 0.75f : 0.25f;
      const float wsum = (1 - a) * vs[j] + a * vs[j + 1];
      const float hsum = (1 - a) * vh[j] + a * vh[j + 1];
      // Require most of the interpolation weight: no extrapolation far from data.
      const bool fill = !vrow[c] && wsum >= 0.5f;
      hrow[c] = fill ? hsum / std::max(wsum, 0.5f) : hrow[c];
      srow[c] = static_cast<std::uint8_t>(vrow[c] | (fill ? 1u : 0u));
    }
  }
}

cv::Mat HeightGrid::heightImage() const {
  cv::Mat img(geometry_.rows, geometry_.cols, CV_32F);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int r = 0; r < geometry_.rows; ++r) {
    float* row = img.ptr<float>(r);
    for (int c = 0; c < geometry_.cols; ++c) {
      row[c] = isValid(r, c) ? height(r, c) : nan;
    }
  }
  return img;
}

}  // namespace dlo
