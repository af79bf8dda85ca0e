/// \file deskew.h
/// \brief Motion compensation of a rotating-LiDAR sweep with a constant-velocity model.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <vector>

#include "dlo/core/point_cloud.h"
#include "dlo/core/rigid_transform.h"

namespace dlo {

/// A pose as a row-major 3 x 4 matrix [R | t] of floats, the layout the point loops read.
struct RowMajorPose {
  RowMajorPose() = default;
  explicit RowMajorPose(const Eigen::Isometry3f& pose);
  /// R p + t, each row summed left to right: the vectorised rasterisation follows the same
  /// order, so a cloud moved by this and one moved while rasterised fall in the same cells.
  void apply(float px, float py, float pz, float& x, float& y, float& z) const {
    x = m[0] * px + m[1] * py + m[2] * pz + m[3];
    y = m[4] * px + m[5] * py + m[6] * pz + m[7];
    z = m[8] * px + m[9] * py + m[10] * pz + m[11];
  }
  Eigen::Vector3f operator*(const Eigen::Vector3f& p) const {
    Eigen::Vector3f q;
    apply(p.x(), p.y(), p.z(), q.x(), q.y(), q.z());
    return q;
  }
  float m[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};  ///< identity by default
};

/// The motion of the vehicle during one sweep, tabulated so that it can be applied point by point
/// while the points are used for something else (rasterised), with no deskewed copy of the cloud.
/// Point i was measured at `times[i]` seconds (relative to the reference, t = 0) in the vehicle
/// frame of that instant; with a constant body twist `velocity` (per second: the motion between
/// two sweeps is expSE3(velocity * dt)) the vehicle pose at t relative to t = 0 is
/// expSE3(velocity * t). Times are quantised to `bins` steps over their range, which bounds the
/// error to (speed * range / bins) while costing `bins` matrix exponentials instead of one per
/// point.
class SweepMotion {
 public:
  /// No motion: apply() returns points unchanged.
  SweepMotion() = default;
  /// Tabulates the motion over the range of `times`, which must outlive this object. Empty
  /// (identity) when `times` is empty or bins < 1.
  SweepMotion(const std::vector<float>& times, const Vector6d& velocity, int bins = 128);

  /// True when there is no motion to apply.
  bool empty() const { return times_ == nullptr; }
  /// Whether apply() can be used for a cloud of `points` points (one time per point).
  bool fits(size_t points) const { return times_ != nullptr && times_->size() == points; }

  /// Point `p`, measured at times[i], expressed in the vehicle frame at t = 0. Only valid
  /// when !empty().
  Eigen::Vector3f apply(size_t i, const Eigen::Vector3f& p) const {
    return motion_[static_cast<size_t>(bin((*times_)[i]))] * p;
  }
  /// apply(first + k, p[k]) for k in [0, n), into out[0, n): the same points, their bins found
  /// several at a time (bins()). Only valid when the cloud of p fits().
  void apply(size_t first, const Eigen::Vector3f* p, size_t n, Eigen::Vector3f* out) const;
  /// The bin of a point measured at time `t`: the nearest of 0..bins(). Only valid when
  /// !empty().
  int bin(float t) const {
    // The nearest bin, as std::lround would round (half away from zero) but without a library
    // call per point: f - trunc(f) is exact for these magnitudes.
    const float f = (t - lo_) / span_ * static_cast<float>(bins_);
    const int i = static_cast<int>(f);
    return std::clamp(i + (f - static_cast<float>(i) >= 0.5f ? 1 : 0), 0, bins_);
  }
  /// bin(t[k]) for k in [0, n), into out[0, n): the same bins, several at a time. Only valid
  /// when !empty().
  void bins(const float* t, size_t n, int* out) const;
  /// Number of time steps; bins() + 1 poses are tabulated.
  int bins() const { return bins_; }
  /// Per-point times (only valid when !empty()).
  const std::vector<float>& times() const { return *times_; }
  /// Pose of bin `b` (0..bins()).
  const RowMajorPose& pose(int b) const { return motion_[static_cast<size_t>(b)]; }

 private:
  const std::vector<float>* times_ = nullptr;
  float lo_ = 0.0f;
  float span_ = 1.0f;  ///< seconds from the first to the last time
  int bins_ = 0;
  std::vector<RowMajorPose> motion_;  ///< pose of bin b, bins + 1 entries
};

/// Expresses every point in the vehicle frame at the sweep's reference time (t = 0); see
/// SweepMotion for the model.
/// \return `points` unchanged if `times` is empty or of a different size.
PointCloud deskew(const PointCloud& points, const std::vector<float>& times,
                  const Vector6d& velocity, int bins = 128);
/// The same with a tabulated motion, e.g. to materialise the cloud a fused rasterisation did
/// not need. \return `points` unchanged if `motion` does not fit them.
PointCloud deskew(const PointCloud& points, const SweepMotion& motion);
/// In-place form: writes the deskewed cloud into `out`, reusing its memory (a fresh 1.4 MB
/// vector per HDL-64 sweep costs its page faults every time). `out` = `points` if `motion` does
/// not fit them.
void deskew(const PointCloud& points, const SweepMotion& motion, PointCloud& out);

}  // namespace dlo
