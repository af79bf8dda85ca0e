#include "dlo/eval/plot2d.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "dlo/eval/axis_ticks.h"

namespace dlo::eval {

namespace {

// Margins leave room for tick labels like "-1250" on the left and the x label below.
constexpr int kLeftMargin = 80;
constexpr int kRightMargin = 25;
constexpr int kTopMargin = 20;
constexpr int kTitleHeight = 30;
constexpr int kBottomMargin = 60;
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kTickFontScale = 0.45;
constexpr double kLabelFontScale = 0.55;
constexpr double kTitleFontScale = 0.65;
constexpr int kLegendRow = 22;
constexpr int kLegendSwatch = 30;
constexpr int kLegendInset = 10;
constexpr int kMarkerRadius = 5;
constexpr double kAutoMargin = 0.04;
// Sub-pixel drawing: OpenCV takes fixed-point coordinates with this many fractional bits.
constexpr int kShift = 4;

const cv::Scalar kBlack(0, 0, 0);
const cv::Scalar kGrid(225, 225, 225);
const cv::Scalar kLegendBorder(160, 160, 160);

/// Data range of the points of all series along one coordinate; empty (min > max) without data.
AxisRange dataRange(const std::vector<PlotSeries>& series, bool along_x) {
  AxisRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  for (const PlotSeries& s : series) {
    for (const cv::Point2d& p : s.points) {
      const double v = along_x ? p.x : p.y;
      if (!std::isfinite(v)) continue;
      r.min = std::min(r.min, v);
      r.max = std::max(r.max, v);
    }
  }
  return r;
}

/// A drawable range around the data: a margin so curves do not touch the axes, and a unit
/// range around a constant so that a flat curve still gets ticks.
AxisRange autoRange(AxisRange r, bool include_zero) {
  if (r.min > r.max) r = {0.0, 1.0};
  if (include_zero) {
    r.min = std::min(r.min, 0.0);
    r.max = std::max(r.max, 0.0);
  }
  if (r.span() <= 1e-12 * std::max(1.0, std::fabs(r.max))) {
    r.min -= 1.0;
    r.max += 1.0;
  }
  const double pad = kAutoMargin * r.span();
  const bool starts_at_zero = include_zero && r.min == 0.0;
  // Errors start at 0: a margin below would show meaningless negative values.
  if (!starts_at_zero) r.min -= pad;
  r.max += pad;
  return r;
}

void widen(AxisRange& r, double span) {
  const double centre = 0.5 * (r.min + r.max);
  r.min = centre - 0.5 * span;
  r.max = centre + 0.5 * span;
}

cv::Point fixedPoint(const cv::Point2d& p) {
  // Points far outside the area would overflow int; clipping happens at the area anyway.
  const double limit = 1e6;
  const double x = std::clamp(p.x, -limit, limit), y = std::clamp(p.y, -limit, limit);
  return cv::Point(static_cast<int>(std::lround(x * (1 << kShift))),
                   static_cast<int>(std::lround(y * (1 << kShift))));
}

void drawMarker(cv::Mat& image, const cv::Point2d& c, Marker marker, const cv::Scalar& colour,
                int line_type) {
  const double r = kMarkerRadius;
  const cv::Point centre = fixedPoint(c);
  const int r_fixed = kMarkerRadius << kShift;
  auto polygon = [&](std::initializer_list<cv::Point2d> offsets) {
    std::vector<cv::Point> pts;
    for (const cv::Point2d& o : offsets) pts.push_back(fixedPoint(c + o));
    cv::fillConvexPoly(image, pts, colour, line_type, kShift);
  };
  switch (marker) {
    case Marker::kNone:
      break;
    case Marker::kCircle:
      cv::circle(image, centre, r_fixed, colour, cv::FILLED, line_type, kShift);
      break;
    case Marker::kSquare:
      polygon({{-r, -r}, {r, -r}, {r, r}, {-r, r}});
      break;
    case Marker::kTriangle:
      polygon({{0, -1.2 * r}, {1.1 * r, 0.8 * r}, {-1.1 * r, 0.8 * r}});
      break;
    case Marker::kDiamond:
      polygon({{0, -1.3 * r}, {1.3 * r, 0}, {0, 1.3 * r}, {-1.3 * r, 0}});
      break;
    case Marker::kCross:
      cv::line(image, fixedPoint(c + cv::Point2d(-r, -r)), fixedPoint(c + cv::Point2d(r, r)),
               colour, 2, line_type, kShift);
      cv::line(image, fixedPoint(c + cv::Point2d(-r, r)), fixedPoint(c + cv::Point2d(r, -r)),
               colour, 2, line_type, kShift);
      break;
  }
}

cv::Size textSize(const std::string& text, double scale) {
  int baseline = 0;
  return cv::getTextSize(text, kFont, scale, 1, &baseline);
}

/// Draws `text` with its left end at `x` and its vertical centre at `y_centre`.
void putTextAt(cv::Mat& image, const std::string& text, int x, int y_centre, double scale) {
  const cv::Size s = textSize(text, scale);
  cv::putText(image, text, cv::Point(x, y_centre + s.height / 2), kFont, scale, kBlack, 1,
              cv::LINE_AA);
}

/// OpenCV cannot draw rotated text: draw it upright on a patch and rotate the patch.
void putVerticalText(cv::Mat& image, const std::string& text, int x_centre, int y_centre,
                     double scale) {
  int baseline = 0;
  const cv::Size s = cv::getTextSize(text, kFont, scale, 1, &baseline);
  cv::Mat patch(s.height + baseline + 4, s.width + 4, CV_8UC3, cv::Scalar::all(255));
  cv::putText(patch, text, cv::Point(2, s.height + 2), kFont, scale, kBlack, 1, cv::LINE_AA);
  cv::rotate(patch, patch, cv::ROTATE_90_COUNTERCLOCKWISE);
  cv::Rect target(x_centre - patch.cols / 2, y_centre - patch.rows / 2, patch.cols, patch.rows);
  target &= cv::Rect(0, 0, image.cols, image.rows);
  if (target.area() > 0) {
    patch(cv::Rect(0, 0, target.width, target.height)).copyTo(image(target));
  }
}

std::vector<const PlotSeries*> legendEntries(const std::vector<PlotSeries>& series) {
  std::vector<const PlotSeries*> entries;
  for (const PlotSeries& s : series) {
    if (s.in_legend && !s.label.empty()) entries.push_back(&s);
  }
  return entries;
}

}  // namespace

cv::Point2d PlotFrame::toPixel(const cv::Point2d& p) const {
  const double u = (p.x - x.min) / x.span();
  const double v = (p.y - y.min) / y.span();
  return {area.x + u * area.width, area.y + (1.0 - v) * area.height};
}

Plot2D::Plot2D(cv::Size size) : size_(size) {}

void Plot2D::setXRange(double min, double max) {
  x_fixed_ = max > min;
  x_range_ = {min, max};
}

void Plot2D::setYRange(double min, double max) {
  y_fixed_ = max > min;
  y_range_ = {min, max};
}

PlotFrame Plot2D::frame() const {
  PlotFrame f;
  const int top = kTopMargin + (title_.empty() ? 0 : kTitleHeight);
  f.area = cv::Rect(kLeftMargin, top, std::max(10, size_.width - kLeftMargin - kRightMargin),
                    std::max(10, size_.height - top - kBottomMargin));
  f.x = x_fixed_ ? x_range_ : autoRange(dataRange(series_, true), false);
  f.y = y_fixed_ ? y_range_ : autoRange(dataRange(series_, false), y_includes_zero_);
  if (equal_aspect_) {
    const double per_pixel = std::max(f.x.span() / f.area.width, f.y.span() / f.area.height);
    widen(f.x, per_pixel * f.area.width);
    widen(f.y, per_pixel * f.area.height);
  }
  // About one tick per 90 pixels across and 60 up: labels never collide.
  const int max_x_ticks = std::max(2, f.area.width / 90);
  const int max_y_ticks = std::max(2, f.area.height / 60);
  f.x_step = niceTickStep(f.x.min, f.x.max, max_x_ticks);
  f.y_step = niceTickStep(f.y.min, f.y.max, max_y_ticks);
  f.x_ticks = niceTicks(f.x.min, f.x.max, max_x_ticks);
  f.y_ticks = niceTicks(f.y.min, f.y.max, max_y_ticks);

  const std::vector<const PlotSeries*> entries = legendEntries(series_);
  if (entries.empty()) return f;
  int text_width = 0;
  for (const PlotSeries* s : entries) {
    text_width = std::max(text_width, textSize(s->label, kLabelFontScale).width);
  }
  const cv::Size box(kLegendSwatch + text_width + 28,
                     static_cast<int>(entries.size()) * kLegendRow + 10);
  const int left = f.area.x + kLegendInset;
  const int right = f.area.x + f.area.width - kLegendInset - box.width;
  const int upper = f.area.y + kLegendInset;
  const int lower = f.area.y + f.area.height - kLegendInset - box.height;
  // Like matplotlib's "best": the corner hiding the fewest data points, top right on ties.
  const std::array<cv::Point, 4> corners = {cv::Point(right, upper), cv::Point(left, upper),
                                            cv::Point(right, lower), cv::Point(left, lower)};
  size_t best_hidden = std::numeric_limits<size_t>::max();
  for (const cv::Point& corner : corners) {
    const cv::Rect candidate(corner, box);
    size_t hidden = 0;
    for (const PlotSeries& s : series_) {
      for (const cv::Point2d& p : s.points) {
        const cv::Point2d px = f.toPixel(p);
        hidden += candidate.contains(cv::Point(static_cast<int>(px.x), static_cast<int>(px.y)));
      }
    }
    if (hidden < best_hidden) {
      best_hidden = hidden;
      f.legend = candidate;
    }
  }
  return f;
}

cv::Mat Plot2D::render() const {
  const PlotFrame f = frame();
  cv::Mat image(size_, CV_8UC3, cv::Scalar::all(255));

  for (double t : f.x_ticks) {
    const int px = static_cast<int>(std::lround(f.toPixel({t, f.y.min}).x));
    cv::line(image, {px, f.area.y}, {px, f.area.y + f.area.height}, kGrid, 1);
  }
  for (double t : f.y_ticks) {
    const int py = static_cast<int>(std::lround(f.toPixel({f.x.min, t}).y));
    cv::line(image, {f.area.x, py}, {f.area.x + f.area.width, py}, kGrid, 1);
  }

  // Curves go into a view of the plot area, which clips them at the axes.
  cv::Mat area = image(f.area);
  const cv::Point2d origin(f.area.x, f.area.y);
  for (const PlotSeries& s : series_) {
    std::vector<cv::Point> polyline;
    for (const cv::Point2d& p : s.points) polyline.push_back(fixedPoint(f.toPixel(p) - origin));
    if (s.connect && s.thickness > 0 && polyline.size() >= 2) {
      cv::polylines(area, polyline, false, s.colour, s.thickness, cv::LINE_AA, kShift);
    }
    if (s.marker != Marker::kNone) {
      for (const cv::Point2d& p : s.points) {
        drawMarker(area, f.toPixel(p) - origin, s.marker, s.colour, cv::LINE_AA);
      }
    }
  }

  cv::rectangle(image, f.area, kBlack, 1);
  const int bottom = f.area.y + f.area.height;
  for (double t : f.x_ticks) {
    const int px = static_cast<int>(std::lround(f.toPixel({t, f.y.min}).x));
    cv::line(image, {px, bottom}, {px, bottom + 5}, kBlack, 1);
    const std::string label = tickLabel(t, f.x_step);
    putTextAt(image, label, px - textSize(label, kTickFontScale).width / 2, bottom + 16,
              kTickFontScale);
  }
  for (double t : f.y_ticks) {
    const int py = static_cast<int>(std::lround(f.toPixel({f.x.min, t}).y));
    cv::line(image, {f.area.x - 5, py}, {f.area.x, py}, kBlack, 1);
    const std::string label = tickLabel(t, f.y_step);
    putTextAt(image, label, f.area.x - 8 - textSize(label, kTickFontScale).width, py,
              kTickFontScale);
  }
  if (!x_label_.empty()) {
    putTextAt(image, x_label_,
              f.area.x + (f.area.width - textSize(x_label_, kLabelFontScale).width) / 2,
              bottom + 42, kLabelFontScale);
  }
  if (!y_label_.empty()) {
    putVerticalText(image, y_label_, 14, f.area.y + f.area.height / 2, kLabelFontScale);
  }
  if (!title_.empty()) {
    const cv::Size s = textSize(title_, kTitleFontScale);
    cv::putText(image, title_, cv::Point((size_.width - s.width) / 2, kTopMargin + s.height), kFont,
                kTitleFontScale, kBlack, 1, cv::LINE_AA);
  }

  if (f.legend.area() > 0) {
    cv::rectangle(image, f.legend, cv::Scalar::all(255), cv::FILLED);
    cv::rectangle(image, f.legend, kLegendBorder, 1);
    int row = 0;
    for (const PlotSeries* s : legendEntries(series_)) {
      const int y = f.legend.y + 5 + row * kLegendRow + kLegendRow / 2;
      const int x = f.legend.x + 8;
      // A solid swatch without anti-aliasing: the exact series colour, findable in the image.
      cv::rectangle(image, cv::Rect(x, y - 2, kLegendSwatch, 5), s->colour, cv::FILLED);
      if (s->marker != Marker::kNone) {
        drawMarker(image, cv::Point2d(x + kLegendSwatch / 2.0, y), s->marker, s->colour,
                   cv::LINE_8);
      }
      putTextAt(image, s->label, x + kLegendSwatch + 10, y, kLabelFontScale);
      ++row;
    }
  }
  return image;
}

cv::Scalar seriesColour(size_t i) {
  // Tableau 10 without its grey, as BGR: colour-blind friendlier than pure RGB primaries.
  static const std::array<cv::Scalar, 8> kPalette = {
      cv::Scalar(180, 119, 31),  cv::Scalar(14, 127, 255),  cv::Scalar(44, 160, 44),
      cv::Scalar(40, 39, 214),   cv::Scalar(189, 103, 148), cv::Scalar(75, 86, 140),
      cv::Scalar(194, 119, 227), cv::Scalar(34, 189, 188)};
  return kPalette[i % kPalette.size()];
}

Marker seriesMarker(size_t i) {
  static const std::array<Marker, 5> kMarkers = {
      Marker::kCircle, Marker::kSquare, Marker::kTriangle, Marker::kDiamond, Marker::kCross};
  return kMarkers[i % kMarkers.size()];
}

cv::Scalar referenceColour() {
  return kBlack;
}

}  // namespace dlo::eval
