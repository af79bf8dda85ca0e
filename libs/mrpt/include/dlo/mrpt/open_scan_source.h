/// \file open_scan_source.h
/// \brief The scan source for a path the programs take as input: a rawlog, a Velodyne capture
/// or a KITTI folder.
#pragma once

#include <memory>
#include <string>

#include "dlo/mrpt/scan_source.h"

namespace dlo {

/// Opens `input`: a `.pcap` (a Velodyne capture; needs `model`, VLP16, HDL32 or HDL64), a
/// folder (a KITTI sequence) or anything else as an MRPT rawlog (plain or gzip).
/// \throws UsageError if a .pcap comes without a model; InputError naming the file if it cannot
///         be read.
std::unique_ptr<ScanSource> openScanSource(const std::string& input, const std::string& model,
                                           const ScanSourceOptions& options);

}  // namespace dlo
