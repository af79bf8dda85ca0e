#include "dlo/core/height_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "simd/height_grid_kernels.h"

namespace dlo {

HeightGrid HeightGrid::fromPoints(const PointCloud& points, const GridGeometry& geometry,
                                  int min_points, double min_z, double max_z) {
  HeightGrid g;
  g.rasterise(points, geometry, min_points, min_z, max_z);
  return g;
}

namespace {

/// Cells after the grid's own that rasterisation sends rejected points to (see
/// simd::CellMapping).
constexpr size_t kDiscardCells = simd::kDiscardCells;

/// The arithmetic half of rasterisation, kept apart from the scatter into cells so that it
/// vectorises: which cell each point falls in and its height, for points mapped by a row-major
/// 3 x 4 pose [R | t]. The widest kernel the processor has maps what it can, the next one what
/// remains, and the scalar reference (simd/height_grid_scalar.cpp) the last few points; all of
/// them give the same cells bit for bit.
class CellMapper {
 public:
  CellMapper(const GridGeometry& geometry, double min_z, double max_z)
      : cells_(geometry, min_z, max_z) {}

  /// Cell index and height of p[0..n) mapped by `m`, into idx[0..n) and z[0..n), and where
  /// in their cells they fell into f (unless its pointers are null).
  void map(const Eigen::Vector3f* p, size_t n, const RowMajorPose& m, int* idx, float* z,
           simd::CellFractions f) const {
    size_t k = 0;
#ifdef DLO_SIMD_AVX2_DISPATCH
    if (simd::hasAvx2()) k = simd::mapPointsAvx2(cells_, p, k, n, m, idx, z, f);
#endif
#ifdef __SSE2__
    k = simd::mapPointsSse2(cells_, p, k, n, m, idx, z, f);
#endif
    simd::mapPointsScalar(cells_, p, k, n, m, idx, z, f);
  }

  /// The same for weighted points; their weights go to w[0..n).
  void map(const WeightedPoint* p, size_t n, const RowMajorPose& m, int* idx, float* z,
           std::uint32_t* w, simd::CellFractions f) const {
    size_t k = 0;
#ifdef DLO_SIMD_AVX2_DISPATCH
    if (simd::hasAvx2()) k = simd::mapWeightedAvx2(cells_, p, k, n, m, idx, z, w, f);
#endif
#ifdef __SSE2__
    k = simd::mapWeightedSse2(cells_, p, k, n, m, idx, z, w, f);
#endif
    simd::mapWeightedScalar(cells_, p, k, n, m, idx, z, w, f);
  }

