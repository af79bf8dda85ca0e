// dlo_fuzz_seeds SHARED_DATA_DIR OUT_DIR: writes the seed corpora of the fuzz targets into
// OUT_DIR/<target>/, small valid inputs cut from the real samples of ../shared/data, so that
// mutations start from real structure and every branch of each reader is reachable:
//   rawlog/    the VLP-16 rawlog decompressed and cut to a few packets (with and without its
//              point cloud, plain and gzip), point clouds in both layouts (observation-only and
//              action / sensory-frame pairs), 3D range scans (points and range image), a
//              rotating scan, and a rawlog cut inside an entry;
//   kitti_bin/ the first 64 points of the real HDL-64 scan, plain and gzip;
//   ply/       those points as ascii, binary little-endian and binary big-endian PLY, with other
//              elements, list properties and double coordinates;
//   pcap/      the VLP-16 capture cut at packet boundaries, before and after its first complete
//              rotation (dlo_fuzz_pcap picks the sensor model from the length, so each cut is
//              written at the three lengths mod 3), and the same cuts as pcapng.
// Config seeds are the project's config/*.ini, copied by scripts/run_fuzz.sh.
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/maps/CPointsMapXYZI.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "../kitti_scan_points.h"
#include "dlo/mrpt/rawlog_scan_source.h"

namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<char>;

/// The whole file, decompressed if it is gzip.
Bytes readAll(const std::string& path) {
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) throw std::runtime_error("cannot open " + path);
  Bytes bytes;
  char chunk[65536];
  for (size_t got; (got = in.Read(chunk, sizeof(chunk))) > 0;) {
    if (got > sizeof(chunk)) throw std::runtime_error("corrupt gzip data in " + path);
    bytes.insert(bytes.end(), chunk, chunk + got);
  }
  return bytes;
}

void writeFile(const fs::path& path, const Bytes& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

void writeFile(const fs::path& path, const std::string& text) {
  writeFile(path, Bytes(text.begin(), text.end()));
}

void writeGzip(const fs::path& path, const Bytes& bytes) {
  mrpt::io::CFileGZOutputStream out(path.string());
  out.Write(bytes.data(), bytes.size());
}

/// Serialized MRPT objects one after the other, as a rawlog holds them (plain).
template <typename... Objects>
void writeObjects(const fs::path& path, const Objects&... objects) {
  mrpt::io::CFileOutputStream out(path.string());
  auto archive = mrpt::serialization::archiveFrom(out);
  (archive.WriteObject(&objects), ...);
}

/// The first `n` points of the real HDL-64 scan with reflectance.
mrpt::maps::CPointsMapXYZI::Ptr kittiPoints(const std::string& shared, size_t n) {
  return dlo::test::kittiScanPoints(shared + "/kitti_00_000000.bin.gz", 1, n);
}

void rawlogSeeds(const std::string& shared, const fs::path& dir) {
  // The real VLP-16 scan, cut to its first packets; once as stored (with its decoded cloud, no
  // per-point times) and once with packets only, which the reader decodes itself.
  dlo::RawlogScanSource source(shared + "/test_velodyne_VLP16.rawlog");
  auto velo =
      std::dynamic_pointer_cast<mrpt::obs::CObservationVelodyneScan>(source.nextObservation());
  if (!velo) throw std::runtime_error("test_velodyne_VLP16.rawlog holds no Velodyne scan");
  velo->scan_packets.resize(std::min<size_t>(velo->scan_packets.size(), 6));
  velo->generatePointCloud();
  writeObjects(dir / "velodyne_cloud.rawlog", *velo);
  velo->point_cloud.clear_deep();
  writeObjects(dir / "velodyne_packets.rawlog", *velo);
  const Bytes packets = readAll((dir / "velodyne_packets.rawlog").string());
  writeGzip(dir / "velodyne_packets.rawlog.gz", packets);
  writeFile(dir / "velodyne_cut.rawlog", Bytes(packets.begin(), packets.begin() + 2000));

  const auto points = kittiPoints(shared, 24);
  auto cloud = mrpt::obs::CObservationPointCloud::Create();
  cloud->pointcloud = points;
  cloud->sensorLabel = "LIDAR";
  cloud->timestamp = mrpt::Clock::fromDouble(1.0e9);
  cloud->sensorPose = mrpt::poses::CPose3D(1.0, 0.0, 1.7, 0.1, 0.0, 0.0);
  writeObjects(dir / "pointcloud_observations.rawlog", *cloud, *cloud);

  mrpt::obs::CObservation3DRangeScan r3d;
  r3d.resizePoints3DVectors(4);
  r3d.hasPoints3D = true;
  r3d.points3D_x = {1, 2, 3, 4};
  r3d.points3D_y = {0, 1, 0, 1};
  r3d.points3D_z = {0, 1, 2, 3};
  r3d.sensorLabel = "CAM";

  mrpt::obs::CObservation3DRangeScan image;
  image.hasRangeImage = true;
  image.rangeImage_setSize(4, 6);
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 6; ++c) image.rangeImage(r, c) = static_cast<uint16_t>(1000 + 10 * r + c);
  }
  image.rangeUnits = 0.001f;
  image.cameraParams.ncols = 6;
  image.cameraParams.nrows = 4;
  image.cameraParams.setIntrinsicParamsFromValues(5.0, 5.0, 3.0, 2.0);
  image.sensorLabel = "CAM";
  writeObjects(dir / "range_scans.rawlog", r3d, image);

  mrpt::obs::CObservationOdometry odometry;
  mrpt::obs::CActionCollection actions;
  mrpt::obs::CSensoryFrame frame;
  auto simple = mrpt::maps::CSimplePointsMap::Create();
  simple->insertPoint(1, 2, 3);
  simple->insertPoint(4, 5, 6);
  auto small_cloud = mrpt::obs::CObservationPointCloud::Create();
  small_cloud->pointcloud = simple;
  frame.insert(small_cloud);
  frame.insert(mrpt::obs::CObservation3DRangeScan::Create(r3d));
  frame.insert(mrpt::obs::CObservationOdometry::Create(odometry));
  writeObjects(dir / "pairs.rawlog", actions, frame, actions, frame);

  mrpt::obs::CObservationRotatingScan rotating;
  rotating.rowCount = 2;
  rotating.columnCount = 3;
  rotating.rangeImage.setZero(2, 3);
  rotating.intensityImage.setZero(2, 3);
  rotating.rangeResolution = 0.01;
  writeObjects(dir / "rotating.rawlog", rotating, *cloud);
}

