/// \file velodyne_pcap_reader.h
/// \brief Velodyne `.pcap` captures as CObservationVelodyneScan observations and TimedScans,
/// through mrpt::hwdrivers::CVelodyneScanner. Part of the dlo_mrpt_pcap library, so that only
/// programs that read captures link MRPT's hardware drivers.
#pragma once

#include <mrpt/obs/CObservationVelodyneScan.h>
#include <memory>
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
class VelodynePcapReader {
 public:
  /// \throws InputError naming the file if it is missing or not a pcap capture.
  VelodynePcapReader(const std::string& path, VelodyneModel model);
  ~VelodynePcapReader();

  /// The next rotation (raw packets and default calibration, no point cloud generated yet), or
  /// nullptr at the end of the capture.
  mrpt::obs::CObservationVelodyneScan::Ptr next();

  /// GPS (position) packets seen so far; they are not part of the scans.
  size_t gpsPackets() const { return gps_packets_; }

 private:
  std::unique_ptr<mrpt::hwdrivers::CVelodyneScanner> scanner_;
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
