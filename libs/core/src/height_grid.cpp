#include "dlo/core/height_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace dlo {

HeightGrid HeightGrid::fromPoints(const PointCloud& points, const GridGeometry& geometry,
                                  int min_points, double min_z, double max_z) {
  HeightGrid g;
  g.rasterise(points, geometry, min_points, min_z, max_z);
  return g;
}

namespace {

/// Bins points into `count` and `sum` in one pass. `get(items, i, p, n)` yields item i as a point
/// in the grid frame and how many raw points it stands for; written so that NaN fails every
/// comparison.
template <typename Range, typename Get>
void accumulate(const Range& items, Get get, const GridGeometry& geometry, double min_z,
                double max_z, std::uint32_t* count, float* sum) {
  const float inv_res = static_cast<float>(1.0 / geometry.resolution);
  const float x0 = static_cast<float>(geometry.x_min);
  const float y0 = static_cast<float>(geometry.y_min);
  const float cols = static_cast<float>(geometry.cols);
  const float rows = static_cast<float>(geometry.rows);
  const float zlo = static_cast<float>(min_z);
  const float zhi = static_cast<float>(max_z);
  Eigen::Vector3f p;
  std::uint32_t n = 1;
  for (size_t i = 0; i < items.size(); ++i) {
    get(items, i, p, n);
    const float u = (p.x() - x0) * inv_res;
    const float v = (p.y() - y0) * inv_res;
    if (!(u >= 0.0f && u < cols && v >= 0.0f && v < rows && p.z() >= zlo && p.z() <= zhi)) {
      continue;
    }
    const int idx = static_cast<int>(v) * geometry.cols + static_cast<int>(u);
    count[idx] += n;
    sum[idx] += static_cast<float>(n) * p.z();
  }
}

}  // namespace

void HeightGrid::rasterise(const PointCloud& points, const GridGeometry& geometry, int min_points,
                           double min_z, double max_z) {
  rasterise(points, SweepMotion(), geometry, min_points, min_z, max_z);
}

void HeightGrid::rasterise(const PointCloud& points, const SweepMotion& motion,
                           const GridGeometry& geometry, int min_points, double min_z,
                           double max_z) {
  geometry_ = geometry;
  min_points_ = min_points;
  count_.assign(geometry.cellCount(), 0u);
  sum_z_.assign(geometry.cellCount(), 0.0f);
  if (motion.fits(points.size())) {
    accumulate(
        points,
        [&motion](const PointCloud& c, size_t i, Eigen::Vector3f& p, std::uint32_t&) {
          p = motion.apply(i, c[i]);
        },
        geometry, min_z, max_z, count_.data(), sum_z_.data());
  } else {
    accumulate(
        points, [](const PointCloud& c, size_t i, Eigen::Vector3f& p, std::uint32_t&) { p = c[i]; },
        geometry, min_z, max_z, count_.data(), sum_z_.data());
  }
  finalise();
}

void HeightGrid::rasterise(const WeightedCloud& points, const Eigen::Isometry3d& pose,
                           const GridGeometry& geometry, int min_points, double min_z,
                           double max_z) {
  rasterise(std::vector<PosedCloud>{PosedCloud{&points, pose}}, geometry, min_points, min_z, max_z);
}

void HeightGrid::rasterise(const std::vector<PosedCloud>& parts, const GridGeometry& geometry,
                           int min_points, double min_z, double max_z) {
  geometry_ = geometry;
  min_points_ = min_points;
  count_.assign(geometry.cellCount(), 0u);
  sum_z_.assign(geometry.cellCount(), 0.0f);
  for (const PosedCloud& part : parts) {
    const Eigen::Isometry3f T = part.pose.cast<float>();
    accumulate(
        *part.cloud,
        [&T](const WeightedCloud& c, size_t i, Eigen::Vector3f& p, std::uint32_t& n) {
          p = T * c[i].p;
          n = c[i].n;
        },
        geometry, min_z, max_z, count_.data(), sum_z_.data());
  }
  finalise();
}

