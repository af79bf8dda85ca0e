// Fuzz target: PLY files (ascii, binary little and big endian) through loadPlyStream, the reader
// behind loadPlyFile and dlo-register's `.ply` inputs: header parsing, elements and list
// properties skipped before the vertices, and the vertex x, y, z. A bad file must throw
// InputError naming it.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

#include "allocation_limit.h"
#include "dlo/files/error.h"
#include "dlo/formats/ply_file.h"
#include "fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dlo::fuzz::withHeapBudget([&] {
    static const std::string kName = "fuzz_input.ply";
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size), std::ios::binary);
    try {
      const dlo::PointCloud points = dlo::loadPlyStream(in, kName);
      for (const auto& p : points) {
        if (!p.allFinite()) __builtin_trap();  // non-finite vertices are documented as dropped
      }
    } catch (const dlo::InputError& e) {
      dlo::fuzz::requireNames(e.what(), kName);
    }
  });
  return 0;
}
