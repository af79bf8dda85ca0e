// Fuzz target: KITTI Velodyne `.bin` files, plain or gzip (MRPT's gzip stream), through both
// readers: loadKittiBinXYZI (points with reflectance, as dlo-kitti2rawlog reads them) and
// loadKittiBin (points only, as dlo-register reads them). A bad file must throw InputError naming
// it.
#include <mrpt/maps/CPointsMapXYZI.h>
#include <cstddef>
#include <cstdint>

#include "allocation_limit.h"
#include "dlo/files/error.h"
#include "dlo/formats/kitti_bin.h"
#include "dlo/mrpt/kitti_conversion.h"
#include "fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dlo::fuzz::withHeapBudget([&] {
    static dlo::fuzz::FuzzInputFile file;
    const std::string& path = file.write(data, size);
    try {
      mrpt::maps::CPointsMapXYZI map;
      const size_t dropped = dlo::loadKittiBinXYZI(path, map);
      size_t dropped_again = 0;
      const dlo::PointCloud points = dlo::loadKittiBin(path, &dropped_again);
      // Both readers see the same records: they must agree on what they keep.
      if (points.size() != map.size() || dropped != dropped_again) __builtin_trap();
    } catch (const dlo::InputError& e) {
      dlo::fuzz::requireNames(e.what(), path);
    }
  });
  return 0;
}
