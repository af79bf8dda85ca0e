#include "dlo/sim/object_grid.h"

#include <algorithm>
#include <cmath>

namespace dlo::sim {

ObjectGrid::ObjectGrid(std::vector<Primitive> primitives, double cellSize)
    : primitives_(std::move(primitives)), cell_(cellSize) {
  if (primitives_.empty()) return;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& p : primitives_) {
    const Eigen::Vector2d e = p.horizontalHalfExtent();
    lo = lo.cwiseMin(p.centre.head<2>() - e);
    hi = hi.cwiseMax(p.centre.head<2>() + e);
  }
  min_ = lo;
  nx_ = static_cast<int>(std::floor((hi.x() - lo.x()) / cell_)) + 1;
  ny_ = static_cast<int>(std::floor((hi.y() - lo.y()) / cell_)) + 1;
  const size_t cells = static_cast<size_t>(nx_) * ny_;
  std::vector<std::vector<uint32_t>> bins(cells);
  cellTop_.assign(cells, -1e30f);
  primTop_.resize(primitives_.size());
  for (uint32_t k = 0; k < primitives_.size(); ++k) {
    const auto& p = primitives_[k];
    const Eigen::Vector2d e = p.horizontalHalfExtent();
    const int i0 = static_cast<int>(std::floor((p.centre.x() - e.x() - min_.x()) / cell_));
    const int i1 = static_cast<int>(std::floor((p.centre.x() + e.x() - min_.x()) / cell_));
    const int j0 = static_cast<int>(std::floor((p.centre.y() - e.y() - min_.y()) / cell_));
    const int j1 = static_cast<int>(std::floor((p.centre.y() + e.y() - min_.y()) / cell_));
    primTop_[k] = p.centre.z() + p.half.z();
    globalTop_ = std::max(globalTop_, primTop_[k]);
    for (int j = std::max(j0, 0); j <= std::min(j1, ny_ - 1); ++j) {
      for (int i = std::max(i0, 0); i <= std::min(i1, nx_ - 1); ++i) {
        const size_t c = static_cast<size_t>(j) * nx_ + i;
        bins[c].push_back(k);
        cellTop_[c] = std::max(cellTop_[c], static_cast<float>(primTop_[k]));
      }
    }
  }
  cellStart_.resize(cells + 1);
  cellStart_[0] = 0;
  for (size_t c = 0; c < cells; ++c) {
    cellStart_[c + 1] = cellStart_[c] + static_cast<uint32_t>(bins[c].size());
    cellItems_.insert(cellItems_.end(), bins[c].begin(), bins[c].end());
  }
}

RayHit ObjectGrid::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double tmin,
                             double tmax, GridScratch& scratch) const {
  RayHit best;
  if (primitives_.empty()) return best;
  if (scratch.stamp.size() != primitives_.size()) {
    scratch.stamp.assign(primitives_.size(), 0);
    scratch.counter = 0;
  }
  if (++scratch.counter == 0) {  // Wrapped: clear stale stamps.
    std::fill(scratch.stamp.begin(), scratch.stamp.end(), 0);
    scratch.counter = 1;
  }
  const uint32_t stamp = scratch.counter;

  // Clip the ray to the grid's horizontal bounds.
  double t0 = tmin, t1 = tmax;
  const Eigen::Vector2d gmax = min_ + Eigen::Vector2d(nx_ * cell_, ny_ * cell_);
  for (int k = 0; k < 2; ++k) {
    if (std::abs(dir[k]) < 1e-12) {
      if (origin[k] < min_[k] || origin[k] > gmax[k]) return best;
      continue;
    }
    double a = (min_[k] - origin[k]) / dir[k], b = (gmax[k] - origin[k]) / dir[k];
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
  }
  if (t0 > t1) return best;

  const double px = origin.x() + t0 * dir.x() - min_.x();
  const double py = origin.y() + t0 * dir.y() - min_.y();
  int i = std::clamp(static_cast<int>(std::floor(px / cell_)), 0, nx_ - 1);
  int j = std::clamp(static_cast<int>(std::floor(py / cell_)), 0, ny_ - 1);
  const int si = dir.x() > 0 ? 1 : -1, sj = dir.y() > 0 ? 1 : -1;
  const double inf = 1e300;
  const double dtx = std::abs(dir.x()) > 1e-12 ? cell_ / std::abs(dir.x()) : inf;
  const double dty = std::abs(dir.y()) > 1e-12 ? cell_ / std::abs(dir.y()) : inf;
  double tx =
      std::abs(dir.x()) > 1e-12
          ? ((dir.x() > 0 ? (i + 1) * cell_ : i * cell_) - (origin.x() - min_.x())) / dir.x()
          : inf;
  double ty =
      std::abs(dir.y()) > 1e-12
          ? ((dir.y() > 0 ? (j + 1) * cell_ : j * cell_) - (origin.y() - min_.y())) / dir.y()
          : inf;
  double tEnter = t0;
  while (true) {
    const double tExit = std::min({tx, ty, t1});
    // Above every object from here on, and rising: nothing more to hit.
    if (dir.z() >= 0.0 && origin.z() + tEnter * dir.z() > globalTop_) break;
    const size_t c = static_cast<size_t>(j) * nx_ + i;
    const double zLow = origin.z() + std::min(tEnter * dir.z(), tExit * dir.z());
    if (zLow <= cellTop_[c]) {
      for (uint32_t n = cellStart_[c]; n < cellStart_[c + 1]; ++n) {
        const uint32_t k = cellItems_[n];
        if (scratch.stamp[k] == stamp) continue;
        scratch.stamp[k] = stamp;
        const double limit = best.valid() ? best.t : t1;
        const double t = intersectPrimitive(primitives_[k], origin, dir, tmin, limit);
        if (t >= 0.0) {
          best.t = t;
          best.surface = primitives_[k].surface;
        }
      }
    }
    if (best.valid() && best.t <= tExit) break;
    if (tExit >= t1) break;
    if (tx < ty) {
      i += si;
      tEnter = tx;
      tx += dtx;
      if (i < 0 || i >= nx_) break;
    } else {
      j += sj;
      tEnter = ty;
      ty += dty;
      if (j < 0 || j >= ny_) break;
    }
  }
  return best;
}

}  // namespace dlo::sim
