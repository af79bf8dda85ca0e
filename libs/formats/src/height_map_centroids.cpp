#include "dlo/formats/height_map_centroids.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "dlo/files/atomic_file.h"
#include "dlo/files/error.h"
#include "gz_file.h"

namespace dlo {

namespace {

constexpr std::array<char, 8> kMagic = {'D', 'L', 'O', 'H', 'M', 'C', '0', '1'};
constexpr size_t kHeaderBytes = kMagic.size() + 8;
/// More cells than any map (a 20 km square at 0.2 m): a header beyond it is not this format.
constexpr std::uint64_t kMaxCells = 1ull << 34;

void putU32(std::uint32_t v, unsigned char* out) {
  for (int i = 0; i < 4; ++i) out[i] = static_cast<unsigned char>(v >> (8 * i));
}

std::uint32_t getU32(const unsigned char* in) {
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(in[i]) << (8 * i);
  return v;
}

/// Reads exactly `n` bytes; false at the end of the data or on corrupt data.
bool readAll(gzFile file, unsigned char* out, std::uint64_t n) {
  while (n > 0) {
    const unsigned chunk = static_cast<unsigned>(std::min<std::uint64_t>(n, 1u << 24));
    const int got = gzread(file, out, chunk);
    if (got <= 0) return false;
    out += got;
    n -= static_cast<std::uint64_t>(got);
  }
  return true;
}

}  // namespace

std::uint8_t HeightMapCentroids::quantise(double fraction) {
  if (!(fraction > 0.0)) return 0;
  return static_cast<std::uint8_t>(std::min(255.0, std::floor(fraction * 256.0)));
}

void writeHeightMapCentroids(const HeightMapCentroids& centroids, const std::string& path) {
  const std::uint64_t cells = static_cast<std::uint64_t>(centroids.cols) * centroids.rows;
  if (centroids.places.size() != 2 * cells) {
    throw OutputError("cannot write '" + path + "' (its places do not match its " +
                      std::to_string(centroids.cols) + " x " + std::to_string(centroids.rows) +
                      " cells).");
  }
  writeAtomically(path, [&](const std::string& temp) {
    GzFile out(temp, "wb1");
    if (!out.file) throw std::runtime_error("cannot create '" + temp + "'");
    std::array<unsigned char, kHeaderBytes> header{};
    std::memcpy(header.data(), kMagic.data(), kMagic.size());
    putU32(centroids.cols, header.data() + kMagic.size());
    putU32(centroids.rows, header.data() + kMagic.size() + 4);
    bool ok = gzwrite(out.file, header.data(), header.size()) == static_cast<int>(header.size());
    for (size_t done = 0; ok && done < centroids.places.size();) {
      const unsigned chunk =
          static_cast<unsigned>(std::min<size_t>(centroids.places.size() - done, 1u << 24));
      ok = gzwrite(out.file, centroids.places.data() + done, chunk) == static_cast<int>(chunk);
      done += chunk;
    }
    const int closed = gzclose(out.file);
    out.file = nullptr;
    if (!ok || closed != Z_OK) throw std::runtime_error("write failed");
  });
}

HeightMapCentroids readHeightMapCentroids(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError("'" + path + "' does not exist.");
  GzFile in(path);
  if (!in.file) throw InputError("cannot open '" + path + "'.");
  std::array<unsigned char, kHeaderBytes> header{};
  if (!readAll(in.file, header.data(), header.size()) ||
      std::memcmp(header.data(), kMagic.data(), kMagic.size()) != 0) {
    throw InputError("'" + path + "' is not a height map centroid file (no DLOHMC01 header).");
  }
  HeightMapCentroids c;
  c.cols = getU32(header.data() + kMagic.size());
  c.rows = getU32(header.data() + kMagic.size() + 4);
  const std::uint64_t cells = static_cast<std::uint64_t>(c.cols) * c.rows;
  if (cells == 0 || cells > kMaxCells) {
    throw InputError("'" + path + "' declares " + std::to_string(c.cols) + " x " +
                     std::to_string(c.rows) + " cells, which is no height map.");
  }
  c.places.resize(2 * cells);
  unsigned char extra = 0;
  if (!readAll(in.file, c.places.data(), c.places.size())) {
    throw InputError("'" + path + "' is truncated or corrupt: it holds fewer than its " +
                     std::to_string(c.cols) + " x " + std::to_string(c.rows) + " cells.");
  }
  if (gzread(in.file, &extra, 1) != 0) {
    throw InputError("'" + path + "' holds more than its " + std::to_string(c.cols) + " x " +
                     std::to_string(c.rows) + " cells.");
  }
  return c;
}

}  // namespace dlo
