#include "dlo/core/height_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#ifdef __SSE2__
#include <emmintrin.h>
#endif
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
/// Wider vector code chosen at run time (the build targets plain x86-64, which has SSE2 only).
#define DLO_X86_DISPATCH 1
#endif

namespace dlo {

HeightGrid HeightGrid::fromPoints(const PointCloud& points, const GridGeometry& geometry,
                                  int min_points, double min_z, double max_z) {
  HeightGrid g;
  g.rasterise(points, geometry, min_points, min_z, max_z);
  return g;
}

namespace {

/// Cells after the grid's own that rasterisation sends rejected points to (see CellMapper).
constexpr size_t kDiscardCells = 4;

#ifdef DLO_X86_DISPATCH
/// Whether this processor has AVX2, asked once.
bool hasAvx2() {
  static const bool has = __builtin_cpu_supports("avx2") != 0;
  return has;
}
#endif

/// The arithmetic half of rasterisation, kept apart from the scatter into cells so that it
/// vectorises: which cell each point falls in and its height, for points mapped by a row-major
/// 3 x 4 pose [R | t]. Points outside the grid or the height band (NaN fails every comparison)
/// go to discard cells after the grid's cells, so that the scatter has no branch on data:
/// which points fall outside is as good as random along a sweep (near and far rings
/// interleave), and mispredicting it cost more than the rest of the loop. There are
/// kDiscardCells of them, point k going to number k % kDiscardCells: with a single one, the
/// sixth of an HDL-64 sweep beyond the grid made one chain of dependent additions to the same
/// address.
class CellMapper {
 public:
  CellMapper(const GridGeometry& geometry, double min_z, double max_z)
      : inv_res_(static_cast<float>(1.0 / geometry.resolution)),
        x0_(static_cast<float>(geometry.x_min)),
        y0_(static_cast<float>(geometry.y_min)),
        cols_(static_cast<float>(geometry.cols)),
        rows_(static_cast<float>(geometry.rows)),
        zlo_(static_cast<float>(min_z)),
        zhi_(static_cast<float>(max_z)),
        grid_cols_(geometry.cols),
        discard_(geometry.cellCount()) {}

  /// Cell index and height of p[0..n) mapped by `m`, into idx[0..n) and z[0..n).
  void map(const Eigen::Vector3f* p, size_t n, const RowMajorPose& m, int* __restrict__ idx,
           float* __restrict__ z) const {
    const float* __restrict__ q = p->data();
    size_t k = 0;
#ifdef DLO_X86_DISPATCH
    if (hasAvx2()) k = map8(q, n, m, idx, z);
#endif
#ifdef __SSE2__
    const Pose4 pose(m);
    for (; k + 4 <= n; k += 4) {
      // The sweep is read once, front to back; fetched a batch ahead, its loads stopped
      // stalling the loop (rasterisation 0.54 -> 0.42 ms per HDL-64 sweep).
      _mm_prefetch(reinterpret_cast<const char*>(q + 3 * k + 768), _MM_HINT_T0);
      // a = x0 y0 z0 x1, b = y1 z1 x2 y2, c = z2 x3 y3 z3: deinterleave into x, y, z.
      const __m128 a = _mm_loadu_ps(q + 3 * k);
      const __m128 b = _mm_loadu_ps(q + 3 * k + 4);
      const __m128 c = _mm_loadu_ps(q + 3 * k + 8);
      const __m128 bc = _mm_shuffle_ps(b, c, _MM_SHUFFLE(1, 1, 2, 2));
      const __m128 px = _mm_shuffle_ps(a, bc, _MM_SHUFFLE(2, 0, 3, 0));
      const __m128 py =
          _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1)),
                         _mm_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3)), _MM_SHUFFLE(2, 0, 2, 0));
      const __m128 pz =
          _mm_shuffle_ps(_mm_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2)),
                         _mm_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0)), _MM_SHUFFLE(2, 0, 2, 0));
      cells4(pose, px, py, pz, idx + k, z + k);
    }