 private:
  simd::CellMapping cells_;
};

/// Where the run of points in time bin bin[k] ends, from k + 1 on.
size_t binRunEnd(const int* bin, size_t k, size_t n) {
  size_t end = k + 1;
#ifdef __SSE2__
  end = simd::binRunEndSse2(bin, k, end, n);
#endif
  return simd::binRunEndScalar(bin, k, end, n);
}

/// Points are mapped in batches of this many: small enough for the stack and the L1 cache.
constexpr size_t kBatch = 256;

/// Where rasterisation adds its points: counts and height sums per cell, and with
/// `sum_uv` (not null) the sums of where in their cells the points fell, u and v of a cell side
/// by side (HeightGrid::centroidSums()): one cache line for both.
struct CellTargets {
  std::uint32_t* count;
  float* sum;
  float* sum_uv;
};

/// Rasterises a sweep, deskewed by `motion` if it fits, in batches: the cells of a batch are
/// computed first (vectorised, one pose per run of points in the same time bin; a sweep in
/// firing order has runs of hundreds of points), then scattered into `to`.
template <bool kFractions>
void rasteriseSweep(const PointCloud& points, const SweepMotion& motion,
                    const GridGeometry& geometry, double min_z, double max_z,
                    const CellTargets& to) {
  const CellMapper mapper(geometry, min_z, max_z);
  const bool moving = motion.fits(points.size());
  const RowMajorPose identity;
  int idx[kBatch];
  float z[kBatch];
  float fu[kBatch];
  float fv[kBatch];
  int bin[kBatch];
  simd::CellFractions f;
  if constexpr (kFractions) f = simd::CellFractions{fu, fv};
  for (size_t first = 0; first < points.size(); first += kBatch) {
    const size_t n = std::min(kBatch, points.size() - first);
    const Eigen::Vector3f* p = points.data() + first;
    if (!moving) {
      mapper.map(p, n, identity, idx, z, f);
    } else {
      motion.bins(motion.times().data() + first, n, bin);
      for (size_t k = 0; k < n;) {
        const size_t end = binRunEnd(bin, k, n);
        simd::CellFractions at;
        if constexpr (kFractions) at = simd::CellFractions{fu + k, fv + k};
        mapper.map(p + k, end - k, motion.pose(bin[k]), idx + k, z + k, at);
        k = end;
      }
    }
    for (size_t k = 0; k < n; ++k) {
      to.count[idx[k]] += 1;
      to.sum[idx[k]] += z[k];
      if constexpr (kFractions) {
        float* uv = to.sum_uv + 2 * static_cast<size_t>(idx[k]);
        uv[0] += fu[k];
        uv[1] += fv[k];
      }
    }
  }
}

/// Rasterises weighted points seen from `pose`, in batches as sweeps.
template <bool kFractions>
void rasteriseWeighted(const WeightedCloud& points, const Eigen::Isometry3d& pose,
                       const GridGeometry& geometry, double min_z, double max_z,
                       const CellTargets& to) {
  const RowMajorPose m(pose.cast<float>());
  const CellMapper mapper(geometry, min_z, max_z);
  int idx[kBatch];
  float z[kBatch];
  float fu[kBatch];
  float fv[kBatch];
  std::uint32_t w[kBatch];
  simd::CellFractions f;
  if constexpr (kFractions) f = simd::CellFractions{fu, fv};
  for (size_t first = 0; first < points.size(); first += kBatch) {
    const size_t n = std::min(kBatch, points.size() - first);
    mapper.map(points.data() + first, n, m, idx, z, w, f);
    for (size_t k = 0; k < n; ++k) {
      const float wk = static_cast<float>(w[k]);
      to.count[idx[k]] += w[k];
      to.sum[idx[k]] += wk * z[k];
      if constexpr (kFractions) {
        float* uv = to.sum_uv + 2 * static_cast<size_t>(idx[k]);
        uv[0] += wk * fu[k];
        uv[1] += wk * fv[k];
      }
    }
  }
}

}  // namespace

void HeightGrid::rasterise(const PointCloud& points, const GridGeometry& geometry, int min_points,
                           double min_z, double max_z) {
  rasterise(points, SweepMotion(), geometry, min_points, min_z, max_z);
}

void HeightGrid::rasterise(const PointCloud& points, const SweepMotion& motion,
                           const GridGeometry& geometry, int min_points, double min_z, double max_z,
                           HeightGrid* coarser) {
  geometry_ = geometry;
  min_points_ = min_points;
  clearSums(keep_centroids_);
  const CellTargets to{count_.data(), sum_z_.data(), sum_uv_.data()};
  if (keep_centroids_) {
    rasteriseSweep<true>(points, motion, geometry, min_z, max_z, to);
  } else {
    rasteriseSweep<false>(points, motion, geometry, min_z, max_z, to);
  }
  finalise(coarser);
}

void HeightGrid::rasterise(const WeightedCloud& points, const Eigen::Isometry3d& pose,
                           const GridGeometry& geometry, int min_points, double min_z,
                           double max_z) {
  rasterise(std::vector<PosedCloud>{PosedCloud{&points, pose}}, geometry, min_points, min_z, max_z);
}

void HeightGrid::rasterise(const std::vector<PosedCloud>& parts, const GridGeometry& geometry,
                           int min_points, double min_z, double max_z, HeightGrid* coarser) {
  geometry_ = geometry;
  min_points_ = min_points;
  clearSums(keep_centroids_);
  const CellTargets to{count_.data(), sum_z_.data(), sum_uv_.data()};
  for (const PosedCloud& part : parts) {
    if (keep_centroids_) {
      rasteriseWeighted<true>(*part.cloud, part.pose, geometry, min_z, max_z, to);
    } else {
      rasteriseWeighted<false>(*part.cloud, part.pose, geometry, min_z, max_z, to);
    }
  }
  finalise(coarser);
}

void HeightGrid::accumulateCells(const GridGeometry& geometry, int min_points,
                                 const CellFiller& fill, HeightGrid* coarser) {
  geometry_ = geometry;
  min_points_ = min_points;
  clearSums();
  fill(count_.data(), sum_z_.data());
  finalise(coarser);
}

HeightGrid HeightGrid::fromCells(const GridGeometry& geometry,
                                 const std::vector<float>& mean_heights,
                                 const std::vector<std::uint32_t>& counts, int min_points) {
  HeightGrid g;
  g.geometry_ = geometry;
  g.min_points_ = min_points;
  const int n = geometry.cellCount();
  g.clearSums();
  for (int i = 0;
       i < n && i < static_cast<int>(mean_heights.size()) && i < static_cast<int>(counts.size());
       ++i) {
    if (!std::isfinite(mean_heights[i])) continue;
    g.count_[i] = counts[i];
    g.sum_z_[i] = mean_heights[i] * static_cast<float>(counts[i]);
  }
  g.finalise(nullptr);
  return g;
}

HeightGrid HeightGrid::coarser() const {
  HeightGrid g;
  g.poolFrom(*this);
  return g;
}

void HeightGrid::startPooling(const HeightGrid& finer) {
  geometry_ = finer.geometry_.coarser();
  min_points_ = finer.min_points_;
  clearSums();
}

void HeightGrid::poolFrom(const HeightGrid& finer) {
  HeightGrid& g = *this;
  g.startPooling(finer);
  const int cols = finer.geometry_.cols;
  for (int r = 0; r < finer.geometry_.rows; ++r) {
    const size_t coarse_at = static_cast<size_t>(r / 2) * g.geometry_.cols;
    const size_t at = static_cast<size_t>(r) * cols;
    simd::poolPairs(finer.count_.data() + at, finer.sum_z_.data() + at, 0, cols,
                    simd::PoolRow{g.count_.data() + coarse_at, g.sum_z_.data() + coarse_at});
  }
  g.finalise(nullptr);
}

void HeightGrid::clearSums(bool centroids) {
  const size_t n = static_cast<size_t>(geometry_.cellCount()) + kDiscardCells;
  count_.assign(n, 0u);
  sum_z_.assign(n, 0.0f);
  // clear() keeps the memory for the next frame that wants them.
  sum_uv_.clear();
  if (centroids) sum_uv_.assign(2 * n, 0.0f);
}

namespace {

/// Heights and valid flags of n cells from their counts and sums, and the number of valid ones;
/// with `pool` (n cells of one fine row), each pair of cells is also added into the coarse row
/// as HeightGrid::poolFrom() adds it.
int finaliseCells(const std::int32_t* cnt, const float* sum, int n, std::int32_t need,
                  float* height, std::uint8_t* valid, const simd::PoolRow* pool) {
  const simd::CellSums cells{cnt, sum, n, need, height, valid, pool};
  int valid_cells = 0;
  int i = 0;
#ifdef __SSE2__
  i = simd::finaliseCellsSse2(cells, i, valid_cells);
#endif
  simd::finaliseCellsScalar(cells, i, valid_cells);
  return valid_cells;
}

}  // namespace

void HeightGrid::finalise(HeightGrid* coarser) {
  const int n = geometry_.cellCount();
  height_.resize(n);
  valid_.resize(n);
  const std::int32_t need = std::max(min_points_, 1);
  const std::int32_t* cnt = reinterpret_cast<const std::int32_t*>(count_.data());
  if (coarser == nullptr) {
    valid_cells_ =
        finaliseCells(cnt, sum_z_.data(), n, need, height_.data(), valid_.data(), nullptr);
  } else {
    // Row by row, each row's pairs added into the coarse row while its cells are at hand: the
    // same sums in the same order as coarser->poolFrom(*this), without reading the counts and
    // sums (two megabytes at 400 x 400) a second time.
    coarser->startPooling(*this);
    const int cols = geometry_.cols;
    const int coarse_cols = coarser->geometry_.cols;
    int valid_cells = 0;
    for (int r = 0; r < geometry_.rows; ++r) {
      const size_t at = static_cast<size_t>(r) * cols;
      const size_t coarse_at = static_cast<size_t>(r / 2) * coarse_cols;
      const simd::PoolRow pool{coarser->count_.data() + coarse_at,
                               coarser->sum_z_.data() + coarse_at};
      valid_cells += finaliseCells(cnt + at, sum_z_.data() + at, cols, need, height_.data() + at,
                                   valid_.data() + at, &pool);
    }
    valid_cells_ = valid_cells;
    coarser->finalise(nullptr);
  }
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
    // Arithmetic, to vectorise: a cell without support has height 0 (finalise() and
    // fillHolesFrom() leave it so), and 1 * h is h exactly.
    for (int c = 0; c < g.cols; ++c) {
      const float sc = static_cast<float>(sup[c]);
      srow[c + 1] = sc;
      hrow[c + 1] = sc * hr[c];
    }
  }
}

