/// \file icp_method.h
/// \brief MRPT's point-to-point ICP (mrpt::slam::CICP, 3D), frame to frame.
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/slam/CICP.h>

#include <string>

#include "dlo/bench/classic_preprocessing.h"
#include "dlo/bench/constant_velocity_chain.h"
#include "dlo/bench/odometry_method.h"

namespace dlo::bench {

/// The CICP options the benchmark uses, all set explicitly rather than inherited from MRPT's
/// defaults (which are tuned for 2D laser scans).
mrpt::slam::CICP::TConfigParams benchmarkIcpOptions();

/// Registers each preprocessed scan (a CSimplePointsMap of voxel centroids) against the
/// previous one with CICP::Align3DPDF, starting from the constant-velocity guess.
class IcpFrameToFrame : public OdometryMethod {
 public:
  explicit IcpFrameToFrame(const ClassicPreprocessing& preprocessing = ClassicPreprocessing(),
                           const mrpt::slam::CICP::TConfigParams& options = benchmarkIcpOptions());
  Eigen::Isometry3d process(double time, const PointCloud& points,
                            const std::vector<float>& point_times) override;

  /// Preprocessing and ICP settings, one line for the benchmark table.
  static std::string describe(const ClassicPreprocessing& preprocessing,
                              const mrpt::slam::CICP::TConfigParams& options);

 private:
  ClassicPreprocessing preprocessing_;
  mrpt::slam::CICP icp_;
  ConstantVelocityChain chain_;
  mrpt::maps::CSimplePointsMap previous_;
};

}  // namespace dlo::bench
