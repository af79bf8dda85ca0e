/// \file trajectory_overlay.h
/// \brief Top view of the ground truth and every method's trajectory in one image.
#pragma once

#include <opencv2/core/mat.hpp>
#include <string>
#include <utility>
#include <vector>

#include "dlo/metrics/trajectory.h"

namespace dlo::bench {

/// Draws the x-y plane with equal scale on both axes: the ground truth in black and each
/// estimate in its own colour, each aligned to the ground truth with the same SE(3) Umeyama
/// transform the ATE uses (estimates start in their first scan's frame), a 10 m grid, a scale
/// label and a legend. Estimates that match fewer than 3 ground-truth poses are drawn unaligned.
cv::Mat drawTrajectoryOverlay(
    const metrics::Trajectory& ground_truth,
    const std::vector<std::pair<std::string, metrics::Trajectory>>& estimates,
    cv::Size size = cv::Size(1200, 900));

}  // namespace dlo::bench
