// The benchmark's initial-guess policy and pose chaining.
#include <gtest/gtest.h>

#include "dlo/bench/constant_velocity_chain.h"
#include "dlo/core/rigid_transform.h"

namespace dlo::bench {
namespace {

TEST(ConstantVelocityChain, PredictsTheLastMotionRepeated) {
  ConstantVelocityChain chain;
  EXPECT_TRUE(chain.predictedMotion().isApprox(Eigen::Isometry3d::Identity()));
  const Eigen::Isometry3d motion = poseFromXYZYPR(0.8, 0.1, 0.0, 0.05, 0.0, 0.0);
  EXPECT_TRUE(chain.advance(0.0, motion).isApprox(Eigen::Isometry3d::Identity()))
      << "the first scan is the origin whatever the motion";
  const Eigen::Isometry3d p1 = chain.advance(0.1, motion);
  EXPECT_TRUE(p1.isApprox(motion));
  // guess_k = pose_{k-1} * (pose_{k-2}^-1 pose_{k-1}): the relative part is the last motion.
  EXPECT_TRUE(chain.predictedMotion().isApprox(motion));
  const Eigen::Isometry3d p2 = chain.advance(0.2, chain.predictedMotion());
  EXPECT_TRUE(p2.isApprox(p1 * (Eigen::Isometry3d::Identity().inverse() * p1)));
  EXPECT_EQ(chain.size(), 3u);
}

TEST(ConstantVelocityChain, VelocityIsTheLastMotionPerSecond) {
  ConstantVelocityChain chain;
  EXPECT_TRUE(chain.velocity().isZero());
  const Eigen::Isometry3d motion = poseFromXYZYPR(1.0, 0.0, 0.0, 0.1, 0.0, 0.0);
  chain.advance(10.0, Eigen::Isometry3d::Identity());
  chain.advance(10.5, motion);
  EXPECT_TRUE(chain.velocity().isApprox(logSE3(motion) / 0.5));
}

}  // namespace
}  // namespace dlo::bench
