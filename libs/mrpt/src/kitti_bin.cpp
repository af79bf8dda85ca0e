#include "dlo/mrpt/kitti_bin.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <cmath>
#include <fstream>

#include "dlo/mrpt/input_error.h"

namespace dlo {

std::vector<float> readKittiBinRecords(const std::string& path) {
  if (!std::ifstream(path, std::ios::binary)) {
    throw InputError("cannot open KITTI file '" + path + "': no such file or not readable.");
  }
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) throw InputError("cannot open KITTI file '" + path + "'.");
  std::vector<char> bytes;
  constexpr size_t kChunk = 1 << 20;
  for (;;) {
    const size_t old = bytes.size();
    bytes.resize(old + kChunk);
    // CFileGZInputStream::Read passes on gzread's -1 for a corrupt gzip stream, as SIZE_MAX.
    const size_t got = in.Read(bytes.data() + old, kChunk);
    if (got > kChunk) {
      throw InputError("KITTI file '" + path +
                       "' is corrupt: its gzip data cannot be decompressed (" +
                       std::to_string(old) + " bytes were read before the error).");
    }
    bytes.resize(old + got);
    if (got == 0) break;
  }
  if (bytes.size() % 16 != 0) {
    throw InputError("KITTI file '" + path + "' holds " + std::to_string(bytes.size()) +
                     " bytes, not a multiple of 16 (float32 x, y, z, reflectance per point).");
  }
  std::vector<float> records(bytes.size() / sizeof(float));
  std::copy(bytes.begin(), bytes.end(), reinterpret_cast<char*>(records.data()));
  return records;
}

size_t loadKittiBinXYZI(const std::string& path, mrpt::maps::CPointsMapXYZI& map) {
  const std::vector<float> r = readKittiBinRecords(path);
  const size_t n = r.size() / 4;
  map.clear();
  map.reserve(n);
  size_t dropped = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* v = &r[4 * i];
    if (!(std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]))) {
      ++dropped;
      continue;
    }
    map.insertPointFast(v[0], v[1], v[2]);
    map.setPointIntensity(map.size() - 1, std::isfinite(v[3]) ? v[3] : 0.0f);
  }
  map.mark_as_modified();
  return dropped;
}

}  // namespace dlo
