/// \file velodyne_capture_check.h
/// \brief Checks a Velodyne capture (pcap or pcapng) before MRPT's driver reads it: the checks
/// MRPT 2.5's CVelodyneScanner lacks.
#pragma once

#include <cstddef>
#include <string>

namespace dlo {

/// What checkVelodyneCapture() found.
struct VelodyneCaptureSummary {
  /// Packets in the capture (as libpcap returns them).
  size_t packets = 0;
  /// Packets that pass the driver's filter: UDP to port 2368 (data) or 8308 (position).
  size_t velodyne_packets = 0;
};

/// Reads the packet headers of the capture `path` (classic pcap, either byte order, micro- or
/// nanosecond timestamps; or pcapng) the way libpcap returns them to
/// mrpt::hwdrivers::CVelodyneScanner, and rejects what that driver (MRPT 2.5) cannot read safely:
/// - a link type other than Ethernet: the driver reads fixed Ethernet + IPv4 offsets, and for some
///   link types its packet filter does not compile, after which it filters with an
///   uninitialised program (a crash);
/// - a packet that passes the driver's filter (UDP to port 2368 or 8308) but was captured shorter
///   than the 1248 or 554 bytes the driver copies out of it: it would read past its end;
/// - a capture with no such packet: the driver then loops forever on "Maybe the PCAP file is
///   empty?".
/// A last record cut short by the end of the file ends the capture, as it does for libpcap (an
/// interrupted capture); anything else malformed is an error.
/// \throws InputError naming the file (and the packet's index and byte offset, where one is
///         at fault).
VelodyneCaptureSummary checkVelodyneCapture(const std::string& path);

}  // namespace dlo
