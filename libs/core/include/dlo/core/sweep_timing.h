/// \file sweep_timing.h
/// \brief Per-point times of a spinning LiDAR's sweep estimated from the points' azimuths, for
/// inputs that carry none (KITTI `.bin`, PLY, `CObservationPointCloud`), so that their motion
/// distortion can be undone like that of scans with measured times.
#pragma once

#include <deque>
#include <vector>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// How a spinning sensor sweeps, for the cases the points themselves do not tell.
struct SweepTimingParams {
  /// Seconds per revolution (10 Hz sensors: 0.1).
  double period = 0.1;
  /// Spin direction seen from above (z up): -1 clockwise (Velodyne, Ouster, Hesai), +1
  /// counter-clockwise. Used only when the point order does not reveal it.
  int direction = -1;
  /// Azimuth where a sweep begins, degrees counter-clockwise from +x (forward) in the frame of
  /// the points. 180: behind the vehicle (KITTI). Used only when the point order does not
  /// reveal it.
  double start_azimuth_deg = 180.0;
  /// Where in the sweep the scan's timestamp was taken, as a fraction of the revolution from its
  /// start: 0 its first point (MRPT's Velodyne scans), 0.5 its middle (KITTI, whose scans are
  /// stamped when the head faces forward), 1 its end. The estimated times are relative to it.
  double stamp_phase = 0.5;
};

/// What estimateSweepTimes() based the times on.
struct SweepTimingEstimate {
  /// The points are stored in firing order (their azimuth goes round once along the cloud),
  /// and `direction` and `start_azimuth_deg` were read off it; false: the parameters' were
  /// used.
  bool from_order = false;
  int direction = -1;              ///< -1 clockwise, +1 counter-clockwise
  double start_azimuth_deg = 0.0;  ///< degrees counter-clockwise from +x
};

/// Estimates the time of every point of one sweep from its azimuth: a point at azimuth a was
/// measured (phase(a) - stamp_phase) * period seconds after the scan's timestamp, where
/// phase(a) in [0, 1) is the fraction of the revolution from the start azimuth to a in the spin
/// direction. When the points are stored in firing order (the order of time: their azimuth
/// goes round once along the cloud), the spin direction is that in which the azimuth advances
/// along it and the start lies between the last points and the first; otherwise `params`
/// supply both: a shuffled or voxelised cloud has no order, and one stored ring by ring has
/// its driver's order, not the sensor's (KITTI's rings run counter-clockwise from the front,
/// the sensor spins clockwise from behind).
/// In firing order, a point near the seam (where the azimuth is the same at both ends of the
/// sweep: the lasers' azimuth offsets, a sweep that overlaps itself) takes the end its place in
/// the cloud says, so times may reach a little beyond one period.
/// Non-finite points get the stamp's time (0).
/// \param times resized to points.size(), memory reused.
SweepTimingEstimate estimateSweepTimes(const PointCloud& points, const SweepTimingParams& params,
                                       std::vector<float>& times);

/**
 * The revolution period of a spinning sensor read off its scans' timestamps: one scan per
 * revolution, so the period is the interval between consecutive scans. Sensors that cut their
 * sweeps at packet boundaries stamp them a packet early or late (a simulated VLP-16: intervals
 * of 99.53 and 100.86 ms, in a pattern), so the period is the mean of every interval so far
 * within 20 % of the median of the last kWindow: a dropped scan (two periods), a gap in the
 * recording or a repeated stamp does not count. Intervals outside (0, 1] seconds are ignored.
 */
class SweepPeriodEstimate {
 public:
  static constexpr size_t kWindow = 21;

  /// Takes the next scan's timestamp (seconds).
  void add(double time);
  /// Whether at least one interval has been seen.
  bool known() const { return !recent_.empty(); }
  /// The period, or `fallback` before the second scan.
  double period(double fallback) const;

 private:
  std::deque<double> recent_;  ///< the last kWindow intervals
  double sum_ = 0.0;           ///< of the intervals that counted
  size_t counted_ = 0;
  double last_ = 0.0;
  bool has_last_ = false;
};

}  // namespace dlo