#endif
    for (; k < n; ++k) cell1(m, q[3 * k], q[3 * k + 1], q[3 * k + 2], k, idx[k], z[k]);
  }

  /// The same for weighted points; their weights go to w[0..n).
  void map(const WeightedPoint* p, size_t n, const RowMajorPose& m, int* __restrict__ idx,
           float* __restrict__ z, std::uint32_t* __restrict__ w) const {
    static_assert(sizeof(WeightedPoint) == 4 * sizeof(float), "x y z n, packed");
    const float* __restrict__ q = p->p.data();
    size_t k = 0;
#ifdef DLO_X86_DISPATCH
    if (hasAvx2()) k = map8(q, n, m, idx, z, w);
#endif
#ifdef __SSE2__
    const Pose4 pose(m);
    for (; k + 4 <= n; k += 4) {
      _mm_prefetch(reinterpret_cast<const char*>(q + 4 * k + 1024), _MM_HINT_T0);
      // Four rows of x y z n, transposed into columns.
      __m128 px = _mm_loadu_ps(q + 4 * k);
      __m128 py = _mm_loadu_ps(q + 4 * k + 4);
      __m128 pz = _mm_loadu_ps(q + 4 * k + 8);
      __m128 pn = _mm_loadu_ps(q + 4 * k + 12);
      _MM_TRANSPOSE4_PS(px, py, pz, pn);
      cells4(pose, px, py, pz, idx + k, z + k);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(w + k), _mm_castps_si128(pn));
    }
#endif
    for (; k < n; ++k) {
      cell1(m, p[k].p.x(), p[k].p.y(), p[k].p.z(), k, idx[k], z[k]);
      w[k] = p[k].n;
    }
  }

 private:
  /// One point, scalar: the reference the vector code follows operation for operation.
  void cell1(const RowMajorPose& m, float px, float py, float pz, size_t k, int& idx,
             float& z) const {
    float x, y, h;
    m.apply(px, py, pz, x, y, h);
    const float u = (x - x0_) * inv_res_;
    const float v = (y - y0_) * inv_res_;
    // NaN fails every comparison; out-of-range floats are never converted to int.
    const bool inside = u >= 0.0f && u < cols_ && v >= 0.0f && v < rows_ && h >= zlo_ && h <= zhi_;
    const int discard = discard_ + static_cast<int>(k % kDiscardCells);
    idx = inside ? static_cast<int>(v) * grid_cols_ + static_cast<int>(u) : discard;
    z = h;
  }

#ifdef __SSE2__
  /// The pose broadcast into vectors.
  struct Pose4 {
    explicit Pose4(const RowMajorPose& m) {
      for (int i = 0; i < 12; ++i) r[i] = _mm_set1_ps(m.m[i]);
    }
    __m128 r[12];
  };

  /// Four points at a time (SSE2 is part of x86-64). The compiler does not vectorise the scalar
  /// code by itself: float compares may trap, which keeps it from if-converting them, and SSE2
  /// has no 32-bit integer multiply. Same operations in the same order as cell1(), so both give
  /// the same cells.
  void cells4(const Pose4& m, __m128 px, __m128 py, __m128 pz, int* idx, float* z) const {
    const auto row = [&](int i) {
      return _mm_add_ps(_mm_add_ps(_mm_add_ps(_mm_mul_ps(m.r[i], px), _mm_mul_ps(m.r[i + 1], py)),
                                   _mm_mul_ps(m.r[i + 2], pz)),
                        m.r[i + 3]);
    };
    const __m128 x = row(0), y = row(4), h = row(8);
    const __m128 u = _mm_mul_ps(_mm_sub_ps(x, _mm_set1_ps(x0_)), _mm_set1_ps(inv_res_));
    const __m128 v = _mm_mul_ps(_mm_sub_ps(y, _mm_set1_ps(y0_)), _mm_set1_ps(inv_res_));
    const __m128 zero = _mm_setzero_ps();
    // Ordered compares: false for NaN.
    const __m128 inside = _mm_and_ps(
        _mm_and_ps(_mm_and_ps(_mm_cmpge_ps(u, zero), _mm_cmplt_ps(u, _mm_set1_ps(cols_))),
                   _mm_and_ps(_mm_cmpge_ps(v, zero), _mm_cmplt_ps(v, _mm_set1_ps(rows_)))),
        _mm_and_ps(_mm_cmpge_ps(h, _mm_set1_ps(zlo_)), _mm_cmple_ps(h, _mm_set1_ps(zhi_))));
    const __m128i col = _mm_cvttps_epi32(_mm_and_ps(inside, u));
    const __m128i r = _mm_cvttps_epi32(_mm_and_ps(inside, v));
    // r * grid_cols in 32 bits: lanes 0 and 2, then 1 and 3.
    const __m128i cols = _mm_set1_epi32(grid_cols_);
    const __m128i even = _mm_mul_epu32(r, cols);
    const __m128i odd = _mm_mul_epu32(_mm_srli_epi64(r, 32), cols);
    const __m128i prod = _mm_unpacklo_epi32(_mm_shuffle_epi32(even, _MM_SHUFFLE(0, 0, 2, 0)),
                                            _mm_shuffle_epi32(odd, _MM_SHUFFLE(0, 0, 2, 0)));
    const __m128i cell = _mm_add_epi32(prod, col);
    const __m128i in = _mm_castps_si128(inside);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(idx),
                     _mm_or_si128(_mm_and_si128(in, cell), _mm_andnot_si128(in, discard4_)));
    _mm_storeu_ps(z, h);
  }
