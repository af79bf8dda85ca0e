/// \file velodyne_pcap_reader.h
/// \brief Velodyne `.pcap` captures as CObservationVelodyneScan observations and TimedScans,
/// through mrpt::hwdrivers::CVelodyneScanner. Part of the dlo_mrpt_pcap library, so that only
/// programs that read captures link MRPT's hardware drivers.
#pragma once

#include <mrpt/obs/CObservationVelodyneScan.h>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "dlo/mrpt/scan_source.h"

namespace mrpt::hwdrivers {
class CVelodyneScanner;
}

namespace dlo {

/// The Velodyne models whose packet layout and default calibration MRPT 2.5 knows.
enum class VelodyneModel { kVLP16, kHDL32, kHDL64 };

/// "VLP16", "HDL32" or "HDL64" (case-insensitive). \throws InputError for any other text.
VelodyneModel parseVelodyneModel(const std::string& name);

/// Reads one full rotation at a time from a Velodyne capture. The capture is read once, as fast
/// as possible (MRPT's default replays at sensor speed and loops forever). As with MRPT's
/// driver, the packets after the last 360-degree wrap (a partial rotation) are not returned; the
/// first rotation may be partial when the capture starts mid-turn.
///
/// Timestamps: MRPT stamps a rotation with GPS time once the capture has shown a GPS fix, and
/// before that with the computer's clock AT READING TIME, which for a file is meaningless and
/// makes the stream jump by years. So every rotation is re-stamped from the sensor's own clock
/// (microseconds since the top of the hour, in each data packet) plus the hour taken from the
/// first GPS-stamped rotation (looked for up to kGpsLookahead rotations ahead). Without a GPS fix
/// the timestamps are seconds since the top of the hour: consistent, but not absolute.
class VelodynePcapReader {
 public:
  /// \throws InputError naming the file if it is missing, not a pcap capture, or fails
  ///         checkVelodyneCapture() (velodyne_capture_check.h).
  VelodynePcapReader(const std::string& path, VelodyneModel model);
  ~VelodynePcapReader();

  /// The next rotation (raw packets and default calibration, no point cloud generated yet), or
  /// nullptr at the end of the capture.
  mrpt::obs::CObservationVelodyneScan::Ptr next();

  /// GPS (position) packets seen so far; they are not part of the scans.
  size_t gpsPackets() const { return gps_packets_; }

  /// Rotations read ahead to find the first GPS-stamped one (2 s at 10 Hz).
  static constexpr size_t kGpsLookahead = 20;

 private:
  mrpt::obs::CObservationVelodyneScan::Ptr readRotation();
  void restamp(mrpt::obs::CObservationVelodyneScan& scan);

  std::unique_ptr<mrpt::hwdrivers::CVelodyneScanner> scanner_;
  std::deque<mrpt::obs::CObservationVelodyneScan::Ptr> ahead_;
  bool primed_ = false;
  std::optional<double> hour_start_;  ///< GPS time of the top of the current hour, seconds.
  double fix_clock_ = 0;              ///< Sensor clock of the rotation that set hour_start_.
  size_t gps_packets_ = 0;
  bool finished_ = false;
};

/// TimedScans (with per-point times) from a Velodyne capture; see VelodynePcapReader.
/// TimedScan::entry_index is the rotation number, from 0.
class VelodynePcapScanSource : public ScanSource {
 public:
  /// \throws InputError as VelodynePcapReader.
  VelodynePcapScanSource(const std::string& path, VelodyneModel model,
                         const ScanSourceOptions& options = {});

  bool next(TimedScan& scan) override;
  const ScanSourceStats& stats() const override { return stats_; }

 private:
  VelodynePcapReader reader_;
  ScanSourceOptions options_;
  ScanSourceStats stats_;
};

}  // namespace dlo
