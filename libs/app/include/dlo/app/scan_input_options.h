/// \file scan_input_options.h
/// \brief The options of the programs that read a drive (dlo-slam, dlo-localize, dlo-bench,
/// dlo-rawlog2kitti): which sensor, which points of each scan count and how many scans, declared
/// and checked once for all of them.
#pragma once

#include <string>

#include "dlo/app/program_options.h"

namespace dlo {

/// What a program reads of a drive. The initial values are the defaults --help shows; a program
/// may change them before declaring the options.
struct ScanInputOptions {
  std::string model;         ///< --model: the Velodyne model of a .pcap input
  std::string sensor_label;  ///< --sensor-label: only observations with this label
  double min_range = 2.0;    ///< --min-range: points closer to the sensor are dropped, metres
  double max_range = 120.0;  ///< --max-range: points farther are dropped, metres
  long max_frames = -1;      ///< --max-frames: stop after this many scans; -1: all
};

/// Which of the options a program takes (bits, combined with |).
enum ScanInputOption : unsigned {
  kScanModel = 1u,        ///< --model
  kScanSensorLabel = 2u,  ///< --sensor-label
  kScanRange = 4u,        ///< --min-range and --max-range
  kScanMaxFrames = 8u,    ///< --max-frames
  kScanAll = 15u,
};

/// Declares the options in `which` on `cl`, bound to `options`.
void declareScanInputOptions(ProgramOptions& cl, ScanInputOptions& options, unsigned which);

/// \throw UsageError "--min-range and --max-range must satisfy 0 <= min < max." or "--max-frames
/// expects a whole number of scans >= 1, or -1 for all."
void checkScanInputOptions(const ScanInputOptions& options);

}  // namespace dlo