#endif

#ifdef DLO_X86_DISPATCH
  /// Four floats at `low` and four at `high` as the two halves of one 256-bit vector.
  __attribute__((target("avx2"))) static __m256 loadHalves(const float* low, const float* high) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(low)), _mm_loadu_ps(high), 1);
  }

  /// The pose broadcast into 256-bit vectors (Pose4 for AVX2).
  struct Pose8 {
    __attribute__((target("avx2"))) explicit Pose8(const RowMajorPose& m) {
      for (int i = 0; i < 12; ++i) r[i] = _mm256_set1_ps(m.m[i]);
    }
    __m256 r[12];
  };

  /// Eight points at a time with AVX2, where the processor has it (checked at run time; the
  /// build targets plain x86-64): cells4()'s operations lane by lane, in the same order (no
  /// fused multiply-add), so both give the same cells. 256-bit shuffles work within 128-bit
  /// halves: each half deinterleaves four points exactly as cells4()'s input does. Returns how
  /// many points it mapped (a multiple of 8).
  __attribute__((target("avx2"))) size_t map8(const float* __restrict__ q, size_t n,
                                              const RowMajorPose& m, int* __restrict__ idx,
                                              float* __restrict__ z) const {
    const Pose8 pose(m);
    size_t k = 0;
    for (; k + 8 <= n; k += 8) {
      _mm_prefetch(reinterpret_cast<const char*>(q + 3 * k + 768), _MM_HINT_T0);
      const float* at = q + 3 * k;
      const __m256 a = loadHalves(at, at + 12);
      const __m256 b = loadHalves(at + 4, at + 16);
      const __m256 c = loadHalves(at + 8, at + 20);
      const __m256 bc = _mm256_shuffle_ps(b, c, _MM_SHUFFLE(1, 1, 2, 2));
      const __m256 px = _mm256_shuffle_ps(a, bc, _MM_SHUFFLE(2, 0, 3, 0));
      const __m256 py = _mm256_shuffle_ps(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(0, 0, 1, 1)),
                                          _mm256_shuffle_ps(b, c, _MM_SHUFFLE(2, 2, 3, 3)),
                                          _MM_SHUFFLE(2, 0, 2, 0));
      const __m256 pz = _mm256_shuffle_ps(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(1, 1, 2, 2)),
                                          _mm256_shuffle_ps(c, c, _MM_SHUFFLE(3, 3, 0, 0)),
                                          _MM_SHUFFLE(2, 0, 2, 0));
      cells8(pose, px, py, pz, idx + k, z + k);
    }
    return k;
  }

  /// The same for weighted points (x y z n rows, transposed eight at a time); their weights go
  /// to w.
  __attribute__((target("avx2"))) size_t map8(const float* __restrict__ q, size_t n,
                                              const RowMajorPose& m, int* __restrict__ idx,
                                              float* __restrict__ z,
                                              std::uint32_t* __restrict__ w) const {
    const Pose8 pose(m);
    size_t k = 0;
    for (; k + 8 <= n; k += 8) {
      _mm_prefetch(reinterpret_cast<const char*>(q + 4 * k + 1024), _MM_HINT_T0);
      const float* at = q + 4 * k;
      // Rows k..k+3 in the low halves, k+4..k+7 in the high ones; then _MM_TRANSPOSE4_PS in
      // each half.
      const __m256 r0 = loadHalves(at, at + 16);
      const __m256 r1 = loadHalves(at + 4, at + 20);
      const __m256 r2 = loadHalves(at + 8, at + 24);
      const __m256 r3 = loadHalves(at + 12, at + 28);
      const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpacklo_ps(r2, r3);
      const __m256 t2 = _mm256_unpackhi_ps(r0, r1), t3 = _mm256_unpackhi_ps(r2, r3);
      const __m256 px = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(1, 0, 1, 0));
      const __m256 py = _mm256_shuffle_ps(t0, t1, _MM_SHUFFLE(3, 2, 3, 2));
      const __m256 pz = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(1, 0, 1, 0));
      const __m256 pn = _mm256_shuffle_ps(t2, t3, _MM_SHUFFLE(3, 2, 3, 2));
      cells8(pose, px, py, pz, idx + k, z + k);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(w + k), _mm256_castps_si256(pn));
    }
    return k;
  }

  /// cells4() for eight points: the same operations lane by lane.
  __attribute__((target("avx2"))) void cells8(const Pose8& pose, __m256 px, __m256 py, __m256 pz,
                                              int* idx, float* z) const {
    const __m256* r = pose.r;
    // Each row of the pose summed left to right, as RowMajorPose::apply().
    const __m256 x =
        _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(r[0], px), _mm256_mul_ps(r[1], py)),
                                    _mm256_mul_ps(r[2], pz)),
                      r[3]);
    const __m256 y =
        _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(r[4], px), _mm256_mul_ps(r[5], py)),
                                    _mm256_mul_ps(r[6], pz)),
                      r[7]);
    const __m256 h =
        _mm256_add_ps(_mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(r[8], px), _mm256_mul_ps(r[9], py)),
                                    _mm256_mul_ps(r[10], pz)),
                      r[11]);
    const __m256 x0 = _mm256_set1_ps(x0_), y0 = _mm256_set1_ps(y0_), inv = _mm256_set1_ps(inv_res_);
    const __m256 zero = _mm256_setzero_ps(), cols_f = _mm256_set1_ps(cols_),
                 rows_f = _mm256_set1_ps(rows_), zlo = _mm256_set1_ps(zlo_),
                 zhi = _mm256_set1_ps(zhi_);
    const __m256i cols_i = _mm256_set1_epi32(grid_cols_);
    const __m256i discard =
        _mm256_add_epi32(_mm256_set1_epi32(discard_), _mm256_setr_epi32(0, 1, 2, 3, 0, 1, 2, 3));
    const __m256 u = _mm256_mul_ps(_mm256_sub_ps(x, x0), inv);
    const __m256 v = _mm256_mul_ps(_mm256_sub_ps(y, y0), inv);
    // Ordered compares: false for NaN.
    const __m256 inside = _mm256_and_ps(
        _mm256_and_ps(
            _mm256_and_ps(_mm256_cmp_ps(u, zero, _CMP_GE_OQ), _mm256_cmp_ps(u, cols_f, _CMP_LT_OQ)),
            _mm256_and_ps(_mm256_cmp_ps(v, zero, _CMP_GE_OQ),
                          _mm256_cmp_ps(v, rows_f, _CMP_LT_OQ))),
        _mm256_and_ps(_mm256_cmp_ps(h, zlo, _CMP_GE_OQ), _mm256_cmp_ps(h, zhi, _CMP_LE_OQ)));
    const __m256i col = _mm256_cvttps_epi32(_mm256_and_ps(inside, u));
    const __m256i rr = _mm256_cvttps_epi32(_mm256_and_ps(inside, v));
    const __m256i cell = _mm256_add_epi32(_mm256_mullo_epi32(rr, cols_i), col);
    const __m256i in = _mm256_castps_si256(inside);
    _mm256_storeu_si256(
        reinterpret_cast<__m256i*>(idx),
        _mm256_or_si256(_mm256_and_si256(in, cell), _mm256_andnot_si256(in, discard)));
    _mm256_storeu_ps(z, h);
  }
