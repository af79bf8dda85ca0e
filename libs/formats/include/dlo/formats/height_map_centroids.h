/// \file height_map_centroids.h
/// \brief Where the points of each cell of dlo-slam's height map lie in it
/// (`heightmap_centroids.bin`, beside `heightmap.bin`).
///
/// MRPT's CHeightGridMap2D serialises each cell's mean height and weight only. A registration
/// that compares a scan's cells with the map's at their centres carries a bias where a cell's
/// points lie to one side of it (a ring crossing a kerb, a wall's face): the mean height belongs
/// to the centroid of its points. This file keeps those centroids, one byte per axis per cell.
///
/// Layout: gzip-compressed; the 8 bytes `DLOHMC01`, then the grid's columns and rows as 32-bit
/// little-endian unsigned integers, then per cell (row-major, row 0 at the grid's lowest y, the
/// cells of heightmap.bin) two bytes: the centroid's place along the cell's columns (x) and
/// rows (y), in 256ths of the cell (byte q stands for (q + 0.5) / 256). Cells with no point hold
/// 128, 128 (the centre).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dlo {

/// The centroids of a height map's cells, quantised as in the file.
struct HeightMapCentroids {
  std::uint32_t cols = 0, rows = 0;
  /// 2 per cell, row-major: along the columns, then along the rows; see the file's layout.
  std::vector<std::uint8_t> places;

  /// A place in [0, 1) of the cell as its byte (clamped).
  static std::uint8_t quantise(double fraction);
  /// The fraction of the cell that a byte stands for.
  static float fraction(std::uint8_t q) { return (static_cast<float>(q) + 0.5f) / 256.0f; }
};

/// Writes `centroids` to `path` atomically. \throws OutputError naming `path`.
void writeHeightMapCentroids(const HeightMapCentroids& centroids, const std::string& path);

/// Reads a file written by writeHeightMapCentroids().
/// \throws InputError naming `path` if it is missing, not such a file, or truncated.
HeightMapCentroids readHeightMapCentroids(const std::string& path);

}  // namespace dlo