namespace {

/// The coarse level's interpolation for the cells of fine row `row` (`cols` cells) in columns
/// [2 j0, 2 j1), j0 a multiple of 4, measured or not: value[c] = sum(w*s*h) / max(sum(w*s), 1/2)
/// and ok[c] = 1 where sum(w*s) >= 1/2 (most of the interpolation weight is supported: no
/// extrapolation far from data), else 0. Both are indexed by fine column and point into
/// `scratch`, valid until its next use; whole vectors are computed, so a few columns past 2 j1
/// are written too. The same operations in the same order for every cell, vectorised four
/// coarse columns (eight fine cells) at a time.
struct InterpolatedRow {
  const float* value;
  const float* ok;
};
InterpolatedRow interpolateRow(const PullSource& source, int row, int cols, int j0, int j1,
                               std::vector<float>& scratch) {
  const int pc = source.cols;
  const int half = (cols + 1) / 2;  // coarse columns; pc == half + 2
  const int blocks = (half + 3) / 4;
  // Vertical blends (padded to whole vectors, with zeros) and the fine row's values and flags.
  const size_t blend = static_cast<size_t>(pc) + 8;
  const size_t fine = static_cast<size_t>(blocks) * 8;
  scratch.resize(2 * blend + 2 * fine);
  float* __restrict__ vs = scratch.data();
  float* __restrict__ vh = vs + blend;
  float* __restrict__ value = vh + blend;
  float* __restrict__ ok = value + fine;
  // Coarse pairs j0 .. j_end - 1 in whole vectors; they read blends j0 .. j_end + 1.
  const int j_end = j0 + 4 * ((j1 - j0 + 3) / 4);
  const int blend_end = std::min(pc, j_end + 2);
  // A fine cell centre lies a quarter of a coarse cell from the coarse centres around it, so
  // the bilinear weights are 3/4 and 1/4; its padded coarse cell is (r+1)/2, (c+1)/2. First the
  // two padded coarse rows around the fine row are blended.
  const int pr0 = (row + 1) / 2;
  const float b = (row % 2 == 0) ? 0.75f : 0.25f;
  const float* __restrict__ s0 = source.support.data() + static_cast<size_t>(pr0) * pc;
  const float* __restrict__ h0 = source.height.data() + static_cast<size_t>(pr0) * pc;
  for (int j = j0; j < blend_end; ++j) {
    vs[j] = (1 - b) * s0[j] + b * s0[j + pc];
    vh[j] = (1 - b) * h0[j] + b * h0[j + pc];
  }
  for (int j = blend_end; j < j_end + 2; ++j) vs[j] = vh[j] = 0.0f;  // past the padded row
  // Then horizontally: fine column 2j lies 3/4 of the way from padded coarse column j to j + 1,
  // column 2j + 1 1/4 of the way from j + 1 to j + 2.
  int j = j0;
#ifdef __SSE2__
  j = simd::pullColumnsSse2(vs, vh, j, j_end, value, ok);
#endif
  simd::pullColumnsScalar(vs, vh, j, j_end, value, ok);
  return InterpolatedRow{value, ok};
}

}  // namespace