#endif

  float inv_res_, x0_, y0_, cols_, rows_, zlo_, zhi_;
  int grid_cols_, discard_;
#ifdef __SSE2__
  /// The discard cells of lanes 0..3 (a group of four starts at a multiple of four).
  __m128i discard4_ = _mm_add_epi32(_mm_set1_epi32(discard_), _mm_setr_epi32(0, 1, 2, 3));
#endif
};

/// Points are mapped in batches of this many: small enough for the stack and the L1 cache.
constexpr size_t kBatch = 256;

/// Rasterises a sweep, deskewed by `motion` if it fits, in batches: the cells of a batch are
/// computed first (vectorised, one pose per run of points in the same time bin; a sweep in
/// firing order has runs of hundreds of points), then scattered.
void rasteriseSweep(const PointCloud& points, const SweepMotion& motion,
                    const GridGeometry& geometry, double min_z, double max_z, std::uint32_t* count,
                    float* sum) {
  const CellMapper mapper(geometry, min_z, max_z);
  const bool moving = motion.fits(points.size());
  int idx[kBatch];
  float z[kBatch];
  int bin[kBatch];
  for (size_t first = 0; first < points.size(); first += kBatch) {
    const size_t n = std::min(kBatch, points.size() - first);
    const Eigen::Vector3f* p = points.data() + first;
    if (!moving) {
      mapper.map(p, n, RowMajorPose(), idx, z);
    } else {
      const float* t = motion.times().data() + first;
      motion.bins(t, n, bin);
      for (size_t k = 0; k < n;) {
        size_t end = k + 1;
#ifdef __SSE2__
        // Runs are hundreds of points long: compared four bins at a time.
        const __m128i same = _mm_set1_epi32(bin[k]);
        while (end + 4 <= n &&
               _mm_movemask_epi8(_mm_cmpeq_epi32(
                   _mm_loadu_si128(reinterpret_cast<const __m128i*>(bin + end)), same)) == 0xFFFF) {
          end += 4;
        }
#endif
        while (end < n && bin[end] == bin[k]) ++end;
        mapper.map(p + k, end - k, motion.pose(bin[k]), idx + k, z + k);
        k = end;
      }
    }
    for (size_t k = 0; k < n; ++k) {
      count[idx[k]] += 1;
      sum[idx[k]] += z[k];
    }
  }
}

