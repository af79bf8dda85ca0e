#include "dlo/eval/evaluation_figures.h"

#include "dlo/eval/plot2d.h"

namespace dlo::eval {

namespace {

std::vector<cv::Point2d> topView(const metrics::Trajectory& trajectory) {
  std::vector<cv::Point2d> points;
  points.reserve(trajectory.size());
  for (const Eigen::Isometry3d& pose : trajectory.poses) {
    points.emplace_back(pose.translation().x(), pose.translation().y());
  }
  return points;
}

}  // namespace

cv::Mat trajectoriesFigure(const metrics::Trajectory& ground_truth,
                           const std::vector<LabelledEvaluation>& estimates, cv::Size size) {
  Plot2D plot(size);
  plot.setTitle("Trajectories (top view)");
  plot.setAxisLabels("x [m]", "y [m]");
  plot.setEqualAspect(true);
  PlotSeries gt;
  gt.label = "ground truth";
  gt.points = topView(ground_truth);
  gt.colour = referenceColour();
  // Wider than the estimates drawn over it, so the reference stays visible along both edges.
  gt.thickness = 4;
  plot.addSeries(gt);
  for (size_t i = 0; i < estimates.size(); ++i) {
    PlotSeries s;
    s.label = estimates[i].label;
    s.points = topView(estimates[i].evaluation.aligned);
    s.colour = seriesColour(i);
    plot.addSeries(s);
  }
  return plot.render();
}

cv::Mat positionErrorFigure(const std::vector<LabelledEvaluation>& estimates, cv::Size size) {
  Plot2D plot(size);
  plot.setTitle("Position error after alignment");
  plot.setAxisLabels("ground-truth frame", "position error [m]");
  plot.setYIncludesZero(true);
  for (size_t i = 0; i < estimates.size(); ++i) {
    const EstimateEvaluation& ev = estimates[i].evaluation;
    PlotSeries s;
    s.label = estimates[i].label;
    s.colour = seriesColour(i);
    for (size_t k = 0; k < ev.position_errors.size(); ++k) {
      s.points.emplace_back(static_cast<double>(ev.reference_frames[k]), ev.position_errors[k]);
    }
    plot.addSeries(s);
  }
  return plot.render();
}

cv::Mat driftFigure(const std::vector<LabelledEvaluation>& estimates, cv::Size size) {
  Plot2D plot(size);
  plot.setTitle("KITTI translational drift per segment length");
  plot.setAxisLabels("segment length [m]", "translational drift [%]");
  plot.setYIncludesZero(true);
  for (size_t i = 0; i < estimates.size(); ++i) {
    PlotSeries s;
    s.label = estimates[i].label;
    s.colour = seriesColour(i);
    s.marker = seriesMarker(i);
    for (const metrics::KittiLengthError& l : estimates[i].evaluation.kitti.per_length) {
      s.points.emplace_back(l.length, l.translation_percent);
    }
    plot.addSeries(s);
  }
  return plot.render();
}

}  // namespace dlo::eval
