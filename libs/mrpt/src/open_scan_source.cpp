#include "dlo/mrpt/open_scan_source.h"

#include <filesystem>

#include "dlo/files/error.h"
#include "dlo/mrpt/kitti_scan_source.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "dlo/mrpt/velodyne_pcap_reader.h"

namespace dlo {

std::unique_ptr<ScanSource> openScanSource(const std::string& input, const std::string& model,
                                           const ScanSourceOptions& options) {
  if (std::filesystem::path(input).extension() == ".pcap") {
    if (model.empty()) throw UsageError{"reading a .pcap needs --model VLP16|HDL32|HDL64."};
    return std::make_unique<VelodynePcapScanSource>(input, parseVelodyneModel(model), options);
  }
  if (std::filesystem::is_directory(input))
    return std::make_unique<KittiScanSource>(input, options);
  return std::make_unique<RawlogScanSource>(input, options);
}

}  // namespace dlo