/// Rasterises weighted points seen from `pose` in batches, like rasteriseSweep().
void rasteriseWeighted(const WeightedCloud& points, const Eigen::Isometry3d& pose,
                       const GridGeometry& geometry, double min_z, double max_z,
                       std::uint32_t* count, float* sum) {
  const RowMajorPose m(pose.cast<float>());
  const CellMapper mapper(geometry, min_z, max_z);
  int idx[kBatch];
  float z[kBatch];
  std::uint32_t w[kBatch];
  for (size_t first = 0; first < points.size(); first += kBatch) {
    const size_t n = std::min(kBatch, points.size() - first);
    mapper.map(points.data() + first, n, m, idx, z, w);
    for (size_t k = 0; k < n; ++k) {
      count[idx[k]] += w[k];
      sum[idx[k]] += static_cast<float>(w[k]) * z[k];
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
  clearSums();
  rasteriseSweep(points, motion, geometry, min_z, max_z, count_.data(), sum_z_.data());
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
  clearSums();
  for (const PosedCloud& part : parts) {
    rasteriseWeighted(*part.cloud, part.pose, geometry, min_z, max_z, count_.data(), sum_z_.data());
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

namespace {

/// Where a fine row's cells are pooled: the coarse row's counts and sums.
struct PoolRow {
  std::uint32_t* count;
  float* sum;
};

/// Adds cells [from, n) of a fine row (from even) into the coarse row, a pair of cells into each
/// coarse cell (c / 2), an odd last cell alone: the pooling of HeightGrid::poolFrom().
void poolPairs(const std::uint32_t* __restrict__ cnt, const float* __restrict__ sum, int from,
               int n, const PoolRow& pool) {
  std::uint32_t* __restrict__ gc = pool.count;
  float* __restrict__ gs = pool.sum;
  const int pairs = n / 2;
  for (int j = from / 2; j < pairs; ++j) {
    gc[j] += cnt[2 * j] + cnt[2 * j + 1];
    gs[j] += sum[2 * j] + sum[2 * j + 1];
  }
  if (n % 2 != 0) {
    gc[pairs] += cnt[n - 1];
    gs[pairs] += sum[n - 1];
  }
}

}  // namespace

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
    poolPairs(finer.count_.data() + at, finer.sum_z_.data() + at, 0, cols,
              PoolRow{g.count_.data() + coarse_at, g.sum_z_.data() + coarse_at});
  }
  g.finalise(nullptr);
}

void HeightGrid::clearSums() {
  const size_t n = static_cast<size_t>(geometry_.cellCount()) + kDiscardCells;
  count_.assign(n, 0u);
  sum_z_.assign(n, 0.0f);
}

namespace {

/// Heights and valid flags of n cells from their counts and sums, and the number of valid ones;
/// with `pool` (n cells of one fine row), each pair of cells is also added into the coarse row
/// as HeightGrid::poolFrom() adds it. Signed counts throughout: SSE2 converts and compares
/// signed integers in one instruction, unsigned ones not (a cell never holds 2^31 points).
int finaliseCells(const std::int32_t* __restrict__ cnt, const float* __restrict__ sum, int n,
                  std::int32_t need, float* __restrict__ height, std::uint8_t* __restrict__ valid,
                  const PoolRow* pool) {
  int valid_cells = 0;
  int i = 0;
#ifdef __SSE2__
  // Sixteen cells at a time. Measured cells are a few percent of a grid, clustered: a group
  // without one is written as zeros without dividing (the divisions over the whole grid were
  // most of this function). Invalid lanes divide by 1 and are masked; "+ 0" turns -0 into 0.
  const __m128i at_least = _mm_set1_epi32(need - 1);  // cnt > need - 1
  const __m128i one = _mm_set1_epi32(1);
  const __m128 zero = _mm_setzero_ps();
  for (; i + 16 <= n; i += 16) {
    __m128i c[4], ok[4];
    for (int g = 0; g < 4; ++g) {
      c[g] = _mm_loadu_si128(reinterpret_cast<const __m128i*>(cnt + i + 4 * g));
      ok[g] = _mm_cmpgt_epi32(c[g], at_least);  // all ones if valid
    }
    if (pool != nullptr) {
      // Pairs of cells, as even + odd lanes; a group without points adds nothing (the coarse
      // sums start at +0 and never become -0, so adding +0 would not change them either).
      const __m128i any = _mm_or_si128(_mm_or_si128(c[0], c[1]), _mm_or_si128(c[2], c[3]));
      if (_mm_movemask_epi8(_mm_cmpeq_epi32(any, _mm_setzero_si128())) != 0xFFFF) {
        for (int h = 0; h < 2; ++h) {
          const int j = i / 2 + 4 * h;
          const __m128 a = _mm_castsi128_ps(c[2 * h]), b = _mm_castsi128_ps(c[2 * h + 1]);
          const __m128i pairs =
              _mm_add_epi32(_mm_castps_si128(_mm_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0))),
                            _mm_castps_si128(_mm_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1))));
          __m128i* gc = reinterpret_cast<__m128i*>(pool->count + j);
          _mm_storeu_si128(gc, _mm_add_epi32(_mm_loadu_si128(gc), pairs));
          const __m128 s0 = _mm_loadu_ps(sum + i + 8 * h), s1 = _mm_loadu_ps(sum + i + 8 * h + 4);
          const __m128 sums = _mm_add_ps(_mm_shuffle_ps(s0, s1, _MM_SHUFFLE(2, 0, 2, 0)),
                                         _mm_shuffle_ps(s0, s1, _MM_SHUFFLE(3, 1, 3, 1)));
          _mm_storeu_ps(pool->sum + j, _mm_add_ps(_mm_loadu_ps(pool->sum + j), sums));
        }
      }
    }
    // -1 / 0 per cell, narrowed to bytes with signed saturation.
    const __m128i flags =
        _mm_packs_epi16(_mm_packs_epi32(ok[0], ok[1]), _mm_packs_epi32(ok[2], ok[3]));
    const int bits = _mm_movemask_epi8(flags);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(valid + i), _mm_and_si128(flags, _mm_set1_epi8(1)));
    if (bits == 0) {
      for (int g = 0; g < 4; ++g) _mm_storeu_ps(height + i + 4 * g, zero);
      continue;
    }
    valid_cells += __builtin_popcount(static_cast<unsigned>(bits));
    for (int g = 0; g < 4; ++g) {
      const __m128 divisor =
          _mm_cvtepi32_ps(_mm_or_si128(_mm_and_si128(c[g], ok[g]), _mm_andnot_si128(ok[g], one)));
      const __m128 mean = _mm_div_ps(_mm_loadu_ps(sum + i + 4 * g), divisor);
      _mm_storeu_ps(height + i + 4 * g,
                    _mm_add_ps(_mm_and_ps(_mm_castsi128_ps(ok[g]), mean), zero));
    }
  }
