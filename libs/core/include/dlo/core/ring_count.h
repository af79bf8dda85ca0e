/// \file ring_count.h
/// \brief How many laser rings a spinning LiDAR's sweep has, read off the points' elevations:
/// the evidence that picks a sensor profile when the input does not name its sensor.
#pragma once

#include <Eigen/Geometry>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// The rings found in one sweep.
struct RingEstimate {
  /// Rings found (elevations where points gather), 0 when the sweep shows none.
  int rings = 0;
  /// Median elevation step between neighbouring rings, degrees (0 with fewer than two rings).
  double spacing_deg = 0.0;
  /// Fraction of the points used (3 to 120 m from the sensor) that lie on the rings found: near
  /// 1 for a spinning sensor seen from its own origin; low when the points do not come in rings
  /// (a solid-state sensor, a merged or tilted cloud, a sensor far from the cloud's origin).
  double on_rings = 0.0;
  /// Fraction of the occupied elevation span that the rings cover: small for a comb of rings
  /// (a simulated HDL-64: 0.2), near 1 where the elevations blur into each other (lasers with
  /// origins of their own, as the real HDL-64's, seen from close by).
  double coverage = 0.0;
  /// Points used (finite, 3 to 120 m from the origin horizontally).
  size_t points = 0;
  /// The estimate can be trusted: at least 1000 points used, at least 4 rings, 80 % of the
  /// points on them, and gaps between them (coverage at most a half).
  bool reliable() const {
    return points >= 1000 && rings >= 4 && on_rings >= 0.8 && coverage <= 0.5;
  }
};

/// Finds the rings of a sweep whose points are moved into the sensor's frame by `to_sensor`: every
/// laser of a spinning sensor keeps one elevation angle, so the histogram of the points'
/// elevations (0.05 degree bins) is a comb whose teeth are the rings. A tooth is a run of bins
/// each holding at least a fifth of the mean count per bin over the occupied elevation span.
RingEstimate estimateRings(const PointCloud& points,
                           const Eigen::Isometry3f& to_sensor = Eigen::Isometry3f::Identity());

}  // namespace dlo
