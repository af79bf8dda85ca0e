#include "dlo/export/occupancy_grid_export.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/core.hpp>
#include <stdexcept>

#include "dlo/export/height_map_export.h"
#include "dlo/files/atomic_file.h"
#include "dlo/formats/png_file.h"

namespace dlo {

namespace {

constexpr float kNoPoint = std::numeric_limits<float>::infinity();

/// Lowest value within `half` cells along one axis (a separable minimum filter).
void minAlong(const std::vector<float>& in, std::vector<float>& out, int cols, int rows, int half,
              bool along_x) {
  out.assign(in.size(), kNoPoint);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      float m = kNoPoint;
      for (int k = -half; k <= half; ++k) {
        const int cc = along_x ? c + k : c, rr = along_x ? r : r + k;
        if (cc < 0 || cc >= cols || rr < 0 || rr >= rows) continue;
        m = std::min(m, in[static_cast<size_t>(rr) * cols + cc]);
      }
      out[static_cast<size_t>(r) * cols + c] = m;
    }
  }
}

}  // namespace

OccupancyGridAccumulator::OccupancyGridAccumulator(const OccupancyGridOptions& options)
    : options_(options),
      xmin_(std::numeric_limits<double>::max()),
      xmax_(std::numeric_limits<double>::lowest()),
      ymin_(std::numeric_limits<double>::max()),
      ymax_(std::numeric_limits<double>::lowest()) {
  if (!(options.resolution > 0.0) || !(options.obstacle_height > 0.0) ||
      !(options.max_height > options.obstacle_height) || !(options.ground_radius >= 0.0) ||
      !(options.margin >= 0.0)) {
    throw std::invalid_argument(
        "OccupancyGridOptions: resolution and obstacle_height must be positive, max_height above "
        "obstacle_height, ground_radius and margin not negative");
  }
}

void OccupancyGridAccumulator::extend(const WeightedCloud& world_points) {
  for (const WeightedPoint& p : world_points) {
    xmin_ = std::min(xmin_, static_cast<double>(p.p.x()));
    xmax_ = std::max(xmax_, static_cast<double>(p.p.x()));
    ymin_ = std::min(ymin_, static_cast<double>(p.p.y()));
    ymax_ = std::max(ymax_, static_cast<double>(p.p.y()));
    bounded_ = true;
  }
}

void OccupancyGridAccumulator::allocate() {
  if (!bounded_ || cols_ > 0) return;
  xmin_ -= options_.margin;
  ymin_ -= options_.margin;
  xmax_ += options_.margin;
  ymax_ += options_.margin;
  cols_ = std::max(1, static_cast<int>(std::ceil((xmax_ - xmin_) / options_.resolution)));
  rows_ = std::max(1, static_cast<int>(std::ceil((ymax_ - ymin_) / options_.resolution)));
  const size_t n = static_cast<size_t>(cols_) * rows_;
  lowest_.assign(n, kNoPoint);
  seen_.assign(n, 0);
  occupied_.assign(n, 0);
}

bool OccupancyGridAccumulator::cellOf(float x, float y, int& cx, int& cy) const {
  cx = static_cast<int>(std::floor((x - xmin_) / options_.resolution));
  cy = static_cast<int>(std::floor((y - ymin_) / options_.resolution));
  return cx >= 0 && cx < cols_ && cy >= 0 && cy < rows_;
}

void OccupancyGridAccumulator::ground(const WeightedCloud& world_points) {
  allocate();
  int cx = 0, cy = 0;
  for (const WeightedPoint& p : world_points) {
    if (!cellOf(p.p.x(), p.p.y(), cx, cy)) continue;
    float& low = lowest_[static_cast<size_t>(cy) * cols_ + cx];
    low = std::min(low, p.p.z());
  }
}

void OccupancyGridAccumulator::computeLocalGround() {
  const int half = static_cast<int>(std::round(options_.ground_radius / options_.resolution));
  std::vector<float> rows_done;
  minAlong(lowest_, rows_done, cols_, rows_, half, true);
  minAlong(rows_done, local_ground_, cols_, rows_, half, false);
}

