#include "trajectory_overlay.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "dlo/metrics/absolute_trajectory_error.h"
#include "dlo/metrics/timestamp_matching.h"

namespace dlo::bench {

namespace {

/// Distinct colours (BGR) readable on white; black is kept for the ground truth.
cv::Scalar colour(size_t i) {
  static const cv::Scalar palette[] = {{200, 80, 0},  {0, 140, 255},  {40, 160, 40},
                                       {30, 30, 220}, {180, 60, 160}, {140, 140, 0},
                                       {0, 90, 140},  {120, 120, 255}};
  return palette[i % (sizeof palette / sizeof palette[0])];
}

std::vector<cv::Point2d> alignedPositions(const metrics::Trajectory& estimate,
                                          const metrics::Trajectory& ground_truth) {
  Eigen::Isometry3d align = Eigen::Isometry3d::Identity();
  const auto [matched, reference] = metrics::matchedTrajectories(estimate, ground_truth, 0.005);
  if (matched.size() >= 3) {
    align = metrics::absoluteTrajectoryError(matched, reference, metrics::Alignment::kUmeyama)
                .transform;
  }
  std::vector<cv::Point2d> out;
  for (const auto& pose : estimate.poses) {
    const Eigen::Vector3d p = align * pose.translation();
    if (std::isfinite(p.x()) && std::isfinite(p.y())) out.emplace_back(p.x(), p.y());
  }
  return out;
}

std::vector<cv::Point2d> positions(const metrics::Trajectory& t) {
  std::vector<cv::Point2d> out;
  for (const auto& pose : t.poses) out.emplace_back(pose.translation().x(), pose.translation().y());
  return out;
}

}  // namespace

cv::Mat drawTrajectoryOverlay(
    const metrics::Trajectory& ground_truth,
    const std::vector<std::pair<std::string, metrics::Trajectory>>& estimates, cv::Size size) {
  std::vector<std::pair<std::string, std::vector<cv::Point2d>>> curves;
  curves.emplace_back("ground truth", positions(ground_truth));
  for (const auto& [name, trajectory] : estimates) {
    curves.emplace_back(name, alignedPositions(trajectory, ground_truth));
  }

  double x0 = std::numeric_limits<double>::max(), y0 = x0, x1 = -x0, y1 = -x0;
  for (const auto& curve : curves) {
    for (const auto& p : curve.second) {
      x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
      y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
    }
  }
  if (x0 > x1) x0 = y0 = -1.0, x1 = y1 = 1.0;
  const int margin = 50, legend_width = 260;
  const cv::Rect area(margin, margin, size.width - 2 * margin - legend_width,
                      size.height - 2 * margin);
  // One scale for both axes, so the top view keeps its shape.
  const double span = std::max({x1 - x0, y1 - y0, 1.0}) * 1.06;
  const double scale = std::min(area.width, area.height) / span;
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  const auto pixel = [&](const cv::Point2d& p) {
    return cv::Point(cvRound(area.x + 0.5 * area.width + (p.x - cx) * scale),
                     cvRound(area.y + 0.5 * area.height - (p.y - cy) * scale));
  };

  cv::Mat image(size, CV_8UC3, cv::Scalar(255, 255, 255));
  const double grid = 10.0;  // metres
  for (double x = std::floor((cx - 0.5 * area.width / scale) / grid) * grid;
       x <= cx + 0.5 * area.width / scale; x += grid) {
    const int u = pixel({x, cy}).x;
    if (u >= area.x && u <= area.br().x)
      cv::line(image, {u, area.y}, {u, area.br().y}, {225, 225, 225}, 1);
  }
  for (double y = std::floor((cy - 0.5 * area.height / scale) / grid) * grid;
       y <= cy + 0.5 * area.height / scale; y += grid) {
    const int v = pixel({cx, y}).y;
    if (v >= area.y && v <= area.br().y)
      cv::line(image, {area.x, v}, {area.br().x, v}, {225, 225, 225}, 1);
  }
  cv::rectangle(image, area, {120, 120, 120}, 1);
  const auto text = [&](const std::string& s, cv::Point at, cv::Scalar c, double h = 0.5) {
    cv::putText(image, s, at, cv::FONT_HERSHEY_SIMPLEX, h, c, 1, cv::LINE_AA);
  };
  text("top view (x, y), grid 10 m; estimates aligned to ground truth (SE(3) Umeyama)",
       {margin, margin - 18}, {0, 0, 0});

  const cv::Point legend(area.br().x + 20, area.y + 10);
  for (size_t i = 0; i < curves.size(); ++i) {
    const cv::Scalar c = i == 0 ? cv::Scalar(0, 0, 0) : colour(i - 1);
    const int thickness = i == 0 ? 3 : 2;
    std::vector<cv::Point> line;
    for (const auto& p : curves[i].second) line.push_back(pixel(p));
    if (line.size() > 1) cv::polylines(image, line, false, c, thickness, cv::LINE_AA);
    if (!line.empty()) cv::circle(image, line.front(), 5, c, -1, cv::LINE_AA);
    const cv::Point row = legend + cv::Point(0, 28 * static_cast<int>(i));
    cv::line(image, row + cv::Point(0, -5), row + cv::Point(30, -5), c, thickness, cv::LINE_AA);
    text(curves[i].first, row + cv::Point(40, 0), {0, 0, 0}, 0.6);
  }
  text("dots: first pose", legend + cv::Point(0, 28 * static_cast<int>(curves.size()) + 10),
       {90, 90, 90});
  return image;
}

}  // namespace dlo::bench
