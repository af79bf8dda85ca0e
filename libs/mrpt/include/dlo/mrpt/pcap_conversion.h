/// \file pcap_conversion.h
/// \brief A Velodyne `.pcap` capture to an MRPT rawlog of CObservationVelodyneScan.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "dlo/mrpt/velodyne_pcap_reader.h"

namespace dlo {

/// What convertVelodynePcap() did.
struct PcapConversionResult {
  size_t scans = 0;        ///< Observations (rotations) written.
  size_t packets = 0;      ///< Velodyne data packets in them.
  size_t gps_packets = 0;  ///< GPS packets seen (used by the driver for timestamps, not written).
};

/// Writes every rotation of the capture `pcap` as a CObservationVelodyneScan (raw packets and
/// calibration, as MRPT's own grabbers store them) to `out_rawlog`, observation-only layout,
/// through a temporary file renamed at the end. `progress(done, 0)` is called after each scan
/// (the number of rotations is not known in advance).
/// \throws InputError naming the file if the capture is missing, not a pcap, or holds no
///         Velodyne data for `model`; an existing `out_rawlog` is then left untouched.
PcapConversionResult convertVelodynePcap(
    const std::string& pcap, VelodyneModel model, const std::string& out_rawlog,
    const std::function<void(size_t, size_t)>& progress = nullptr);

}  // namespace dlo
