/// \file pcl_methods.h
/// \brief PCL's 3D-NDT (the paper's baseline) and GICP, frame to frame; built only with PCL.
#pragma once

#include <vector>

#include "dlo/bench/method_registry.h"

namespace dlo::bench {

/// "ndt" (pcl::NormalDistributionsTransform) and "gicp" (pcl::GeneralizedIterativeClosestPoint),
/// each registering the preprocessed scan against the previous one from the constant-velocity
/// guess. Both are slow methods.
std::vector<MethodSpec> pclMethods();

}  // namespace dlo::bench
