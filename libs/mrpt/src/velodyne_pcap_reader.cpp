#include "dlo/mrpt/velodyne_pcap_reader.h"

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/hwdrivers/CVelodyneScanner.h>
#include <algorithm>
#include <cctype>
#include <fstream>

#include "dlo/files/error.h"
#include "dlo/mrpt/observation_to_scan.h"
#include "dlo/mrpt/velodyne_capture_check.h"

namespace dlo {

namespace {

const char* modelName(VelodyneModel model) {
  switch (model) {
    case VelodyneModel::kHDL32:
      return "HDL32";
    case VelodyneModel::kHDL64:
      return "HDL64";
    default:
      return "VLP16";
  }
}

/// The sentence after "Error opening PCAP file:" in MRPT's multi-line exception text.
std::string pcapReason(const std::string& what) {
  const auto at = what.find("Error opening PCAP file:");
  std::string line = at == std::string::npos ? what : what.substr(at + 24);
  line = line.substr(0, line.find('\n'));
  const auto first = line.find_first_not_of(" '");
  const auto last = line.find_last_not_of(" '");
  return first == std::string::npos ? line : line.substr(first, last - first + 1);
}

}  // namespace

VelodyneModel parseVelodyneModel(const std::string& name) {
  std::string upper = name;
  std::transform(upper.begin(), upper.end(), upper.begin(),
                 [](unsigned char c) { return std::toupper(c); });
  if (upper == "VLP16") return VelodyneModel::kVLP16;
  if (upper == "HDL32") return VelodyneModel::kHDL32;
  if (upper == "HDL64") return VelodyneModel::kHDL64;
  throw InputError("unknown Velodyne model '" + name + "': expected VLP16, HDL32 or HDL64.");
}

VelodynePcapReader::VelodynePcapReader(const std::string& path, VelodyneModel model)
    : scanner_(std::make_unique<mrpt::hwdrivers::CVelodyneScanner>()) {
  if (!std::ifstream(path, std::ios::binary)) {
    throw InputError("cannot open pcap '" + path + "': no such file or not readable.");
  }
  // Before MRPT's driver sees it: it over-reads short packets, crashes on some link types and
  // loops forever on a capture without Velodyne packets.
  checkVelodyneCapture(path);
  // pcap_read_fast has no setter in MRPT 2.5; without it the driver sleeps 100 ms per rotation.
  mrpt::config::CConfigFileMemory cfg;
  cfg.write("velodyne", "model", modelName(model));
  cfg.write("velodyne", "pcap_input", path);
  cfg.write("velodyne", "pcap_read_once", true);
  cfg.write("velodyne", "pcap_read_fast", true);
  try {
    scanner_->loadConfig(cfg, "velodyne");
    scanner_->setPCAPVerbosity(false);
    scanner_->initialize();
  } catch (const std::exception& e) {
    throw InputError("'" + path + "' is not a readable pcap capture (" + pcapReason(e.what()) +
                     ").");
  }
}

VelodynePcapReader::~VelodynePcapReader() = default;

mrpt::obs::CObservationVelodyneScan::Ptr VelodynePcapReader::readRotation() {
  while (!finished_) {
    mrpt::obs::CObservationVelodyneScan::Ptr scan;
    mrpt::obs::CObservationGPS::Ptr gps;
    if (!scanner_->getNextObservation(scan, gps)) {
      finished_ = true;  // end of the capture (or a read error, which the driver reports so)
      break;
    }
    if (gps) ++gps_packets_;
    if (scan && !scan->scan_packets.empty()) return scan;
  }
  return nullptr;
}

void VelodynePcapReader::restamp(mrpt::obs::CObservationVelodyneScan& scan) {
  const double clock = scan.scan_packets.front().gps_timestamp() * 1e-6;  // since top of hour
  if (scan.has_satellite_timestamp) {
    hour_start_ = mrpt::Clock::toDouble(scan.timestamp) - clock;
    fix_clock_ = clock;
    return;
  }
  double t = hour_start_.value_or(0.0) + clock;
  // Rotations read ahead of the first fix may lie in the hour before it.
  if (hour_start_ && clock > fix_clock_ + 1800.0) t -= 3600.0;
  scan.timestamp = mrpt::Clock::fromDouble(t);
}

mrpt::obs::CObservationVelodyneScan::Ptr VelodynePcapReader::next() {
  if (!primed_) {
    primed_ = true;
    while (ahead_.size() < kGpsLookahead) {
      auto scan = readRotation();
      if (!scan) break;
      ahead_.push_back(scan);
      if (scan->has_satellite_timestamp) {
        restamp(*scan);  // sets the hour for the rotations before it
        break;
      }
    }
  }
  mrpt::obs::CObservationVelodyneScan::Ptr scan;
  if (!ahead_.empty()) {
    scan = ahead_.front();
    ahead_.pop_front();
  } else {
    scan = readRotation();
  }
  if (scan) restamp(*scan);
  return scan;
}

VelodynePcapScanSource::VelodynePcapScanSource(const std::string& path, VelodyneModel model,
                                               const ScanSourceOptions& options)
    : reader_(path, model), options_(options) {}

bool VelodynePcapScanSource::next(TimedScan& scan) {
  for (;;) {
    const auto obs = reader_.next();
    if (!obs) return false;
    scan.entry_index = stats_.entries_read++;
    if (admitObservation(*obs, options_, scan, stats_)) {
      scan.observation = obs;
      return true;
    }
  }
}

}  // namespace dlo
