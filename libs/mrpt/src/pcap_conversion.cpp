#include "dlo/mrpt/pcap_conversion.h"

#include "dlo/files/error.h"
#include "dlo/mrpt/rawlog_writer.h"

namespace dlo {

PcapConversionResult convertVelodynePcap(const std::string& pcap, VelodyneModel model,
                                         const std::string& out_rawlog,
                                         const std::function<void(size_t, size_t)>& progress) {
  VelodynePcapReader reader(pcap, model);
  PcapConversionResult result;
  // Opened only once the capture is known to be readable, so a bad input leaves no file behind.
  std::unique_ptr<RawlogWriter> writer;
  while (const auto scan = reader.next()) {
    if (!writer) writer = std::make_unique<RawlogWriter>(out_rawlog);
    writer->write(*scan);
    ++result.scans;
    result.packets += scan->scan_packets.size();
    if (progress) progress(result.scans, 0);
  }
  result.gps_packets = reader.gpsPackets();
  if (!writer) {
    throw InputError("pcap '" + pcap +
                     "' holds no Velodyne scan (no data packets on UDP port 2368, or another "
                     "model than the one given).");
  }
  writer->commit();
  return result;
}

}  // namespace dlo