void kittiSeeds(const std::string& shared, const fs::path& dir) {
  const Bytes all = readAll(shared + "/kitti_00_000000.bin.gz");
  const Bytes first(all.begin(), all.begin() + 64 * 16);
  writeFile(dir / "points64.bin", first);
  writeGzip(dir / "points64.bin.gz", first);
}

/// Appends `v` to `out` in the byte order `big_endian` asks for.
template <typename T>
void put(std::string& out, T v, bool big_endian) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &v, sizeof(T));
  if (big_endian) std::reverse(bytes, bytes + sizeof(T));
  out.append(bytes, sizeof(T));
}

void plySeeds(const std::string& shared, const fs::path& dir) {
  const auto points = kittiPoints(shared, 8);
  const size_t n = points->size();
  auto xyz = [&](size_t i) {
    float x, y, z;
    points->getPointFast(i, x, y, z);
    return std::vector<float>{x, y, z};
  };

  std::ostringstream ascii;
  ascii << "ply\nformat ascii 1.0\ncomment seed from kitti_00_000000\nelement vertex " << n
        << "\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\n"
        << "element face 2\nproperty list uchar int vertex_indices\nend_header\n";
  for (size_t i = 0; i < n; ++i) {
    const auto p = xyz(i);
    ascii << p[0] << " " << p[1] << " " << p[2] << " " << points->getPointIntensity(i) << "\n";
  }
  ascii << "3 0 1 2\n3 2 3 nan\n";
  writeFile(dir / "ascii.ply", ascii.str());

  std::string le =
      "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
      "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar intensity\n"
      "end_header\n";
  for (size_t i = 0; i < n; ++i) {
    for (float v : xyz(i)) put(le, v, false);
    put(le, static_cast<uint8_t>(i), false);
  }
  writeFile(dir / "binary_little_endian.ply", le);

  // Another element before the vertices, double coordinates and a list per vertex.
  std::string be =
      "ply\nformat binary_big_endian 1.0\nelement camera 1\nproperty short view\n"
      "property list ushort uint junk\nproperty list uint8 int16 ids\nelement vertex " +
      std::to_string(n) +
      "\nproperty double z\nproperty list char uint neighbours\nproperty double y\n"
      "property double x\nend_header\n";
  put(be, static_cast<int16_t>(-3), true);
  put(be, static_cast<uint16_t>(0), true);  // an empty list
  put(be, static_cast<uint8_t>(2), true);
  put(be, static_cast<int16_t>(7), true);
  put(be, static_cast<int16_t>(-7), true);
  for (size_t i = 0; i < n; ++i) {
    const auto p = xyz(i);
    put(be, static_cast<double>(p[2]), true);
    put(be, static_cast<int8_t>(1), true);
    put(be, static_cast<uint32_t>(i), true);
    put(be, static_cast<double>(p[1]), true);
    put(be, static_cast<double>(p[0]), true);
  }
  writeFile(dir / "binary_big_endian.ply", be);
}