void HeightGrid::accumulateCells(const GridGeometry& geometry, int min_points,
                                 const CellFiller& fill) {
  geometry_ = geometry;
  min_points_ = min_points;
  count_.assign(geometry.cellCount(), 0u);
  sum_z_.assign(geometry.cellCount(), 0.0f);
  fill(count_.data(), sum_z_.data());
  finalise();
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
  for (int i = 0;
       i < n && i < static_cast<int>(mean_heights.size()) && i < static_cast<int>(counts.size());
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
  g.poolFrom(*this);
  return g;
}

void HeightGrid::poolFrom(const HeightGrid& finer) {
  HeightGrid& g = *this;
  g.geometry_ = finer.geometry_.coarser();
  g.min_points_ = finer.min_points_;
  const int n = g.geometry_.cellCount();
  g.count_.assign(n, 0u);
  g.sum_z_.assign(n, 0.0f);
  const int cols = finer.geometry_.cols;
  for (int r = 0; r < finer.geometry_.rows; ++r) {
    const int cr = (r / 2) * g.geometry_.cols;
    const std::uint32_t* cnt = &finer.count_[r * cols];
    const float* sum = &finer.sum_z_[r * cols];
    std::uint32_t* gc = &g.count_[cr];
    float* gs = &g.sum_z_[cr];
    const int pairs = cols / 2;
    for (int j = 0; j < pairs; ++j) {
      gc[j] += cnt[2 * j] + cnt[2 * j + 1];
      gs[j] += sum[2 * j] + sum[2 * j + 1];
    }
    if (cols % 2 != 0) {
      gc[pairs] += cnt[cols - 1];
      gs[pairs] += sum[cols - 1];
    }
  }
  g.finalise();
}

void HeightGrid::finalise() {
  const int n = geometry_.cellCount();
  height_.resize(n);
  valid_.resize(n);
  // Signed counts throughout: SSE2 converts and compares signed integers in one instruction,
  // unsigned ones not (a cell never holds 2^31 points). Raw restrict pointers and one output
  // type per loop, so that both loops vectorise.
  const std::int32_t need = std::max(min_points_, 1);
  const std::int32_t* __restrict__ cnt = reinterpret_cast<const std::int32_t*>(count_.data());
  const float* __restrict__ sum = sum_z_.data();
  float* __restrict__ height = height_.data();
  std::uint8_t* __restrict__ valid = valid_.data();
  for (int i = 0; i < n; ++i) {
    // Divided unconditionally, by 1 where the cell is invalid, and masked by a product, all
    // with integer masks: the compiler does not speculate a division (it might trap), and
    // turns any conditional it can see back into a branch around it, which keeps the loop
    // scalar. "+ 0.0f" turns -0 into 0.
    const std::int32_t ok = -static_cast<std::int32_t>(cnt[i] >= need);  // all ones if valid
    const float mean = sum[i] / static_cast<float>((cnt[i] & ok) | (1 & ~ok));
    height[i] = static_cast<float>(ok & 1) * mean + 0.0f;
  }
  int valid_cells = 0;
  for (int i = 0; i < n; ++i) {
    valid[i] = cnt[i] >= need ? 1u : 0u;
    valid_cells += valid[i];
  }
  valid_cells_ = valid_cells;
  support_ = valid_;
}

void HeightGrid::preparePull(PullSource& out) const {
  const GridGeometry& g = geometry_;
  out.geometry = g;
  out.cols = g.cols + 2;
  const size_t padded_rows = static_cast<size_t>(g.rows) + 2;
  out.support.resize(static_cast<size_t>(out.cols) * padded_rows);
  out.height.resize(out.support.size());
  float* __restrict__ s = out.support.data();
  float* __restrict__ h = out.height.data();
  // Only the border is zeroed separately; the interior is written branch-free.
  std::fill_n(s, out.cols, 0.0f);
  std::fill_n(h, out.cols, 0.0f);
  std::fill_n(s + (padded_rows - 1) * out.cols, out.cols, 0.0f);
  std::fill_n(h + (padded_rows - 1) * out.cols, out.cols, 0.0f);
  for (int r = 0; r < g.rows; ++r) {
    const std::uint8_t* __restrict__ sup = support_.data() + r * g.cols;
    const float* __restrict__ hr = height_.data() + r * g.cols;
    float* __restrict__ srow = s + (r + 1) * out.cols;
    float* __restrict__ hrow = h + (r + 1) * out.cols;
    srow[0] = hrow[0] = srow[g.cols + 1] = hrow[g.cols + 1] = 0.0f;
    for (int c = 0; c < g.cols; ++c) {
      srow[c + 1] = sup[c] ? 1.0f : 0.0f;
      hrow[c + 1] = sup[c] ? hr[c] : 0.0f;
    }
  }
}

void HeightGrid::fillHolesFrom(const HeightGrid& coarser) {
  if (!isCoarserLevel(coarser)) {
    throw std::invalid_argument("HeightGrid::fillHolesFrom needs the grid's own coarser() level");
  }
  // Scratch kept across calls: streaming frames should not hand memory back to the system.
  thread_local PullSource source;
  coarser.preparePull(source);
  const int pc = source.cols;
  thread_local std::vector<float> vs, vh;
  // A fine cell centre lies a quarter of a coarse cell from the coarse centres around it, so
  // the bilinear weights are 3/4 and 1/4; its padded coarse cell is (r+1)/2, (c+1)/2.
  // Per fine row: blend the two coarse rows around it (weights 3/4, 1/4), then blend
  // horizontally; even fine columns lie 3/4 of the way to padded coarse column c/2 + 1, odd
  // ones 1/4 of the way to it.
  vs.resize(static_cast<size_t>(pc));
  vh.resize(static_cast<size_t>(pc));
  const int half = (geometry_.cols + 1) / 2;
  thread_local std::vector<float> fill_even, fill_odd, ok_even, ok_odd;
  fill_even.resize(half);
  fill_odd.resize(half);
  ok_even.resize(half);
  ok_odd.resize(half);
  // Raw restrict pointers: the loops below then vectorise (thread_local vectors otherwise
  // force a reload of their data pointers at every iteration).
  float* __restrict__ pvs = vs.data();
  float* __restrict__ pvh = vh.data();
  float* __restrict__ fe = fill_even.data();
  float* __restrict__ fo = fill_odd.data();
  float* __restrict__ ke = ok_even.data();
  float* __restrict__ ko = ok_odd.data();
  const float* ps = source.support.data();
  const float* psh = source.height.data();
  const int cols = geometry_.cols;
  for (int r = 0; r < geometry_.rows; ++r) {
    const int pr0 = (r + 1) / 2;  // padded coarse row of the lower neighbour
    const float b = (r % 2 == 0) ? 0.75f : 0.25f;
    const float* s0 = ps + pr0 * pc;
    const float* h0 = psh + pr0 * pc;
    for (int j = 0; j < pc; ++j) {
      pvs[j] = (1 - b) * s0[j] + b * s0[j + pc];
      pvh[j] = (1 - b) * h0[j] + b * h0[j + pc];
    }
    // Fine column 2j lies 3/4 of the way from padded coarse column j to j + 1; column 2j + 1
    // 1/4 of the way from j + 1 to j + 2. Unit-stride loops, so they vectorise.
    for (int j = 0; j < half; ++j) {
      const float we = 0.25f * pvs[j] + 0.75f * pvs[j + 1];
      const float wo = 0.75f * pvs[j + 1] + 0.25f * pvs[j + 2];
      fe[j] = (0.25f * pvh[j] + 0.75f * pvh[j + 1]) / std::max(we, 0.5f);
      fo[j] = (0.75f * pvh[j + 1] + 0.25f * pvh[j + 2]) / std::max(wo, 0.5f);
      // Require most of the interpolation weight: no extrapolation far from data.
      ke[j] = we >= 0.5f ? 1.0f : 0.0f;
      ko[j] = wo >= 0.5f ? 1.0f : 0.0f;
    }
    float* __restrict__ hrow = height_.data() + r * cols;
    const std::uint8_t* __restrict__ vrow = valid_.data() + r * cols;
    std::uint8_t* __restrict__ srow = support_.data() + r * cols;
    for (int j = 0; j < cols / 2; ++j) {
      const int c = 2 * j;
      const bool fill0 = !vrow[c] && ke[j] != 0.0f;
      const bool fill1 = !vrow[c + 1] && ko[j] != 0.0f;
      hrow[c] = fill0 ? fe[j] : hrow[c];
      hrow[c + 1] = fill1 ? fo[j] : hrow[c + 1];
      srow[c] = static_cast<std::uint8_t>(vrow[c] | (fill0 ? 1u : 0u));
      srow[c + 1] = static_cast<std::uint8_t>(vrow[c + 1] | (fill1 ? 1u : 0u));
    }
    if (cols % 2 != 0) {
      const int c = cols - 1;
      const bool fill = !vrow[c] && ke[c / 2] != 0.0f;
      hrow[c] = fill ? fe[c / 2] : hrow[c];
      srow[c] = static_cast<std::uint8_t>(vrow[c] | (fill ? 1u : 0u));
    }
  }
}

bool HeightGrid::isCoarserLevel(const HeightGrid& coarser) const {
  const GridGeometry& cg = coarser.geometry_;
  return cg.cols == (geometry_.cols + 1) / 2 && cg.rows == (geometry_.rows + 1) / 2 &&
         std::abs(cg.resolution - 2.0 * geometry_.resolution) <= 1e-9 * cg.resolution &&
         std::abs(cg.x_min - geometry_.x_min) <= 1e-6 &&
         std::abs(cg.y_min - geometry_.y_min) <= 1e-6;
}

bool HeightGrid::pulledHeight(int row, int col, const PullSource& source, float& h) const {
  if (support_[index(row, col)]) {
    h = height_[index(row, col)];
    return true;
  }
  // fillHolesFrom() for one cell, with the same operations in the same order so that both
  // give the same float: blend the two padded coarse rows around the fine row, then two of
  // those column blends.
  const int pc = source.cols;
  const int pr0 = (row + 1) / 2;
  const float b = (row % 2 == 0) ? 0.75f : 0.25f;
  const float* s0 = source.support.data() + pr0 * pc;
  const float* h0 = source.height.data() + pr0 * pc;
  auto vs = [&](int j) { return (1 - b) * s0[j] + b * s0[j + pc]; };
  auto vh = [&](int j) { return (1 - b) * h0[j] + b * h0[j + pc]; };
  // Fine column col lies between padded coarse columns a and a + 1: 3/4 of the way for an even
  // column, 1/4 for an odd one. Chosen without a branch: the parity of neighbouring cells is
  // as good as random for a branch predictor.
  const int a = (col + 1) / 2;
  const float wl = (col & 1) != 0 ? 0.75f : 0.25f;
  const float wr = 1.0f - wl;  // exact: 0.25 or 0.75
  const float w = wl * vs(a) + wr * vs(a + 1);
  const float sum = wl * vh(a) + wr * vh(a + 1);
  h = sum / std::max(w, 0.5f);
  return w >= 0.5f;
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
