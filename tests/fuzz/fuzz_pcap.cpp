// Fuzz target: Velodyne captures (pcap, pcapng) through VelodynePcapScanSource, the reader
// behind dlo-slam and dlo-pcap2rawlog: checkVelodyneCapture, libpcap's file parsing, MRPT's
// CVelodyneScanner packet handling (data and GPS packets, rotation assembly), the re-stamping of
// rotations and the decoding of each into a TimedScan. The sensor model comes from the input's
// length (mutations change it), so all three packet layouts are decoded. A bad capture must throw
// InputError naming the file.
#include <time.h>

#include <cstddef>
#include <cstdint>

#include "allocation_limit.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/velodyne_pcap_reader.h"
#include "fuzz_input_file.h"

// MRPT's CVelodyneScanner sleeps 250 ms when it reaches the end of a capture read once, which
// would cost a quarter of a second per input; nothing else in the reader sleeps. Interposed here
// (the driver calls nanosleep through the PLT), in the fuzz target only.
extern "C" int nanosleep(const struct timespec*, struct timespec*) {
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dlo::fuzz::withHeapBudget([&] {
    static dlo::fuzz::FuzzInputFile file;
    static const dlo::VelodyneModel kModels[] = {
        dlo::VelodyneModel::kVLP16, dlo::VelodyneModel::kHDL32, dlo::VelodyneModel::kHDL64};
    const std::string& path = file.write(data, size);
    try {
      dlo::VelodynePcapScanSource source(path, kModels[size % 3]);
      dlo::TimedScan scan;
      while (source.next(scan)) {
      }
    } catch (const dlo::InputError& e) {
      dlo::fuzz::requireNames(e.what(), path);
    }
  });
  return 0;
}
