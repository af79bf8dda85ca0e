// Fuzz target: MRPT rawlogs (plain or gzip) through RawlogScanSource, the reader behind dlo-slam,
// dlo-register and the converters. Exercises MRPT's deserialization of any registered class in
// both layouts, and the conversion of every observation into a TimedScan (Velodyne packets
// decoded, point clouds and 3D range scans filtered and moved to the vehicle frame). A broken
// rawlog must end the stream with stats().error, or throw InputError, naming the file.
#include <cstddef>
#include <cstdint>

#include "allocation_limit.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dlo::fuzz::withHeapBudget([&] {
    static dlo::fuzz::FuzzInputFile file;
    const std::string& path = file.write(data, size);
    try {
      dlo::ScanSourceOptions options;
      options.max_range = 200.0;
      dlo::RawlogScanSource source(path, options);
      dlo::TimedScan scan;
      while (source.next(scan)) {
      }
      if (!source.stats().error.empty()) dlo::fuzz::requireNames(source.stats().error, path);
      dlo::describeScanSourceStats(source.stats());
    } catch (const dlo::InputError& e) {
      dlo::fuzz::requireNames(e.what(), path);
    }
  });
  return 0;
}
