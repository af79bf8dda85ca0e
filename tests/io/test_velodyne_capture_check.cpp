// checkVelodyneCapture: the real VLP-16 capture in the layouts libpcap reads (classic pcap in
// both byte orders, pcapng, cut short), and the captures MRPT's driver cannot read safely.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "dlo/files/error.h"
#include "dlo/mrpt/velodyne_capture_check.h"
#include "dlo/mrpt/velodyne_pcap_reader.h"
#include "io_test_helpers.h"

namespace dlo {
namespace {

using Bytes = std::vector<uint8_t>;

/// One record of a classic pcap file.
struct Record {
  uint32_t seconds, microseconds, original_length;
  Bytes data;
};

Bytes readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void writeFile(const std::string& path, const Bytes& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

uint32_t le32(const uint8_t* p) {
  return p[0] | p[1] << 8 | p[2] << 16 | uint32_t(p[3]) << 24;
}

void put32(Bytes& out, uint32_t v, bool big_endian = false) {
  for (int i = 0; i < 4; ++i) out.push_back(uint8_t(v >> (big_endian ? 24 - 8 * i : 8 * i)));
}
void put16(Bytes& out, uint16_t v, bool big_endian = false) {
  for (int i = 0; i < 2; ++i) out.push_back(uint8_t(v >> (big_endian ? 8 - 8 * i : 8 * i)));
}

/// The records of the real capture (little-endian classic pcap).
std::vector<Record> realRecords() {
  const Bytes file = readBytes(test::sharedData("sample_velodyne_vlp16_gps.pcap"));
  std::vector<Record> records;
  for (size_t at = 24; at + 16 <= file.size();) {
    const uint32_t caplen = le32(&file[at + 8]);
    records.push_back({le32(&file[at]), le32(&file[at + 4]), le32(&file[at + 12]),
                       Bytes(file.begin() + at + 16, file.begin() + at + 16 + caplen)});
    at += 16 + caplen;
  }
  return records;
}

/// A classic pcap file of `records`: version, snap length and link type as given.
Bytes classicPcap(const std::vector<Record>& records, bool big_endian = false,
                  uint16_t minor_version = 4, uint32_t link_type = 1) {
  Bytes out;
  put32(out, 0xa1b2c3d4, big_endian);
  put16(out, 2, big_endian);
  put16(out, minor_version, big_endian);
  put32(out, 0, big_endian);
  put32(out, 0, big_endian);
  put32(out, 65535, big_endian);
  put32(out, link_type, big_endian);
  for (const Record& r : records) {
    put32(out, r.seconds, big_endian);
    put32(out, r.microseconds, big_endian);
    put32(out, static_cast<uint32_t>(r.data.size()), big_endian);
    put32(out, r.original_length, big_endian);
    out.insert(out.end(), r.data.begin(), r.data.end());
  }
  return out;
}

/// The same packets as pcapng: a section header, one Ethernet interface (with a name and a
/// microsecond time stamp resolution, as Wireshark writes them), enhanced packet blocks.
Bytes pcapng(const std::vector<Record>& records) {
  Bytes out;
  put32(out, 0x0A0D0D0A);
  put32(out, 28);
  put32(out, 0x1A2B3C4D);
  put16(out, 1);
  put16(out, 0);
  put32(out, 0xffffffff);  // section length unknown
  put32(out, 0xffffffff);
  put32(out, 28);
  put32(out, 1);  // interface description
  put32(out, 40);
  put16(out, 1);  // Ethernet
  put16(out, 0);
  put32(out, 65535);
  put16(out, 2);  // if_name "eth0"
  put16(out, 4);
  out.insert(out.end(), {'e', 't', 'h', '0'});
  put16(out, 9);  // if_tsresol: 10^-6 s, padded to 4 bytes
  put16(out, 1);
  out.insert(out.end(), {6, 0, 0, 0});
  put32(out, 0);  // end of options
  put32(out, 40);
  for (const Record& r : records) {
    const uint32_t padded = (static_cast<uint32_t>(r.data.size()) + 3) / 4 * 4;
    const uint64_t micros = uint64_t(r.seconds) * 1000000 + r.microseconds;
    put32(out, 6);  // enhanced packet
    put32(out, 32 + padded);
    put32(out, 0);
    put32(out, static_cast<uint32_t>(micros >> 32));
    put32(out, static_cast<uint32_t>(micros));
    put32(out, static_cast<uint32_t>(r.data.size()));
    put32(out, r.original_length);
    out.insert(out.end(), r.data.begin(), r.data.end());
    out.resize(out.size() + padded - r.data.size(), 0);
    put32(out, 32 + padded);
  }
  return out;
}

size_t scansIn(const std::string& path) {
  VelodynePcapScanSource source(path, VelodyneModel::kVLP16);
  TimedScan scan;
  size_t n = 0;
  while (source.next(scan)) ++n;
  return n;
}

std::string errorOf(const std::string& path) {
  try {
    checkVelodyneCapture(path);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError for " << path;
  return {};
}

TEST(VelodyneCaptureCheck, CountsThePacketsOfTheRealCapture) {
  const auto summary = checkVelodyneCapture(test::sharedData("sample_velodyne_vlp16_gps.pcap"));
  EXPECT_EQ(summary.packets, 350u);
  EXPECT_EQ(summary.velodyne_packets, 350u);  // 293 data and 57 position packets
}

TEST(VelodyneCaptureCheck, AcceptsBigEndianPcapAndPcapngThatMrptReadsAlike) {
  test::TempDir dir;
  const auto records = realRecords();
  ASSERT_EQ(records.size(), 350u);
  writeFile(dir.path("big.pcap"), classicPcap(records, true));
  writeFile(dir.path("next.pcapng"), pcapng(records));
  for (const std::string name : {"big.pcap", "next.pcapng"}) {
    SCOPED_TRACE(name);
    const auto summary = checkVelodyneCapture(dir.path(name));
    EXPECT_EQ(summary.packets, 350u);
    EXPECT_EQ(summary.velodyne_packets, 350u);
    EXPECT_EQ(scansIn(dir.path(name)), 4u);
  }
}

TEST(VelodyneCaptureCheck, ACaptureCutInsideItsLastPacketEndsThere) {
  test::TempDir dir;
  Bytes cut = classicPcap(realRecords());
  cut.resize(cut.size() - 700);
  writeFile(dir.path("cut.pcap"), cut);
  EXPECT_EQ(checkVelodyneCapture(dir.path("cut.pcap")).packets, 349u);
  EXPECT_EQ(scansIn(dir.path("cut.pcap")), 4u);
}

TEST(VelodyneCaptureCheck, RejectsWhatMrptsDriverCannotReadSafely) {
  test::TempDir dir;
  auto records = realRecords();
  writeFile(dir.path("old.pcap"), classicPcap(records, false, 2));
  EXPECT_NE(errorOf(dir.path("old.pcap")).find("version is 2.2"), std::string::npos);
  writeFile(dir.path("sll.pcap"), classicPcap(records, false, 4, 113));
  EXPECT_NE(errorOf(dir.path("sll.pcap")).find("link type is 113, not Ethernet"),
            std::string::npos);
  writeFile(dir.path("text.pcap"), Bytes{'h', 'e', 'l', 'l', 'o', '\n'});
  EXPECT_NE(errorOf(dir.path("text.pcap")).find("not a pcap or pcapng capture"), std::string::npos);

  // A position packet (the second record) captured without the end of its payload.
  auto cut = records;
  cut[1].data.resize(300);
  writeFile(dir.path("short.pcap"), classicPcap(cut));
  EXPECT_NE(errorOf(dir.path("short.pcap"))
                .find("packet 1 (byte offset 1304) is a Velodyne position packet captured with "
                      "300 of its 554 bytes"),
            std::string::npos);

  // Only packets the driver filters out (not UDP to port 2368 or 8308).
  auto others = std::vector<Record>(records.begin(), records.begin() + 3);
  for (Record& r : others) r.data[37] ^= 0x01;
  writeFile(dir.path("others.pcap"), classicPcap(others));
  EXPECT_NE(errorOf(dir.path("others.pcap")).find("holds no Velodyne packet"), std::string::npos);
}

}  // namespace
}  // namespace dlo
