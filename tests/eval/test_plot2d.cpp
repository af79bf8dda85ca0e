// Specification of the plotting used by the evaluation figures: ticks, axis mapping, equal
// aspect, legend.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "dlo/eval/axis_ticks.h"
#include "dlo/eval/plot2d.h"

namespace dlo::eval {
namespace {

/// Pixels of `image` inside `roi` with exactly colour `bgr`.
int countColour(const cv::Mat& image, const cv::Scalar& bgr, cv::Rect roi = cv::Rect()) {
  if (roi.area() == 0) roi = cv::Rect(0, 0, image.cols, image.rows);
  cv::Mat mask;
  cv::inRange(image(roi), bgr, bgr, mask);
  return cv::countNonZero(mask);
}

PlotSeries line(std::vector<cv::Point2d> points, cv::Scalar colour, std::string label) {
  PlotSeries s;
  s.points = std::move(points);
  s.colour = colour;
  s.label = std::move(label);
  return s;
}

TEST(AxisTicks, AreMultiplesOfOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_EQ(niceTicks(0.0, 10.0, 6), (std::vector<double>{0, 2, 4, 6, 8, 10}));
  EXPECT_DOUBLE_EQ(niceTickStep(-0.3, 0.7, 6), 0.2);
  EXPECT_DOUBLE_EQ(niceTickStep(0.0, 850.0, 10), 100.0);
  EXPECT_DOUBLE_EQ(niceTickStep(0.0, 0.04, 5), 0.01);
  const std::vector<double> t = niceTicks(-0.3, 0.7, 6);
  ASSERT_FALSE(t.empty());
  EXPECT_GE(t.front(), -0.3);
  EXPECT_LE(t.back(), 0.7);
  EXPECT_LE(t.size(), 6u);
}

TEST(AxisTicks, LabelsHaveJustTheDecimalsOfTheStepAndNoNegativeZero) {
  EXPECT_EQ(tickLabel(10.0, 5.0), "10");
  EXPECT_EQ(tickLabel(0.5, 0.5), "0.5");
  EXPECT_EQ(tickLabel(-0.25, 0.05), "-0.25");
  EXPECT_EQ(tickLabel(-1e-12, 0.2), "0.0");
  EXPECT_EQ(tickLabel(-1e-12, 20.0), "0");
}

TEST(Plot2D, MapsFixedRangesOntoTheCornersOfThePlotArea) {
  Plot2D plot(cv::Size(800, 600));
  plot.setXRange(0.0, 10.0);
  plot.setYRange(-5.0, 5.0);
  const PlotFrame f = plot.frame();
  const cv::Point2d bottom_left = f.toPixel({0.0, -5.0});
  const cv::Point2d top_right = f.toPixel({10.0, 5.0});
  EXPECT_DOUBLE_EQ(bottom_left.x, f.area.x);
  EXPECT_DOUBLE_EQ(bottom_left.y, f.area.y + f.area.height);
  EXPECT_DOUBLE_EQ(top_right.x, f.area.x + f.area.width);
  EXPECT_DOUBLE_EQ(top_right.y, f.area.y);
  const cv::Point2d centre = f.toPixel({5.0, 0.0});
  EXPECT_DOUBLE_EQ(centre.x, f.area.x + 0.5 * f.area.width);
  EXPECT_DOUBLE_EQ(centre.y, f.area.y + 0.5 * f.area.height);
  EXPECT_TRUE(cv::Rect(0, 0, 800, 600).contains(f.area.br() - cv::Point(1, 1)));
}

TEST(Plot2D, AutomaticRangesContainTheDataAndStartAtZeroWhenAsked) {
  Plot2D plot(cv::Size(800, 600));
  plot.addSeries(line({{2.0, 0.5}, {8.0, 3.0}}, seriesColour(0), ""));
  plot.setYIncludesZero(true);
  const PlotFrame f = plot.frame();
  EXPECT_LT(f.x.min, 2.0);
  EXPECT_GT(f.x.max, 8.0);
  EXPECT_DOUBLE_EQ(f.y.min, 0.0);
  EXPECT_GT(f.y.max, 3.0);
  EXPECT_TRUE(f.legend.empty());
}

TEST(Plot2D, EqualAspectUsesOneScaleForBothAxes) {
  Plot2D plot(cv::Size(1000, 750));
  plot.setEqualAspect(true);
  plot.addSeries(line({{0.0, 0.0}, {100.0, 10.0}}, seriesColour(0), ""));
  const PlotFrame f = plot.frame();
  EXPECT_NEAR(f.x.span() / f.area.width, f.y.span() / f.area.height, 1e-12);
  EXPECT_LE(f.x.min, 0.0);
  EXPECT_GE(f.x.max, 100.0);
  EXPECT_LE(f.y.min, 0.0);
  EXPECT_GE(f.y.max, 10.0);
  // A 10 m square is as wide as it is tall on the image.
  const cv::Point2d a = f.toPixel({0, 0}), b = f.toPixel({10, 10});
  EXPECT_NEAR(b.x - a.x, a.y - b.y, 1e-9);
}

TEST(Plot2D, DrawsACurveThroughItsMappedPixels) {
  Plot2D plot(cv::Size(600, 400));
  const cv::Scalar colour = seriesColour(2);
  PlotSeries s = line({{0.0, 0.0}, {10.0, 10.0}}, colour, "");
  s.thickness = 5;
  plot.addSeries(s);
  const cv::Mat image = plot.render();
  const cv::Point2d mid = plot.frame().toPixel({5.0, 5.0});
  const cv::Vec3b pixel = image.at<cv::Vec3b>(static_cast<int>(mid.y), static_cast<int>(mid.x));
  EXPECT_EQ(pixel, cv::Vec3b(colour[0], colour[1], colour[2]));
}

TEST(Plot2D, LegendShowsTheColourOfEachLabelledSeriesOnly) {
  Plot2D plot(cv::Size(800, 600));
  plot.addSeries(line({{0, 0}, {1, 1}}, seriesColour(0), "first"));
  plot.addSeries(line({{0, 1}, {1, 0}}, seriesColour(1), "second"));
  plot.addSeries(line({{0, 0.5}, {1, 0.5}}, seriesColour(2), ""));
  const PlotFrame f = plot.frame();
  ASSERT_FALSE(f.legend.empty());
  EXPECT_TRUE(cv::Rect(f.area).contains(f.legend.tl()));
  const cv::Mat image = plot.render();
  EXPECT_GT(countColour(image, seriesColour(0), f.legend), 50);
  EXPECT_GT(countColour(image, seriesColour(1), f.legend), 50);
  EXPECT_EQ(countColour(image, seriesColour(2), f.legend), 0);
}

TEST(Plot2D, LegendGoesToTheCornerWithTheLeastData) {
  Plot2D plot(cv::Size(800, 600));
  std::vector<cv::Point2d> top_right_cluster;
  for (int i = 0; i <= 20; ++i) top_right_cluster.emplace_back(8.0 + 0.1 * i, 8.0 + 0.1 * i);
  PlotSeries s = line(top_right_cluster, seriesColour(0), "cluster");
  s.connect = false;
  s.marker = Marker::kCircle;
  plot.addSeries(s);
  plot.setXRange(0, 10);
  plot.setYRange(0, 10);
  const PlotFrame f = plot.frame();
  for (const cv::Point2d& p : top_right_cluster) {
    const cv::Point2d px = f.toPixel(p);
    EXPECT_FALSE(f.legend.contains(cv::Point(static_cast<int>(px.x), static_cast<int>(px.y))));
  }
}

TEST(Plot2D, SeriesColoursAreDistinctAndNotTheReferenceBlack) {
  for (size_t i = 0; i < 8; ++i) {
    EXPECT_NE(seriesColour(i), referenceColour());
    for (size_t j = i + 1; j < 8; ++j) EXPECT_NE(seriesColour(i), seriesColour(j));
  }
}

}  // namespace
}  // namespace dlo::eval
