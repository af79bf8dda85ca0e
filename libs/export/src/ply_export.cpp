#include "dlo/export/ply_export.h"

#include <cstring>
#include <fstream>

#include "dlo/files/atomic_file.h"

namespace dlo {

namespace {

/// Little-endian bytes of a 4-byte value, whatever the host order.
void appendLittleEndian(std::vector<char>& out, std::uint32_t bits) {
  for (int b = 0; b < 4; ++b) out.push_back(static_cast<char>((bits >> (8 * b)) & 0xFFu));
}

void appendFloat(std::vector<char>& out, float v) {
  std::uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  appendLittleEndian(out, bits);
}

}  // namespace

void exportPly(const WeightedCloud& points, const std::string& path) {
  writeAtomically(path, [&](const std::string& temp) {
    std::ofstream out(temp, std::ios::binary);
    if (!out) throw std::runtime_error("cannot create '" + temp + "'");
    out << "ply\nformat binary_little_endian 1.0\ncomment DLO map, world frame, metres\n"
        << "element vertex " << points.size() << "\n"
        << "property float x\nproperty float y\nproperty float z\nproperty uint count\n"
        << "end_header\n";
    std::vector<char> body;
    body.reserve(points.size() * 16);
    for (const WeightedPoint& wp : points) {
      appendFloat(body, wp.p.x());
      appendFloat(body, wp.p.y());
      appendFloat(body, wp.p.z());
      appendLittleEndian(body, wp.n);
    }
    out.write(body.data(), static_cast<std::streamsize>(body.size()));
    out.close();
    if (!out) throw std::runtime_error("writing '" + temp + "' failed (disk full?)");
  });
}

}  // namespace dlo