/// The pcap global header and the first `packets` records of `capture`.
Bytes pcapPrefix(const Bytes& capture, size_t packets) {
  size_t at = 24;
  for (size_t i = 0; i < packets && at + 16 <= capture.size(); ++i) {
    uint32_t caplen;
    std::memcpy(&caplen, &capture[at + 8], 4);  // the sample is little-endian (magic d4c3b2a1)
    if (at + 16 + caplen > capture.size()) break;
    at += 16 + caplen;
  }
  return Bytes(capture.begin(), capture.begin() + static_cast<std::ptrdiff_t>(at));
}

void put32(Bytes& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>(v >> (8 * i)));
}

/// The little-endian classic pcap `capture` as pcapng: a section header, one Ethernet interface
/// and an enhanced packet block per packet.
Bytes toPcapng(const Bytes& capture) {
  Bytes out;
  for (uint32_t v : {0x0A0D0D0Au, 28u, 0x1A2B3C4Du, 1u, 0xffffffffu, 0xffffffffu, 28u}) {
    put32(out, v);  // section header (version 1.0, length unknown)
  }
  for (uint32_t v : {1u, 20u, 1u, 65535u, 20u}) put32(out, v);  // interface: Ethernet
  for (size_t at = 24; at + 16 <= capture.size();) {
    uint32_t field[4];
    std::memcpy(field, &capture[at], 16);  // seconds, microseconds, captured, original length
    const uint32_t padded = (field[2] + 3) / 4 * 4;
    const uint64_t micros = uint64_t(field[0]) * 1000000 + field[1];
    for (uint32_t v :
         {6u, 32 + padded, 0u, uint32_t(micros >> 32), uint32_t(micros), field[2], field[3]}) {
      put32(out, v);
    }
    out.insert(out.end(), capture.begin() + at + 16, capture.begin() + at + 16 + field[2]);
    out.resize(out.size() + padded - field[2], 0);
    put32(out, 32 + padded);
    at += 16 + field[2];
  }
  return out;
}

void pcapSeeds(const std::string& shared, const fs::path& dir) {
  const Bytes capture = readAll(shared + "/sample_velodyne_vlp16_gps.pcap");
  // 64 packets hold the first 360-degree wrap (packet 62), so one rotation comes out.
  for (size_t packets : {4, 64}) {
    const std::string name = "packets" + std::to_string(packets);
    Bytes cut = pcapPrefix(capture, packets);
    writeFile(dir / (name + ".pcapng"), toPcapng(cut));
    // Trailing bytes too short for a record header read as the end of the capture.
    for (int model = 0; model < 3; ++model) {
      while (cut.size() % 3 != static_cast<size_t>(model)) cut.push_back(0);
      writeFile(dir / (name + "_model" + std::to_string(model) + ".pcap"), cut);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: dlo_fuzz_seeds SHARED_DATA_DIR OUT_DIR\n";
    return 2;
  }
  const std::string shared = argv[1];
  const fs::path out = argv[2];
  try {
    for (const char* target : {"rawlog", "kitti_bin", "ply", "pcap"}) {
      fs::create_directories(out / target);
    }
    rawlogSeeds(shared, out / "rawlog");
    kittiSeeds(shared, out / "kitti_bin");
    plySeeds(shared, out / "ply");
    pcapSeeds(shared, out / "pcap");
  } catch (const std::exception& e) {
    std::cerr << "dlo_fuzz_seeds: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