void OccupancyGridAccumulator::classify(const WeightedCloud& world_points) {
  allocate();
  if (local_ground_.empty() && !lowest_.empty()) computeLocalGround();
  const float low = static_cast<float>(options_.obstacle_height);
  const float high = static_cast<float>(options_.max_height);
  int cx = 0, cy = 0;
  for (const WeightedPoint& p : world_points) {
    if (!cellOf(p.p.x(), p.p.y(), cx, cy)) continue;
    const size_t i = static_cast<size_t>(cy) * cols_ + cx;
    const float above = p.p.z() - local_ground_[i];
    if (above > high) continue;  // canopy, overhang: not seen by a vehicle on the ground
    seen_[i] = 1;
    if (above > low) occupied_[i] = 1;
  }
}

float OccupancyGridAccumulator::heightAboveGround(float x, float y, float z) {
  allocate();
  if (local_ground_.empty() && !lowest_.empty()) computeLocalGround();
  int cx = 0, cy = 0;
  if (!cellOf(x, y, cx, cy)) return std::numeric_limits<float>::quiet_NaN();
  const float ground = local_ground_[static_cast<size_t>(cy) * cols_ + cx];
  return ground == kNoPoint ? std::numeric_limits<float>::quiet_NaN() : z - ground;
}

mrpt::maps::COccupancyGridMap2D OccupancyGridAccumulator::grid() const {
  mrpt::maps::COccupancyGridMap2D g;
  const float res = static_cast<float>(options_.resolution);
  if (cols_ == 0) {
    g.setSize(0.0f, res, 0.0f, res, res, 0.5f);
    return g;
  }
  g.setSize(static_cast<float>(xmin_), static_cast<float>(xmin_ + cols_ * options_.resolution),
            static_cast<float>(ymin_), static_cast<float>(ymin_ + rows_ * options_.resolution), res,
            0.5f);
  // MRPT snaps the bounds to its cells: each of our cells goes where its centre falls.
  for (int cy = 0; cy < rows_; ++cy) {
    for (int cx = 0; cx < cols_; ++cx) {
      const size_t i = static_cast<size_t>(cy) * cols_ + cx;
      if (!seen_[i]) continue;
      const int gx = g.x2idx(xmin_ + (cx + 0.5) * options_.resolution);
      const int gy = g.y2idx(ymin_ + (cy + 0.5) * options_.resolution);
      if (gx < 0 || gy < 0 || gx >= static_cast<int>(g.getSizeX()) ||
          gy >= static_cast<int>(g.getSizeY()))
        continue;
      g.setCell(gx, gy, occupied_[i] ? 0.0f : 1.0f);
    }
  }
  return g;
}

std::vector<std::string> exportOccupancyGrid(const mrpt::maps::COccupancyGridMap2D& grid,
                                             const std::string& stem) {
  std::vector<std::string> written;
  const std::string gridmap = stem + ".gridmap";
  exportSerializedGz(grid, gridmap);
  written.push_back(gridmap);

  // map_server's convention: 0 (black) occupied, 254 free, 205 unknown; row 0 is the top, the
  // largest y.
  const int cols = static_cast<int>(grid.getSizeX()), rows = static_cast<int>(grid.getSizeY());
  cv::Mat image(rows, cols, CV_8UC1);
  for (int cy = 0; cy < rows; ++cy) {
    for (int cx = 0; cx < cols; ++cx) {
      const float free = grid.getCell(cx, cy);
      const std::uint8_t v = free < 0.35f ? 0 : free > 0.65f ? 254 : 205;
      image.at<std::uint8_t>(rows - 1 - cy, cx) = v;
    }
  }
  const std::string png = stem + ".png";
  writePng(image, png);
  written.push_back(png);

  const std::string yaml = stem + ".yaml";
  const std::string image_name = png.substr(png.find_last_of('/') + 1);
  char text[512];
  std::snprintf(text, sizeof(text),
                "# ROS map_server: the occupancy grid of a DLO map (%s.gridmap for MRPT)\n"
                "image: %s\nresolution: %.6f\norigin: [%.6f, %.6f, 0.0]\nnegate: 0\n"
                "occupied_thresh: 0.65\nfree_thresh: 0.196\n",
                image_name.substr(0, image_name.size() - 4).c_str(), image_name.c_str(),
                static_cast<double>(grid.getResolution()), static_cast<double>(grid.getXMin()),
                static_cast<double>(grid.getYMin()));
  const std::string body = text;
  writeBytesAtomically(yaml, std::vector<unsigned char>(body.begin(), body.end()));
  written.push_back(yaml);
  return written;
}

}  // namespace dlo
