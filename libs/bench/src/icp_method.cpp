#include "dlo/bench/icp_method.h"

#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <cstdio>

#include "dlo/mrpt/pose_conversion.h"

namespace dlo::bench {

mrpt::slam::CICP::TConfigParams benchmarkIcpOptions() {
  mrpt::slam::CICP::TConfigParams o;
  o.ICP_algorithm = mrpt::slam::icpClassic;
  o.maxIterations = 80;
  // The guess is good to a few decimetres at driving speed; pairs farther apart than 1 m at the
  // start are not the same surface. The threshold halves (ALFA) at each convergence down to the
  // voxel size, below which point-to-point pairs of voxel centroids carry no information.
  o.thresholdDist = 1.0;
  o.thresholdAng = 0.15 * M_PI / 180.0;
  o.ALFA = 0.5;
  o.smallestThresholdDist = 0.2;
  o.minAbsStep_trans = 1e-4;
  o.minAbsStep_rot = 1e-4;
  o.onlyUniqueRobust = false;
  o.doRANSAC = false;
  // Every point is matched: decimating queries trades accuracy for speed, and the voxel filter
  // already did the thinning.
  o.corresponding_points_decimation = 1;
  o.skip_cov_calculation = true;
  o.skip_quality_calculation = true;
  return o;
}

std::string IcpFrameToFrame::describe(const ClassicPreprocessing& preprocessing,
                                      const mrpt::slam::CICP::TConfigParams& options) {
  char text[160];
  std::snprintf(text, sizeof text, "%s; CICP 3D classic, %u it, thr %.2f->%.2f m, ALFA %.1f",
                preprocessing.describe().c_str(), options.maxIterations, options.thresholdDist,
                options.smallestThresholdDist, options.ALFA);
  return text;
}

IcpFrameToFrame::IcpFrameToFrame(const ClassicPreprocessing& preprocessing,
                                 const mrpt::slam::CICP::TConfigParams& options)
    : preprocessing_(preprocessing), icp_(options) {}

Eigen::Isometry3d IcpFrameToFrame::process(double time, const PointCloud& points,
                                           const std::vector<float>& point_times) {
  const PointCloud cloud = preprocessScan(points, point_times, chain_.velocity(), preprocessing_);
  mrpt::maps::CSimplePointsMap current;
  current.reserve(cloud.size());
  for (const auto& p : cloud) current.insertPointFast(p.x(), p.y(), p.z());

  Eigen::Isometry3d motion = chain_.predictedMotion();
  if (chain_.size() > 0 && !current.isEmpty() && !previous_.isEmpty()) {
    mrpt::poses::CPose3DPDFGaussian guess;
    guess.mean = toCPose3D(motion);
    guess.cov.setDiagonal(1.0);
    // Align3DPDF(m1, m2) returns the pose of m2's frame in m1's: of this scan in the previous.
    const auto pdf = icp_.Align3DPDF(&previous_, &current, guess);
    if (pdf) motion = toIsometry(pdf->getMeanVal());
  }
  previous_ = std::move(current);
  return chain_.advance(time, motion);
}

}  // namespace dlo::bench
