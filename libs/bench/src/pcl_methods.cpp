#include "dlo/bench/pcl_methods.h"

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/gicp.h>
#include <pcl/registration/ndt.h>

#include <cstdio>
#include <memory>

#include "dlo/bench/classic_preprocessing.h"
#include "dlo/bench/constant_velocity_chain.h"

namespace dlo::bench {

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/// Settings of both PCL registrators, set explicitly (PCL's defaults differ between versions).
struct PclSettings {
  /// metres; NDT cell side. 1 m (PCL's tutorial value) drifted 15 % on the simulated 500-sweep
  /// drive with 0.3 m voxels (ATE 2.8 m over 100 scans); 2 m cells 6.6 % (ATE 0.77 m).
  double ndt_resolution = 2.0;
  double ndt_step = 0.1;           ///< metres; More-Thuente line search maximum step
  double gicp_max_distance = 1.0;  ///< metres; correspondence rejection distance
  int gicp_neighbours = 20;        ///< points per local covariance
  int max_iterations = 50;
  double transformation_epsilon = 1e-4;
};

/// A PCL registration (anything with setInputSource/Target and align) chained frame to frame.
template <class Registration>
class PclFrameToFrame : public OdometryMethod {
 public:
  PclFrameToFrame(std::unique_ptr<Registration> registration,
                  const ClassicPreprocessing& preprocessing)
      : registration_(std::move(registration)), preprocessing_(preprocessing) {}

  Eigen::Isometry3d process(double time, const PointCloud& points,
                            const std::vector<float>& point_times) override {
    const PointCloud cloud = preprocessScan(points, point_times, chain_.velocity(), preprocessing_);
    Cloud::Ptr current(new Cloud);
    current->reserve(cloud.size());
    for (const auto& p : cloud) current->push_back(pcl::PointXYZ(p.x(), p.y(), p.z()));

    Eigen::Isometry3d motion = chain_.predictedMotion();
    if (chain_.size() > 0 && !current->empty() && previous_ && !previous_->empty()) {
      // Source = this scan, target = the previous one: the result is this scan's pose in the
      // previous scan's frame.
      registration_->setInputSource(current);
      registration_->setInputTarget(previous_);
      Cloud aligned;
      registration_->align(aligned, motion.matrix().cast<float>());
      if (registration_->hasConverged()) {
        motion.matrix() = registration_->getFinalTransformation().template cast<double>();
      }
    }
    previous_ = current;
    return chain_.advance(time, motion);
  }

 private:
  std::unique_ptr<Registration> registration_;
  ClassicPreprocessing preprocessing_;
  ConstantVelocityChain chain_;
  Cloud::Ptr previous_;
};

using Ndt = pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ>;
using Gicp = pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ>;

std::unique_ptr<OdometryMethod> makeNdt(const PclSettings& s, const ClassicPreprocessing& pre) {
  auto ndt = std::make_unique<Ndt>();
  ndt->setResolution(static_cast<float>(s.ndt_resolution));
  ndt->setStepSize(s.ndt_step);
  ndt->setMaximumIterations(s.max_iterations);
  ndt->setTransformationEpsilon(s.transformation_epsilon);
  return std::make_unique<PclFrameToFrame<Ndt>>(std::move(ndt), pre);
}

std::unique_ptr<OdometryMethod> makeGicp(const PclSettings& s, const ClassicPreprocessing& pre) {
  auto gicp = std::make_unique<Gicp>();
  gicp->setMaxCorrespondenceDistance(s.gicp_max_distance);
  gicp->setCorrespondenceRandomness(s.gicp_neighbours);
  gicp->setMaximumIterations(s.max_iterations);
  gicp->setTransformationEpsilon(s.transformation_epsilon);
  return std::make_unique<PclFrameToFrame<Gicp>>(std::move(gicp), pre);
}

}  // namespace

std::vector<MethodSpec> pclMethods() {
  const PclSettings s;
  const ClassicPreprocessing pre;
  char ndt_text[160], gicp_text[160];
  std::snprintf(ndt_text, sizeof ndt_text, "%s; PCL NDT, cells %.1f m, step %.2f m, %d it",
                pre.describe().c_str(), s.ndt_resolution, s.ndt_step, s.max_iterations);
  std::snprintf(gicp_text, sizeof gicp_text, "%s; PCL GICP, max dist %.1f m, k %d, %d it",
                pre.describe().c_str(), s.gicp_max_distance, s.gicp_neighbours, s.max_iterations);
  return {
      {"ndt", ndt_text, true, [s, pre] { return makeNdt(s, pre); }},
      {"gicp", gicp_text, true, [s, pre] { return makeGicp(s, pre); }},
  };
}

}  // namespace dlo::bench
