#include "dlo/formats/kitti_bin.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "dlo/files/error.h"
#include "gz_file.h"

namespace dlo {

std::vector<float> readKittiBinRecords(const std::string& path) {
  if (!std::ifstream(path, std::ios::binary)) {
    throw InputError("cannot open KITTI file '" + path + "': no such file or not readable.");
  }
  GzFile in(path);
  if (!in.file) throw InputError("cannot open KITTI file '" + path + "'.");
  std::vector<char> bytes;
  constexpr unsigned kChunk = 1 << 20;
  for (;;) {
    const size_t old = bytes.size();
    bytes.resize(old + kChunk);
    // gzread gives -1 for a corrupt gzip stream.
    const int got = gzread(in.file, bytes.data() + old, kChunk);
    if (got < 0) {
      throw InputError("KITTI file '" + path +
                       "' is corrupt: its gzip data cannot be decompressed (" +
                       std::to_string(old) + " bytes were read before the error).");
    }
    bytes.resize(old + static_cast<size_t>(got));
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

PointCloud loadKittiBin(const std::string& path, size_t* dropped_non_finite) {
  const std::vector<float> records = readKittiBinRecords(path);
  const size_t n = records.size() / 4;
  PointCloud out;
  out.reserve(n);
  size_t dropped = 0;
  for (size_t i = 0; i < n; ++i) {
    const float* v = &records[4 * i];
    if (std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2])) {
      out.emplace_back(v[0], v[1], v[2]);
    } else {
      ++dropped;
    }
  }
  if (dropped_non_finite) *dropped_non_finite = dropped;
  return out;
}

}  // namespace dlo
