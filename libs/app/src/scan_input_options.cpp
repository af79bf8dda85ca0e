#include "dlo/app/scan_input_options.h"

#include "dlo/files/error.h"

namespace dlo {

void declareScanInputOptions(ProgramOptions& cl, ScanInputOptions& options, unsigned which) {
  if (which & kScanModel) {
    cl.text("--model", options.model, "the Velodyne model of a .pcap input")
        .valueName("VLP16|HDL32|HDL64");
  }
  if (which & kScanSensorLabel) {
    cl.text("--sensor-label", options.sensor_label, "only observations with this sensor label")
        .valueName("L");
  }
  if (which & kScanRange) {
    cl.number("--min-range", options.min_range,
              "drop points closer than M metres to the sensor (the vehicle)")
        .valueName("M");
    cl.number("--max-range", options.max_range, "drop points farther than M metres").valueName("M");
  }
  if (which & kScanMaxFrames) {
    cl.wholeNumber("--max-frames", options.max_frames, "stop after N scans (-1: all)")
        .valueName("N");
  }
}

void checkScanInputOptions(const ScanInputOptions& options) {
  if (!(options.min_range >= 0.0 && options.max_range > options.min_range)) {
    throw UsageError{"--min-range and --max-range must satisfy 0 <= min < max."};
  }
  if (!(options.max_frames == -1 || options.max_frames >= 1)) {
    throw UsageError{"--max-frames expects a whole number of scans >= 1, or -1 for all."};
  }
}

}  // namespace dlo