void HeightGrid::fillHolesFrom(const HeightGrid& coarser) {
  if (!isCoarserLevel(coarser)) {
    throw std::invalid_argument("HeightGrid::fillHolesFrom needs the grid's own coarser() level");
  }
  // Scratch kept across calls: streaming frames should not hand memory back to the system.
  thread_local PullSource source_scratch;
  thread_local std::vector<float> row_scratch;
  PullSource& source = source_scratch;
  std::vector<float>& scratch = row_scratch;
  coarser.preparePull(source);
  const int cols = geometry_.cols;
  for (int r = 0; r < geometry_.rows; ++r) {
    const InterpolatedRow pulled = interpolateRow(source, r, cols, 0, (cols + 1) / 2, scratch);
    const float* __restrict__ value = pulled.value;
    const float* __restrict__ ok = pulled.ok;
    float* __restrict__ hrow = height_.data() + static_cast<size_t>(r) * cols;
    const std::uint8_t* __restrict__ vrow = valid_.data() + static_cast<size_t>(r) * cols;
    std::uint8_t* __restrict__ srow = support_.data() + static_cast<size_t>(r) * cols;
    // Arithmetic rather than conditionals, so that the loop vectorises: measured cells (v = 1)
    // keep their height exactly (h + 0 * value), the others (height 0) take the pulled one
    // where `ok`.
    for (int c = 0; c < cols; ++c) {
      const float v = static_cast<float>(vrow[c]);
      hrow[c] = v * hrow[c] + (1.0f - v) * ok[c] * value[c];
      srow[c] = static_cast<std::uint8_t>(v + (1.0f - v) * ok[c]);
    }
  }
}

