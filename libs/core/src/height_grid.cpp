#include "dlo/core/height_grid.h"

#include <cmath>
#include <limits>

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
  height_.assign(n, 0.0f);
  valid_.assign(n, 0u);
  valid_cells_ = 0;
  const std::uint32_t need = static_cast<std::uint32_t>(min_points_ < 1 ? 1 : min_points_);
  for (int i = 0; i < n; ++i) {
    if (count_[i] >= need) {
      height_[i] = sum_z_[i] / static_cast<float>(count_[i]);
      valid_[i] = 1u;
      ++valid_cells_;
    }
  }
  support_ = valid_;
}

void HeightGrid::fillHolesFrom(const HeightGrid& coarser) {
  const GridGeometry& cg = coarser.geometry_;
  const int ccols = cg.cols;
  for (int r = 0; r < geometry_.rows; ++r) {
    // Fine cell centre in coarse continuous coordinates, shifted to coarse cell centres.
    const double v = cg.v(geometry_.cellCentreY(r)) - 0.5;
    const int r0 = static_cast<int>(std::floor(v));
    const float b = static_cast<float>(v - r0);
    for (int c = 0; c < geometry_.cols; ++c) {
      const int i = index(r, c);
      if (valid_[i]) continue;
      const double u = cg.u(geometry_.cellCentreX(c)) - 0.5;
      const int c0 = static_cast<int>(std::floor(u));
      const float a = static_cast<float>(u - c0);
      float wsum = 0.0f, hsum = 0.0f;
      const float w[4] = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
      const int rr[4] = {r0, r0, r0 + 1, r0 + 1};
      const int cc[4] = {c0, c0 + 1, c0, c0 + 1};
      for (int k = 0; k < 4; ++k) {
        if (rr[k] < 0 || cc[k] < 0 || rr[k] >= cg.rows || cc[k] >= ccols) continue;
        const int j = rr[k] * ccols + cc[k];
        if (!coarser.support_[j] || w[k] <= 0.0f) continue;
        wsum += w[k];
        hsum += w[k] * coarser.height_[j];
      }
      // Require most of the interpolation weight: no extrapolation far from data.
      if (wsum >= 0.5f) {
        height_[i] = hsum / wsum;
        support_[i] = 1u;
      }
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
