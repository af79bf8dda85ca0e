#include "dlo/mrpt/observation_to_scan.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/system/datetime.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "dlo/files/error.h"

namespace dlo {

namespace {

/// Filters sensor-frame points and moves the kept ones into the vehicle frame. `times` may be
/// null (no per-point times) or hold one time per point.
void appendFiltered(const mrpt::poses::CPose3D& sensor_pose, const float* xs, const float* ys,
                    const float* zs, const float* times, size_t n, const ScanSourceOptions& options,
                    TimedScan& scan) {
  scan.sensor_pose.linear() = sensor_pose.getRotationMatrix().asEigen();
  scan.sensor_pose.translation() =
      Eigen::Vector3d(sensor_pose.x(), sensor_pose.y(), sensor_pose.z());
  const Eigen::Matrix3f R = sensor_pose.getRotationMatrix().asEigen().cast<float>();
  const Eigen::Vector3f t(static_cast<float>(sensor_pose.x()), static_cast<float>(sensor_pose.y()),
                          static_cast<float>(sensor_pose.z()));
  // Squared limits avoid a square root per point.
  const double min2 = options.min_range * options.min_range;
  const double max2 = std::isfinite(options.max_range) ? options.max_range * options.max_range
                                                       : std::numeric_limits<double>::infinity();
  // Written in place and cut to size after: push_back's checks per point cost as much as the
  // filter.
  const size_t base = scan.points.size();
  scan.points.resize(base + n);
  if (times) scan.point_times.resize(base + n);
  Eigen::Vector3f* out = scan.points.data() + base;
  float* out_times = times ? scan.point_times.data() + base : nullptr;
  size_t kept = 0;
  for (size_t i = 0; i < n; ++i) {
    if (!(std::isfinite(xs[i]) && std::isfinite(ys[i]) && std::isfinite(zs[i]))) {
      ++scan.dropped_non_finite;
      continue;
    }
    const Eigen::Vector3f p(xs[i], ys[i], zs[i]);
    const double r2 = p.squaredNorm();
    if (r2 < min2 || r2 > max2) {
      ++scan.dropped_by_range;
      continue;
    }
    out[kept] = R * p + t;
    if (out_times) out_times[kept] = times[i];
    ++kept;
  }
  scan.points.resize(base + kept);
  if (times) scan.point_times.resize(base + kept);
}

void convertVelodyne(mrpt::obs::CObservationVelodyneScan& velo, const ScanSourceOptions& options,
                     TimedScan& scan) {
  auto& pc = velo.point_cloud;
  // Regenerate when the stored cloud lacks times: per-point times are what deskewing needs.
  if (!velo.scan_packets.empty() && (pc.size() == 0 || pc.timestamp.size() != pc.size())) {
    mrpt::obs::CObservationVelodyneScan::TGeneratePointCloudParameters params;
    params.generatePerPointTimestamp = true;
    params.minDistance = 0.0f;  // ScanSourceOptions::min_range decides, counted.
    velo.generatePointCloud(params);
  }
  std::vector<float> times;
  if (pc.timestamp.size() == pc.size() && pc.size() > 0) {
    // mrpt::system::timeDifference()'s arithmetic and checks, with MRPT's thread-local invalid
    // timestamp looked up once per sweep instead of twice per point (docs/benchmarks.md).
    const mrpt::Clock::time_point invalid = INVALID_TIMESTAMP;
    if (velo.timestamp == invalid)
      throw std::runtime_error("a Velodyne sweep has an invalid timestamp");
    times.resize(pc.size());
    for (size_t i = 0; i < pc.size(); ++i) {
      if (pc.timestamp[i] == invalid)
        throw std::runtime_error("a Velodyne sweep has an invalid timestamp");
      const auto us =
          std::chrono::duration_cast<std::chrono::microseconds>(pc.timestamp[i] - velo.timestamp);
      times[i] = static_cast<float>(1e-6 * static_cast<double>(us.count()));
    }
  }
  appendFiltered(velo.sensorPose, pc.x.data(), pc.y.data(), pc.z.data(),
                 times.empty() ? nullptr : times.data(), pc.size(), options, scan);
  scan.beams = static_cast<int>(velo.calibration.laser_corrections.size());
  if (scan.beams == 0 && pc.laser_id.size() == pc.size() && pc.size() > 0)
    scan.beams = std::max(0, 1 + *std::max_element(pc.laser_id.begin(), pc.laser_id.end()));
}

/// Elevation of each row of a rotating scan whose lidarModel names a known layout, in degrees;
/// empty for any other. MRPT 2.5 stores no elevation table in CObservationRotatingScan, so the
/// layout must come from the model: "OS1-<rows>", Ouster OS1 with uniform beam spacing, rows
/// spread evenly over +22.5..-22.5 deg, row 0 the highest.
std::vector<double> rotatingScanElevationsDeg(const std::string& model, int rows) {
  if (rows < 2 || model != "OS1-" + std::to_string(rows)) return {};
  std::vector<double> e(rows);
  for (int r = 0; r < rows; ++r) e[r] = 22.5 - r * 45.0 / (rows - 1);
  return e;
}

/// Points of a rotating scan column by column (the firing order), each column at its azimuth
/// and time interpolated between the first and last (MRPT's definition of startAzimuth,
/// azimuthSpan and sweepDuration).
bool convertRotatingScan(const mrpt::obs::CObservationRotatingScan& rot,
                         const ScanSourceOptions& options, TimedScan& scan, std::string& reason) {
  const int rows = rot.rowCount, cols = rot.columnCount;
  const std::vector<double> elevation = rotatingScanElevationsDeg(rot.lidarModel, rows);
  if (elevation.empty()) {
    reason =
        "MRPT 2.5 stores no per-ring elevation angles in CObservationRotatingScan, and its "
        "lidarModel is not a layout DLO knows (OS1-<rows>), so its points cannot be recovered; "
        "convert the source to CObservationVelodyneScan or CObservationPointCloud.";
    return false;
  }
  if (rot.rangeImage.rows() != rows || rot.rangeImage.cols() != cols) {
    reason = "its range image is not rowCount x columnCount.";
    return false;
  }
  const size_t n = static_cast<size_t>(rows) * cols;
  std::vector<float> xs, ys, zs, times;
  xs.reserve(n);
  ys.reserve(n);
  zs.reserve(n);
  const bool timed = rot.sweepDuration > 0.0 && std::isfinite(rot.sweepDuration);
  if (timed) times.reserve(n);
  std::vector<double> sinE(rows), cosE(rows);
  for (int r = 0; r < rows; ++r) {
    sinE[r] = std::sin(elevation[r] * M_PI / 180.0);
    cosE[r] = std::cos(elevation[r] * M_PI / 180.0);
  }
  const double step = cols > 1 ? 1.0 / (cols - 1) : 0.0;
  for (int c = 0; c < cols; ++c) {
    const double azimuth = rot.startAzimuth + rot.azimuthSpan * c * step;
    const double ca = std::cos(azimuth), sa = std::sin(azimuth);
    const float t = static_cast<float>(rot.sweepDuration * c * step);
    for (int r = 0; r < rows; ++r) {
      const uint16_t units = rot.rangeImage(r, c);
      if (units == 0) continue;
      const double range = units * rot.rangeResolution;
      xs.push_back(static_cast<float>(range * cosE[r] * ca));
      ys.push_back(static_cast<float>(range * cosE[r] * sa));
      zs.push_back(static_cast<float>(range * sinE[r]));
      if (timed) times.push_back(t);
    }
  }
  appendFiltered(rot.sensorPose, xs.data(), ys.data(), zs.data(), timed ? times.data() : nullptr,
                 xs.size(), options, scan);
  scan.beams = rows;
  return true;
}

/// Makes `flag` a valid bool. MRPT 2.5 deserializes a bool as the raw byte in the file, so a
/// corrupt rawlog can leave any byte value there, and reading one other than 0 or 1 as a bool is
/// undefined behaviour (here and in MRPT's inline unprojection code). Any nonzero byte is true.
void normaliseFlag(bool& flag) {
  unsigned char byte;
  std::memcpy(&byte, &flag, 1);
  flag = byte != 0;
}

bool convert3DRangeScan(mrpt::obs::CObservation3DRangeScan& r3d, const ScanSourceOptions& options,
                        TimedScan& scan, std::string& reason) {
  for (bool* flag : {&r3d.hasPoints3D, &r3d.hasRangeImage, &r3d.range_is_depth,
                     &r3d.hasIntensityImage, &r3d.hasConfidenceImage}) {
    normaliseFlag(*flag);
  }
  if (r3d.hasPoints3D && !r3d.points3D_x.empty()) {
    appendFiltered(r3d.sensorPose, r3d.points3D_x.data(), r3d.points3D_y.data(),
                   r3d.points3D_z.data(), nullptr, r3d.points3D_x.size(), options, scan);
    return true;
  }
  if (r3d.hasRangeImage && r3d.rangeImage.rows() > 0 && r3d.cameraParams.fx() > 0 &&
      r3d.cameraParams.fy() > 0) {
    mrpt::maps::CSimplePointsMap local;  // sensor frame: range limits apply before sensorPose
    r3d.unprojectInto(local);
    appendFiltered(r3d.sensorPose, local.getPointsBufferRef_x().data(),
                   local.getPointsBufferRef_y().data(), local.getPointsBufferRef_z().data(),
                   nullptr, local.size(), options, scan);
    return true;
  }
  reason =
      "it has neither 3D points nor a range image with camera intrinsics to unproject (fx, fy "
      "> 0).";
  return false;
}

/// The points of `obs` into `scan` (its other fields already set), by class.
ObservationConversion convertPoints(mrpt::obs::CObservation& obs, const ScanSourceOptions& options,
                                    TimedScan& scan, std::string& reason) {
  if (auto* velo = dynamic_cast<mrpt::obs::CObservationVelodyneScan*>(&obs)) {
    convertVelodyne(*velo, options, scan);
    return ObservationConversion::kConverted;
  }
  if (auto* pco = dynamic_cast<mrpt::obs::CObservationPointCloud*>(&obs)) {
    pco->load();  // externally stored clouds
    if (!pco->pointcloud) return ObservationConversion::kConverted;
    const auto& m = *pco->pointcloud;
    std::vector<float> times = pointCloudObservationTimes(*pco);
    if (times.size() != m.size()) times.clear();
    appendFiltered(pco->sensorPose, m.getPointsBufferRef_x().data(),
                   m.getPointsBufferRef_y().data(), m.getPointsBufferRef_z().data(),
                   times.empty() ? nullptr : times.data(), m.size(), options, scan);
    return ObservationConversion::kConverted;
  }
  if (auto* r3d = dynamic_cast<mrpt::obs::CObservation3DRangeScan*>(&obs)) {
    r3d->load();
    return convert3DRangeScan(*r3d, options, scan, reason) ? ObservationConversion::kConverted
                                                           : ObservationConversion::kUnrecoverable;
  }
  if (auto* rot = dynamic_cast<mrpt::obs::CObservationRotatingScan*>(&obs)) {
    return convertRotatingScan(*rot, options, scan, reason) ? ObservationConversion::kConverted
                                                            : ObservationConversion::kUnrecoverable;
  }
  return ObservationConversion::kUnsupported;
}

}  // namespace

std::vector<float> pointCloudObservationTimes(const mrpt::obs::CObservationPointCloud&) {
  return {};
}

ObservationConversion observationToTimedScan(mrpt::obs::CObservation& obs,
                                             const ScanSourceOptions& options, TimedScan& scan,
                                             std::string& reason) {
  const size_t entry = scan.entry_index;
  scan = TimedScan();
  scan.entry_index = entry;
  scan.timestamp = obs.timestamp;
  scan.sensor_label = obs.sensorLabel;
  scan.source_class = obs.GetRuntimeClass()->className;
  // Class names come with their namespace ("mrpt::obs::..."); the short name reads better.
  const auto colon = scan.source_class.rfind(':');
  if (colon != std::string::npos) scan.source_class = scan.source_class.substr(colon + 1);
  try {
    return convertPoints(obs, options, scan, reason);
  } catch (const std::exception& e) {
    // MRPT checks some fields only while decoding (camera model and lookup-table sizes of a
    // range image, calibration, an externally stored file): a corrupt observation is skipped
    // with the reason, not a failure of the whole input.
    scan.points.clear();
    scan.point_times.clear();
    reason = "MRPT could not decode it (" + oneLineMessage(e) + ").";
    return ObservationConversion::kUnrecoverable;
  }
}

std::string shortClassName(const mrpt::serialization::CSerializable& object) {
  std::string name = object.GetRuntimeClass()->className;
  const auto colon = name.rfind(':');
  return colon == std::string::npos ? name : name.substr(colon + 1);
}

bool admitObservation(mrpt::obs::CObservation& obs, const ScanSourceOptions& options,
                      TimedScan& scan, ScanSourceStats& stats) {
  if (!options.sensor_label.empty() && obs.sensorLabel != options.sensor_label) {
    ++stats.skipped_by_label;
    return false;
  }
  std::string reason;
  const ObservationConversion result = observationToTimedScan(obs, options, scan, reason);
  if (result != ObservationConversion::kConverted) {
    const std::string cls = shortClassName(obs);
    ++stats.skipped_by_class[cls];
    if (result == ObservationConversion::kUnrecoverable) stats.skip_reasons[cls] = reason;
    return false;
  }
  stats.dropped_non_finite += scan.dropped_non_finite;
  stats.dropped_by_range += scan.dropped_by_range;
  if (scan.points.empty()) {
    ++stats.empty_scans;
    return false;
  }
  ++stats.scans;
  return true;
}

}  // namespace dlo