void HeightGrid::pulledRow(int row, const PullSource* source, float* height, float* has,
                           std::vector<float>& scratch, int first, int end) const {
  const int cols = geometry_.cols;
  first = std::max(first, 0);
  end = end < 0 ? cols : std::min(end, cols);
  if (first >= end) return;
  const float* __restrict__ own = height_.data() + static_cast<size_t>(row) * cols;
  const std::uint8_t* __restrict__ sup = support_.data() + static_cast<size_t>(row) * cols;
  if (source == nullptr) {
    for (int c = first; c < end; ++c) {
      has[c] = static_cast<float>(sup[c]);
      height[c] = has[c] * own[c];
    }
    return;
  }
  // Coarse pairs from a multiple of four (whole vectors) to the one holding column end - 1.
  const InterpolatedRow pulled =
      interpolateRow(*source, row, cols, (first / 2) & ~3, (end + 1) / 2, scratch);
  const float* __restrict__ value = pulled.value;
  const float* __restrict__ ok = pulled.ok;
  // Arithmetic, to vectorise: a supported cell keeps its height exactly (s * own + 0 * value).
  for (int c = first; c < end; ++c) {
    const float s = static_cast<float>(sup[c]);
    height[c] = s * own[c] + (1.0f - s) * value[c];
    has[c] = s + (1.0f - s) * ok[c];
  }
}

bool HeightGrid::isCoarserLevel(const HeightGrid& coarser) const {
  const GridGeometry& cg = coarser.geometry_;
  return cg.cols == (geometry_.cols + 1) / 2 && cg.rows == (geometry_.rows + 1) / 2 &&
         std::abs(cg.resolution - 2.0 * geometry_.resolution) <= 1e-9 * cg.resolution &&
         std::abs(cg.x_min - geometry_.x_min) <= 1e-6 &&
         std::abs(cg.y_min - geometry_.y_min) <= 1e-6;
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

namespace {

/// Sum of one byte per 64-byte cache line of `v`.
template <typename T>
std::uint32_t touchLines(const std::vector<T>& v) {
  const unsigned char* p = reinterpret_cast<const unsigned char*>(v.data());
  const size_t bytes = v.size() * sizeof(T);
  std::uint32_t acc = 0;
  for (size_t i = 0; i < bytes; i += 64) acc += p[i];
  return acc;
}

}  // namespace

void HeightGrid::warmCaches() const {
  // Through a volatile, or the compiler drops the reads.
  volatile std::uint32_t sink = touchLines(count_) + touchLines(sum_z_) + touchLines(height_) +
                                touchLines(valid_) + touchLines(support_);
  (void)sink;
}

}  // namespace dlo
