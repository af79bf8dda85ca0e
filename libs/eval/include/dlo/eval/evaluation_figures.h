/// \file evaluation_figures.h
/// \brief The evaluation figures: top view of the trajectories, position error per frame, and
/// KITTI drift per segment length, each with every estimate overlaid and a legend.
#pragma once

#include <opencv2/core.hpp>
#include <vector>

#include "dlo/eval/evaluation_report.h"
#include "dlo/metrics/trajectory.h"

namespace dlo::eval {

/// Size of every figure, pixels: large enough for a paper column at 300 dpi after scaling.
const cv::Size kFigureSize(1000, 750);

/// Top view (x-y, equal scale, metres) of `ground_truth` in black and each estimate after its
/// ATE alignment in seriesColour(i), with a legend of the labels.
cv::Mat trajectoriesFigure(const metrics::Trajectory& ground_truth,
                           const std::vector<LabelledEvaluation>& estimates,
                           cv::Size size = kFigureSize);

/// Position error after alignment (metres) against the ground-truth frame index.
cv::Mat positionErrorFigure(const std::vector<LabelledEvaluation>& estimates,
                            cv::Size size = kFigureSize);

/// KITTI translational drift (%) against segment length (metres), markers joined by lines.
cv::Mat driftFigure(const std::vector<LabelledEvaluation>& estimates, cv::Size size = kFigureSize);

}  // namespace dlo::eval
