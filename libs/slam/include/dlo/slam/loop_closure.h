/// \file loop_closure.h
/// \brief Loop-closure candidates among keyframes, and their verification by DLO registration.
#pragma once

#include <vector>

#include "dlo/core/direct_aligner.h"
#include "dlo/slam/slam_map.h"
#include "dlo/slam/slam_params.h"

namespace dlo {

/// Finds and verifies loops. A candidate is an older keyframe near the newest one's estimate but
/// far back along the path; it is accepted only if registering the two keyframes' clouds gives
/// a well-conditioned, low-residual, consistent answer, so that a wrong loop is rejected rather
/// than bending the map.
class LoopCloser {
 public:
  explicit LoopCloser(const SlamParams& params);

  /// Keyframes that may close a loop with keyframe `newest`, nearest first.
  /// \param path_length metres travelled up to each keyframe.
  std::vector<int> candidates(const SlamMap& map, int newest,
                              const std::vector<double>& path_length) const;

  /// Registers keyframe `to`'s cloud against keyframe `from`'s (both of `map`, read back from
  /// its spill file if they left memory), starting at `guess` (pose of `to` in `from`), and
  /// checks the result. On acceptance `edge` holds the loop edge.
  LoopCandidate verify(const SlamMap& map, int from, int to, const Eigen::Isometry3d& guess,
                       PoseEdge& edge) const;

 private:
  SlamParams params_;
  DloParams grid_;  ///< the registration parameters at the verification resolution
};

}  // namespace dlo
