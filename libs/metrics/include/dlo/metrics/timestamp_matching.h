/// \file timestamp_matching.h
/// \brief Pairing the poses of two trajectories stamped by different clocks or rates.
#pragma once

#include <utility>
#include <vector>

#include "dlo/metrics/trajectory.h"

namespace dlo::metrics {

/// Index pairs (estimate, reference) whose timestamps differ by at most `max_dt` seconds. Each
/// estimate pose is paired with the reference pose nearest in time; a reference pose is used at
/// most once (the closer estimate wins), so errors are not counted twice. Pairs are in
/// increasing time. Timestamps of each trajectory must be non-decreasing.
std::vector<std::pair<size_t, size_t>> matchTimestamps(const Trajectory& estimate,
                                                       const Trajectory& reference, double max_dt);

/// The two trajectories restricted to matched poses, in matching order: the first holds
/// estimate poses, the second the reference poses at the same indices.
std::pair<Trajectory, Trajectory> matchedTrajectories(const Trajectory& estimate,
                                                      const Trajectory& reference, double max_dt);

}  // namespace dlo::metrics