#endif
  // The rest from the even column i, as poolFrom() pools.
  if (pool != nullptr) poolPairs(reinterpret_cast<const std::uint32_t*>(cnt), sum, i, n, *pool);
  for (; i < n; ++i) {
    const bool ok = cnt[i] >= need;
    height[i] = ok ? sum[i] / static_cast<float>(cnt[i]) + 0.0f : 0.0f;
    valid[i] = ok ? 1u : 0u;
    valid_cells += valid[i];
  }
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
      const PoolRow pool{coarser->count_.data() + coarse_at, coarser->sum_z_.data() + coarse_at};
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
  const __m128 quarter = _mm_set1_ps(0.25f), three = _mm_set1_ps(0.75f), half_w = _mm_set1_ps(0.5f);
  const __m128 one = _mm_set1_ps(1.0f);
  for (; j < j_end; j += 4) {
    const __m128 s_a = _mm_loadu_ps(vs + j), s_b = _mm_loadu_ps(vs + j + 1),
                 s_c = _mm_loadu_ps(vs + j + 2);
    const __m128 h_a = _mm_loadu_ps(vh + j), h_b = _mm_loadu_ps(vh + j + 1),
                 h_c = _mm_loadu_ps(vh + j + 2);
    const __m128 we = _mm_add_ps(_mm_mul_ps(quarter, s_a), _mm_mul_ps(three, s_b));
    const __m128 wo = _mm_add_ps(_mm_mul_ps(three, s_b), _mm_mul_ps(quarter, s_c));
    const __m128 fe = _mm_div_ps(_mm_add_ps(_mm_mul_ps(quarter, h_a), _mm_mul_ps(three, h_b)),
                                 _mm_max_ps(we, half_w));
    const __m128 fo = _mm_div_ps(_mm_add_ps(_mm_mul_ps(three, h_b), _mm_mul_ps(quarter, h_c)),
                                 _mm_max_ps(wo, half_w));
    const __m128 ke = _mm_and_ps(_mm_cmpge_ps(we, half_w), one);
    const __m128 ko = _mm_and_ps(_mm_cmpge_ps(wo, half_w), one);
    // Interleaved into fine-column order: 2j, 2j + 1, ...
    _mm_storeu_ps(value + 2 * j, _mm_unpacklo_ps(fe, fo));
    _mm_storeu_ps(value + 2 * j + 4, _mm_unpackhi_ps(fe, fo));
    _mm_storeu_ps(ok + 2 * j, _mm_unpacklo_ps(ke, ko));
    _mm_storeu_ps(ok + 2 * j + 4, _mm_unpackhi_ps(ke, ko));
  }
#endif
  for (; j < j_end; ++j) {
    const float we = 0.25f * vs[j] + 0.75f * vs[j + 1];
    const float wo = 0.75f * vs[j + 1] + 0.25f * vs[j + 2];
    value[2 * j] = (0.25f * vh[j] + 0.75f * vh[j + 1]) / std::max(we, 0.5f);
    value[2 * j + 1] = (0.75f * vh[j + 1] + 0.25f * vh[j + 2]) / std::max(wo, 0.5f);
    ok[2 * j] = we >= 0.5f ? 1.0f : 0.0f;
    ok[2 * j + 1] = wo >= 0.5f ? 1.0f : 0.0f;
  }
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
