/// \file loop_closure.h
/// \brief Loop-closure candidates among keyframes, and their verification by DLO registration.
#pragma once

#include <utility>
#include <vector>

#include "dlo/core/direct_aligner.h"
#include "dlo/core/height_frame.h"
#include "dlo/slam/slam_map.h"
#include "dlo/slam/slam_params.h"

namespace dlo {

/// How a loop candidate's basin is found.
enum class LoopSearch {
  /// A lattice of starts (+-4 m, +-12 deg) on a coarse grid, the best basins refined at full
  /// resolution, and a candidate refused when another basin fits nearly as well: for a first
  /// loop, whose guess carries all the drift since the place was last seen.
  kLattice,
  /// One registration at full resolution from the guess, accepted only if it stays within
  /// 1.5 m of it: for the next keyframes of a revisit whose first loop passed the lattice
  /// search and corrected the graph, so that their guesses are good (about a tenth of the cost).
  kFromGuess,
};

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

  /// The keyframes (first, last) whose clouds make the side of keyframe `id` in a verification
  /// while the map holds `count` keyframes: loop.submap_keyframes of them centred on `id`, moved
  /// to fit within the map (just `id` for 1).
  std::pair<int, int> submapWindow(int count, int id) const;

  /// Registers keyframe `to`'s cloud against keyframe `from`'s (both of `map`, read back from
  /// its spill file if they left memory), starting at `guess` (pose of `to` in `from`), and
  /// checks the result. On acceptance `edge` holds the loop edge.
  LoopCandidate verify(const SlamMap& map, int from, int to, const Eigen::Isometry3d& guess,
                       PoseEdge& edge, LoopSearch search = LoopSearch::kLattice) const;

 private:
  /// The cloud one side of a verification registers: keyframe `id`'s own (loop.submap_keyframes
  /// = 1), or that of the keyframes around it put in its frame, in `buffer`. Valid until
  /// `buffer` or the map changes.
  const WeightedCloud& submapCloud(const SlamMap& map, int id, WeightedCloud& buffer) const;
  /// The lattice search of LoopSearch::kLattice, on a coarse grid: the best distinct basins
  /// (at most kRefinedBasins, best fit first), to be refined at full resolution; empty if no
  /// start overlapped.
  std::vector<Eigen::Isometry3d> searchBasins(const WeightedCloud& from_cloud,
                                              const WeightedCloud& to_cloud,
                                              const Eigen::Isometry3d& guess) const;
  /// The checks on the refined registrations (best fit, ambiguity, RMS, inliers, correction);
  /// fills `c` (whose from, to and tracked are set) and, on acceptance, `edge`.
  void judge(const std::vector<AlignmentResult>& refined, double selected,
             const Eigen::Isometry3d& guess, LoopCandidate& c, PoseEdge& edge) const;

  SlamParams params_;
  DloParams grid_;    ///< the registration parameters at the verification resolution
  DloParams coarse_;  ///< those of the lattice search's coarse grid
  /// The verification's frames, allocated by the constructor (when loops are enabled) and
  /// rebuilt in place for every candidate: allocated afresh, their megabytes of grids and
  /// gradient fields cost page faults at every verification. Scratch only (a LoopCloser is
  /// used from one thread).
  mutable HeightFrame ref_, cur_, ref_coarse_, cur_coarse_;
};

}  // namespace dlo
