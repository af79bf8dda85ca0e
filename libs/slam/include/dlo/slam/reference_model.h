/// \file reference_model.h
/// \brief What each scan is registered against (odometry.reference), behind one interface: the
/// previous scan (the paper's frame to frame), the last keyframe, a height map fused from the
/// recent keyframes, or a world-fixed height map of the recent scans.
#pragma once

#include <Eigen/Geometry>
#include <deque>
#include <memory>
#include <optional>
#include <utility>

#include "dlo/core/height_frame.h"
#include "dlo/core/local_height_map.h"
#include "dlo/core/point_cloud.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/slam/slam_params.h"

namespace dlo {

/// The reference of dlo::LidarOdometry. It holds the frame scans are registered against and
/// its pose in the odometry frame; the odometry tells it about keyframes and about each scan
/// once its pose is decided, and each kind keeps its reference up to date from those.
class ReferenceModel {
 public:
  /// The model odometry.reference names, with the parameters it needs (a copy is kept).
  static std::unique_ptr<ReferenceModel> make(const SlamParams& params);

  virtual ~ReferenceModel() = default;
  /// A copy of this model with everything it holds (a copied odometry continues alike).
  virtual std::unique_ptr<ReferenceModel> clone() const = 0;

  /// There is a reference to register against (false until the first scan is in).
  bool ready() const { return ready_; }
  /// The reference's grids.
  const HeightFrame& frame() const { return frame_; }
  /// Where frame() lies in the odometry frame.
  const Eigen::Isometry3d& pose() const { return pose_; }

  /// The scan is deskewed into a copy of its points (the scan map reads them twice: its grid
  /// and the map); otherwise it is deskewed while it is rasterised.
  virtual bool deskewsACopy() const { return false; }
  /// How the current scan's frame is built: also as the next reference (frame to frame), or
  /// only as the current scan.
  virtual FrameUse currentUse() const { return FrameUse::kCurrentOnly; }
  /// Keyframes make the reference: their clouds at odometry.keyframe_voxel are wanted
  /// (addKeyframe()), and a poor fit can call for a new one (odometry.keyframe_max_rms).
  virtual bool madeOfKeyframes() const { return false; }

  /// A new keyframe at `pose` (odometry frame) with its cloud at odometry.keyframe_voxel
  /// (vehicle frame; empty unless madeOfKeyframes()).
  virtual void addKeyframe(const Eigen::Isometry3d& pose, WeightedCloud fine);
  /// The scan whose pose was just decided: `current` its frame (built with currentUse()),
  /// `points` its points as deskewed (vehicle frame) and `measured` whether its pose was
  /// measured (the first scan, or registered and not rejected); false for a scan whose
  /// registration was rejected or failed.
  virtual void afterScan(HeightFrame& current, const PointCloud& points,
                         const Eigen::Isometry3d& pose, bool measured);
  /// The first scan again, deskewed now that the second gave a velocity: `points` (vehicle
  /// frame) at `pose`, `fine` its cloud at odometry.keyframe_voxel.
  virtual void redoFirstScan(const PointCloud& points, const Eigen::Isometry3d& pose,
                             WeightedCloud fine);
  /// A run of rejected registrations ended by believing one again: what the reference holds
  /// may be what went wrong.
  virtual void restartAfterRejections() {}

 protected:
  explicit ReferenceModel(const SlamParams& params) : params_(params) {}
  ReferenceModel(const ReferenceModel&) = default;
  ReferenceModel& operator=(const ReferenceModel&) = default;

  SlamParams params_;
  HeightFrame frame_;
  Eigen::Isometry3d pose_ = Eigen::Isometry3d::Identity();
  bool ready_ = false;
};

/// odometry.reference = previous: each scan is the next one's reference (the paper).
class PreviousScanReference : public ReferenceModel {
 public:
  explicit PreviousScanReference(const SlamParams& params) : ReferenceModel(params) {}
  std::unique_ptr<ReferenceModel> clone() const override {
    return std::make_unique<PreviousScanReference>(*this);
  }
  FrameUse currentUse() const override { return FrameUse::kCurrentAndReference; }
  void afterScan(HeightFrame& current, const PointCloud& points, const Eigen::Isometry3d& pose,
                 bool measured) override;
};

/// odometry.reference = keyframe (the last keyframe) or keyframe_map (the last
/// odometry.local_map_keyframes keyframes, none farther than odometry.local_map_extent from the
/// newest, fused in one grid anchored at the newest): the reference changes only with a
/// keyframe.
class KeyframeMapReference : public ReferenceModel {
 public:
  /// `keyframes`: how many recent keyframes make the reference (1: the last keyframe).
  KeyframeMapReference(const SlamParams& params, size_t keyframes)
      : ReferenceModel(params), keyframes_(keyframes) {}
  std::unique_ptr<ReferenceModel> clone() const override {
    return std::make_unique<KeyframeMapReference>(*this);
  }
  bool madeOfKeyframes() const override { return true; }
  void addKeyframe(const Eigen::Isometry3d& pose, WeightedCloud fine) override;
  void redoFirstScan(const PointCloud& points, const Eigen::Isometry3d& pose,
                     WeightedCloud fine) override;

 private:
  struct Keyframe {
    Eigen::Isometry3d pose;  ///< odometry frame
    WeightedCloud cloud;     ///< vehicle frame, keyframe_voxel
  };
  void rebuild();

  size_t keyframes_;
  std::deque<Keyframe> recent_;
};

/// odometry.reference = scan_map: a world-fixed height map of the last
/// odometry.local_map_scans registered scans (dlo::LocalHeightMap), updated with every scan
/// whose pose was measured; the reference is the map's window around the newest scan. What
/// sparse sensors need: one sparse scan sees the ground only along its rings.
class ScanMapReference : public ReferenceModel {
 public:
  explicit ScanMapReference(const SlamParams& params) : ReferenceModel(params) {}
  std::unique_ptr<ReferenceModel> clone() const override {
    return std::make_unique<ScanMapReference>(*this);
  }
  bool deskewsACopy() const override { return true; }
  void afterScan(HeightFrame& current, const PointCloud& points, const Eigen::Isometry3d& pose,
                 bool measured) override;
  void redoFirstScan(const PointCloud& points, const Eigen::Isometry3d& pose,
                     WeightedCloud fine) override;
  void restartAfterRejections() override {
    if (map_) map_->clear();
  }

 private:
  /// The map, made on first use: a dense sensor that never uses it does not pay for its arrays
  /// (7.7 MB for the sparse profile's 400 x 400 grid).
  LocalHeightMap& map();

  std::optional<LocalHeightMap> map_;
  Eigen::Vector2d last_position_ = Eigen::Vector2d::Zero();  ///< of the last scan it took
};

/// A ReferenceModel owned by value: copying it clones the model.
class ReferenceModelPtr {
 public:
  explicit ReferenceModelPtr(std::unique_ptr<ReferenceModel> model) : model_(std::move(model)) {}
  ReferenceModelPtr(const ReferenceModelPtr& other) : model_(other.model_->clone()) {}
  ReferenceModelPtr& operator=(const ReferenceModelPtr& other) {
    if (this != &other) model_ = other.model_->clone();
    return *this;
  }
  ReferenceModelPtr(ReferenceModelPtr&&) noexcept = default;
  ReferenceModelPtr& operator=(ReferenceModelPtr&&) noexcept = default;
  ReferenceModel* operator->() const { return model_.get(); }
  ReferenceModel& operator*() const { return *model_; }

 private:
  std::unique_ptr<ReferenceModel> model_;
};

}  // namespace dlo
