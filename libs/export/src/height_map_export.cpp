#include "dlo/export/height_map_export.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "dlo/files/atomic_file.h"

namespace dlo {

HeightGridAccumulator::HeightGridAccumulator(double resolution, double margin)
    : resolution_(resolution), margin_(margin) {}

void HeightGridAccumulator::extend(const WeightedCloud& world_points) {
  for (const WeightedPoint& wp : world_points) {
    x_min_ = std::min<double>(x_min_, wp.p.x());
    x_max_ = std::max<double>(x_max_, wp.p.x());
    y_min_ = std::min<double>(y_min_, wp.p.y());
    y_max_ = std::max<double>(y_max_, wp.p.y());
  }
}

void HeightGridAccumulator::allocate() {
  if (x_min_ > x_max_) x_min_ = x_max_ = y_min_ = y_max_ = 0.0;  // nothing seen
  grid_.emplace(mrpt::maps::CHeightGridMap2D::mrSimpleAverage, x_min_ - margin_, x_max_ + margin_,
                y_min_ - margin_, y_max_ + margin_, resolution_);
  const size_t cells = grid_->getSizeX() * grid_->getSizeY();
  sum_.assign(cells, 0.0);
  sum_sq_.assign(cells, 0.0);
  sum_u_.assign(cells, 0.0f);
  sum_v_.assign(cells, 0.0f);
  count_.assign(cells, 0);
}

void HeightGridAccumulator::add(const WeightedCloud& world_points) {
  if (!grid_) allocate();
  const mrpt::maps::CHeightGridMap2D& grid = *grid_;
  for (const WeightedPoint& wp : world_points) {
    const int cx = grid.x2idx(wp.p.x()), cy = grid.y2idx(wp.p.y());
    if (cx < 0 || cy < 0 || cx >= static_cast<int>(grid.getSizeX()) ||
        cy >= static_cast<int>(grid.getSizeY())) {
      continue;
    }
    const size_t i = static_cast<size_t>(cy) * grid.getSizeX() + static_cast<size_t>(cx);
    const double n = wp.n, z = wp.p.z();
    sum_[i] += n * z;
    sum_sq_[i] += n * z * z;
    const double u = (wp.p.x() - grid.getXMin()) / grid.getResolution() - cx;
    const double v = (wp.p.y() - grid.getYMin()) / grid.getResolution() - cy;
    sum_u_[i] += static_cast<float>(n * std::clamp(u, 0.0, 1.0));
    sum_v_[i] += static_cast<float>(n * std::clamp(v, 0.0, 1.0));
    count_[i] += wp.n;
  }
}

mrpt::maps::CHeightGridMap2D HeightGridAccumulator::grid() {
  if (!grid_) allocate();
  mrpt::maps::CHeightGridMap2D& grid = *grid_;
  for (size_t cy = 0; cy < grid.getSizeY(); ++cy) {
    for (size_t cx = 0; cx < grid.getSizeX(); ++cx) {
      const size_t i = cy * grid.getSizeX() + cx;
      if (count_[i] == 0) continue;
      mrpt::maps::THeightGridmapCell* cell = grid.cellByIndex(cx, cy);
      const double w = static_cast<double>(count_[i]);
      cell->w = static_cast<std::uint32_t>(std::min<std::uint64_t>(count_[i], UINT32_MAX));
      cell->u = static_cast<float>(sum_[i]);
      cell->v = static_cast<float>(sum_sq_[i]);
      cell->h = static_cast<float>(sum_[i] / w);
      cell->var =
          w > 1 ? static_cast<float>(std::max(0.0, (sum_sq_[i] - sum_[i] * sum_[i] / w) / (w - 1)))
                : 0.0f;
    }
  }
  return grid;
}

HeightMapCentroids HeightGridAccumulator::centroids() {
  if (!grid_) allocate();
  HeightMapCentroids c;
  c.cols = static_cast<std::uint32_t>(grid_->getSizeX());
  c.rows = static_cast<std::uint32_t>(grid_->getSizeY());
  c.places.resize(2 * count_.size());
  for (size_t i = 0; i < count_.size(); ++i) {
    const double w = static_cast<double>(count_[i]);
    c.places[2 * i] = HeightMapCentroids::quantise(w > 0 ? sum_u_[i] / w : 0.5);
    c.places[2 * i + 1] = HeightMapCentroids::quantise(w > 0 ? sum_v_[i] / w : 0.5);
  }
  return c;
}

mrpt::maps::CHeightGridMap2D toHeightGridMap(const WeightedCloud& world_points, double resolution,
                                             double margin) {
  HeightGridAccumulator acc(resolution, margin);
  acc.extend(world_points);
  acc.add(world_points);
  return acc.grid();
}

void exportHeightGridMap(const mrpt::maps::CHeightGridMap2D& grid, const std::string& path) {
  exportSerializedGz(grid, path);
}

void exportSerializedGz(const mrpt::serialization::CSerializable& object, const std::string& path,
                        int level) {
  writeAtomically(path, [&](const std::string& temp) {
    mrpt::io::CFileGZOutputStream out;
    if (!out.open(temp, level)) throw std::runtime_error("cannot create '" + temp + "'");
    auto archive = mrpt::serialization::archiveFrom(out);
    archive << object;
    out.close();
  });
}

}  // namespace dlo
