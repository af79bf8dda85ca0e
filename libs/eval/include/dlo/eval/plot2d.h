/// \file plot2d.h
/// \brief A minimal 2D line plot rendered into a cv::Mat: axes, grid, tick labels, axis labels,
/// polylines, markers and a legend. Enough for evaluation figures without Python or gnuplot.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace dlo::eval {

/// Shape drawn at every point of a series.
enum class Marker { kNone, kCircle, kSquare, kTriangle, kDiamond, kCross };

/// One curve of a plot.
struct PlotSeries {
  std::string label;                ///< legend text; series with an empty label are not listed
  std::vector<cv::Point2d> points;  ///< data coordinates, drawn in order
  cv::Scalar colour;                ///< BGR
  Marker marker = Marker::kNone;
  int thickness = 2;      ///< line width, pixels; 0 draws markers only
  bool connect = true;    ///< draw a polyline through the points
  bool in_legend = true;  ///< list the series in the legend (if it has a label)
};

/// A closed interval of data values along one axis.
struct AxisRange {
  double min = 0.0;
  double max = 1.0;
  double span() const { return max - min; }
};

/// Where everything goes in the image; computed from the series and settings by
/// Plot2D::frame(), so tests and callers can map data to pixels exactly as render() does.
struct PlotFrame {
  cv::Rect area;   ///< the plot area in image pixels (inside the axes box)
  AxisRange x, y;  ///< data values at the area's left/right and bottom/top edges
  std::vector<double> x_ticks, y_ticks;
  double x_step = 1.0, y_step = 1.0;  ///< tick spacing, which sets the label decimals
  cv::Rect legend;  ///< legend box in image pixels; empty when no series has a label

  /// Image pixel of data point `p` (sub-pixel; y grows downwards in the image).
  cv::Point2d toPixel(const cv::Point2d& p) const;
};

/// A line plot. Add series, optionally fix ranges, then render(). Ranges not fixed are taken
/// from the data with a 4% margin. With equal aspect (maps, top views) one metre is the same
/// number of pixels along both axes: the shorter range is widened around its centre.
class Plot2D {
 public:
  /// An image of `size` pixels (width x height), white background.
  explicit Plot2D(cv::Size size);

  void setTitle(const std::string& title) { title_ = title; }
  void setAxisLabels(const std::string& x, const std::string& y) {
    x_label_ = x;
    y_label_ = y;
  }
  void setEqualAspect(bool equal) { equal_aspect_ = equal; }
  /// Fixes the x range instead of taking it from the data.
  void setXRange(double min, double max);
  /// Fixes the y range instead of taking it from the data (e.g. errors from 0).
  void setYRange(double min, double max);
  /// Makes the automatic y range include 0 (errors, drifts: the reader compares to zero).
  void setYIncludesZero(bool include) { y_includes_zero_ = include; }

  void addSeries(PlotSeries series) { series_.push_back(std::move(series)); }
  const std::vector<PlotSeries>& series() const { return series_; }

  /// The layout render() uses: plot area, ranges, ticks and legend box.
  PlotFrame frame() const;
  /// Draws the plot: 8-bit BGR, size given to the constructor.
  cv::Mat render() const;

 private:
  cv::Size size_;
  std::string title_, x_label_, y_label_;
  bool equal_aspect_ = false;
  bool y_includes_zero_ = false;
  bool x_fixed_ = false, y_fixed_ = false;
  AxisRange x_range_, y_range_;
  std::vector<PlotSeries> series_;
};

/// Colour of the i-th compared series (BGR): distinct, readable on white, and none of them
/// black or grey, which are kept for the reference (ground truth) and the axes. Cycles after 8.
cv::Scalar seriesColour(size_t i);

/// Marker of the i-th compared series, so curves stay distinguishable in grey print. Cycles.
Marker seriesMarker(size_t i);

/// Colour of the reference (ground truth) curve: black.
cv::Scalar referenceColour();

}  // namespace dlo::eval
