#include "dlo/export/height_map_image.h"

#include "dlo/export/height_range.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace dlo {

namespace {

const cv::Scalar kEmpty(50, 50, 50);
const cv::Scalar kTrajectory(255, 255, 255);
const cv::Scalar kLoop(255, 0, 255);
const cv::Scalar kText(255, 255, 255);

/// A "nice" length (1, 2 or 5 times a power of ten) close to `target` metres.
double niceLength(double target) {
  const double base = std::pow(10.0, std::floor(std::log10(std::max(target, 1e-3))));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * base <= target) return m * base;
  }
  return base;
}

/// Where world (x, y) lands in the image: column from x, row from y flipped so +y is up.
struct PixelMapping {
  double x_min, y_max, scale;  ///< scale: pixels per metre
  cv::Point operator()(const Eigen::Vector3d& p) const {
    return cv::Point(static_cast<int>(std::lround((p.x() - x_min) * scale)),
                     static_cast<int>(std::lround((y_max - p.y()) * scale)));
  }
};

void drawLegend(cv::Mat& image, double lo, double hi, double pixels_per_metre) {
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double fs = 0.5;
  cv::rectangle(image, cv::Rect(5, 5, 300, 95), cv::Scalar(0, 0, 0), cv::FILLED);
  // Colour key: the colormap from lo to hi.
  cv::Mat ramp(1, 200, CV_8UC1);
  for (int i = 0; i < 200; ++i)
    ramp.at<unsigned char>(0, i) = static_cast<unsigned char>(i * 255 / 199);
  cv::Mat ramp_bgr;
  cv::applyColorMap(ramp, ramp_bgr, cv::COLORMAP_TURBO);
  cv::resize(ramp_bgr, ramp_bgr, cv::Size(200, 12), 0, 0, cv::INTER_NEAREST);
  ramp_bgr.copyTo(image(cv::Rect(15, 15, 200, 12)));
  char text[96];
  std::snprintf(text, sizeof text, "height %.2f .. %.2f m", lo, hi);
  cv::putText(image, text, cv::Point(15, 45), font, fs, kText, 1, cv::LINE_AA);
  // Scale bar of a round length about 100 px long.
  const double metres = niceLength(100.0 / pixels_per_metre);
  const int len = static_cast<int>(std::lround(metres * pixels_per_metre));
  cv::line(image, cv::Point(15, 62), cv::Point(15 + len, 62), kText, 2);
  std::snprintf(text, sizeof text, "%g m", metres);
  cv::putText(image, text, cv::Point(20 + len, 67), font, fs, kText, 1, cv::LINE_AA);
  cv::putText(image, "path", cv::Point(15, 88), font, fs, kTrajectory, 1, cv::LINE_AA);
  cv::putText(image, "loops", cv::Point(65, 88), font, fs, kLoop, 1, cv::LINE_AA);
  cv::putText(image, "up = +y", cv::Point(125, 88), font, fs, kText, 1, cv::LINE_AA);
}

}  // namespace

cv::Mat renderHeightMapImage(const mrpt::maps::CHeightGridMap2D& grid, const SlamMap& map,
                             const HeightMapImageOptions& options) {
  const int cols = static_cast<int>(grid.getSizeX()), rows = static_cast<int>(grid.getSizeY());
  std::vector<float> heights;
  for (int cy = 0; cy < rows; ++cy) {
    for (int cx = 0; cx < cols; ++cx) {
      const auto* cell = grid.cellByIndex(cx, cy);
      if (cell->w > 0) heights.push_back(cell->h);
    }
  }
  const auto [lo, hi] =
      colourHeightRange(std::move(heights), options.low_percentile, options.high_percentile);

  // One pixel per cell, row 0 = largest y.
  cv::Mat index(rows, cols, CV_8UC1, cv::Scalar(0));
  cv::Mat empty(rows, cols, CV_8UC1, cv::Scalar(255));
  for (int cy = 0; cy < rows; ++cy) {
    for (int cx = 0; cx < cols; ++cx) {
      const auto* cell = grid.cellByIndex(cx, cy);
      if (cell->w == 0) continue;
      const double t = std::clamp((cell->h - lo) / (hi - lo), 0.0, 1.0);
      index.at<unsigned char>(rows - 1 - cy, cx) = static_cast<unsigned char>(std::lround(255 * t));
      empty.at<unsigned char>(rows - 1 - cy, cx) = 0;
    }
  }
  cv::Mat colour;
  cv::applyColorMap(index, colour, cv::COLORMAP_TURBO);
  colour.setTo(kEmpty, empty);

  const int side = std::max({cols, rows, 1});
  const int scale = std::clamp((options.min_side_px + side - 1) / side, 1, 16);
  cv::Mat image;
  cv::resize(colour, image, cv::Size(cols * scale, rows * scale), 0, 0, cv::INTER_NEAREST);

  const PixelMapping px{grid.getXMin(), grid.getYMax(), scale / grid.getResolution()};
  std::vector<cv::Point> path;
  for (size_t i = 0; i < map.frames.size(); ++i) path.push_back(px(map.framePose(i).translation()));
  if (path.size() >= 2) cv::polylines(image, path, false, kTrajectory, 2, cv::LINE_AA);
  for (const Keyframe& kf : map.keyframes) {
    cv::circle(image, px(kf.pose.translation()), 3, kTrajectory, cv::FILLED, cv::LINE_AA);
  }
  auto keyframe = [&](int id) -> const Keyframe* {
    return id >= 0 && id < static_cast<int>(map.keyframes.size()) ? &map.keyframes[id] : nullptr;
  };
  for (const PoseEdge& e : map.edges) {
    const Keyframe* a = keyframe(e.from);
    const Keyframe* b = keyframe(e.to);
    if (!e.loop || !a || !b) continue;
    cv::line(image, px(a->pose.translation()), px(b->pose.translation()), kLoop, 2, cv::LINE_AA);
  }
  drawLegend(image, lo, hi, px.scale);
  return image;
}

}  // namespace dlo
