/// \file method_registry.h
/// \brief The odometry methods dlo-bench knows, by name.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dlo/bench/odometry_method.h"

namespace dlo::bench {

/// A benchmarked method: how it is called on the command line, what it does to the points (for
/// the table), and how to make one.
struct MethodSpec {
  std::string name;           ///< e.g. "dlo-paper", "icp"
  std::string preprocessing;  ///< one line for the table's "preprocessing" column
  /// Seconds per frame rather than milliseconds: limited to the benchmark's slow-frame cap.
  bool slow = false;
  std::function<std::unique_ptr<OdometryMethod>()> create;
};

/// Every method this build provides, in table order: dlo-paper, dlo, icp, and with PCL ndt and
/// gicp.
const std::vector<MethodSpec>& availableMethods();

/// The method called `name`, or nullptr.
const MethodSpec* findMethod(const std::string& name);

/// The names of availableMethods(), comma separated (for --help and error messages).
std::string availableMethodNames();

}  // namespace dlo::bench
