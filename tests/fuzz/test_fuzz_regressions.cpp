// Inputs the fuzz targets (tests/fuzz) found to crash, hang or break the error contract, fed
// through the same readers: each must now end with an InputError of one line naming the file, or
// be read. The files are in tests/fuzz/regressions/<target>/ (see the README there);
// scripts/run_fuzz.sh also starts each fuzz target from them.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <sstream>
#include <string>

#include "dlo/files/error.h"
#include "dlo/formats/kitti_bin.h"
#include "dlo/formats/ply_file.h"
#include "dlo/mrpt/dlo_config.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "dlo/mrpt/scan_file.h"
#include "dlo/mrpt/velodyne_pcap_reader.h"
#include "dlo/slam/slam_config.h"

namespace dlo {
namespace {

std::string regression(const std::string& name) {
  return std::string(DLO_SOURCE_DIR) + "/tests/fuzz/regressions/" + name;
}

/// The message of the InputError `read` throws; fails the test if it throws nothing or anything
/// else, or if the message is not one line naming `path`.
std::string inputError(const std::function<void()>& read, const std::string& path) {
  try {
    read();
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << "expected an InputError for " << path;
  return {};
}

/// The error of a rawlog whose first entry cannot be read: the reader gives no scan and reports
/// entry 0 corrupt in one message naming `path`.
std::string firstEntryCorrupt(const std::string& path) {
  RawlogScanSource source(path);
  TimedScan scan;
  EXPECT_FALSE(source.next(scan));
  const std::string& error = source.stats().error;
  EXPECT_NE(error.find("corrupt at entry 0"), std::string::npos) << error;
  EXPECT_NE(error.find(path), std::string::npos) << error;
  return error;
}

TEST(FuzzRegression, PlyDoubleCoordinatesBeyondFloatRangeAreDroppedNotMadeInfinite) {
  // A big-endian file whose double z is 1e300 in one vertex: as a float it was infinite.
  const PointCloud points = loadPlyFile(regression("ply/double-beyond-float-range.ply"));
  EXPECT_LT(points.size(), 8u);
  for (const auto& p : points) EXPECT_TRUE(p.allFinite()) << p.transpose();
}

TEST(FuzzRegression, PlyHugeVertexCountIsATruncationNotAnAllocationOfTheCount) {
  // 4e9 vertices declared, one present: reserving the count asked for 48 GB (std::bad_alloc).
  const std::string path = regression("ply/huge-vertex-count.ply");
  const std::string message = inputError([&] { loadPlyFile(path); }, path);
  EXPECT_NE(message.find("after 1 of its 4000000000 vertex items"), std::string::npos) << message;
}

TEST(FuzzRegression, PlyElementsWithoutPropertiesAreSkippedNotLoopedOver) {
  // 4e12 "face" items of no bytes each before the vertices: the reader looped over all of them.
  const PointCloud points = loadPlyFile(regression("ply/element-without-properties.ply"));
  ASSERT_EQ(points.size(), 1u);
  EXPECT_EQ(points[0], Eigen::Vector3f(1, 2, 3));
  // The fuzzer's own input (900 million items of an element without properties) ends quickly.
  const std::string fuzzed = regression("ply/element-without-properties-fuzzed.ply");
  inputError([&] { loadPlyFile(fuzzed); }, fuzzed);
}

TEST(FuzzRegression, KittiCorruptGzipIsAnInputErrorNotALengthError) {
  // gzread's -1 came back from MRPT as SIZE_MAX bytes read: std::length_error.
  const std::string path = regression("kitti_bin/corrupt-gzip.bin.gz");
  const std::string message = inputError([&] { readKittiBinRecords(path); }, path);
  EXPECT_NE(message.find("gzip"), std::string::npos) << message;
  inputError([&] { loadScanFile(path); }, path);
}

TEST(FuzzRegression, ConfigMacroMrptCannotParseIsAnInputErrorNamingTheFile) {
  // An unclosed `$env{`: MRPT's parser threw its own multi-line exception from the constructor
  // of CConfigFile, outside the handler that names the file.
  const std::string path = regression("config/unclosed-env-macro.ini");
  const std::string message = inputError([&] { loadDloParamsFile(path); }, path);
  EXPECT_NE(message.find("Expected closing"), std::string::npos) << message;
  inputError([&] { loadSlamParamsFile(path); }, path);
}

TEST(FuzzRegression, RawlogRangeScanMrptCannotUnprojectIsSkippedWithTheReason) {
  // A 3D range scan whose camera model MRPT does not know: unprojectInto() threw out of next().
  RawlogScanSource source(regression("rawlog/range-image-mrpt-cannot-unproject.rawlog"));
  TimedScan scan;
  while (source.next(scan)) {
  }
  const ScanSourceStats& stats = source.stats();
  ASSERT_EQ(stats.skip_reasons.count("CObservation3DRangeScan"), 1u)
      << describeScanSourceStats(stats);
  EXPECT_NE(stats.skip_reasons.at("CObservation3DRangeScan").find("MRPT could not decode it"),
            std::string::npos);
}

TEST(FuzzRegression, RawlogBoolFieldHoldingAnyByteIsReadWithoutUndefinedBehaviour) {
  // A 3D range scan whose hasPoints3D holds the byte 197 (MRPT deserializes a bool as the raw
  // byte; reading it as a bool is undefined behaviour, which the UndefinedBehaviorSanitizer pass
  // of the suite stops at), then a corrupt entry. Any nonzero byte means true: its points are
  // read.
  RawlogScanSource source(regression("rawlog/bool-field-byte-197.rawlog"));
  TimedScan scan;
  ASSERT_TRUE(source.next(scan)) << describeScanSourceStats(source.stats());
  EXPECT_EQ(scan.source_class, "CObservation3DRangeScan");
  EXPECT_FALSE(source.next(scan));
  EXPECT_NE(source.stats().error.find("corrupt at entry 1"), std::string::npos)
      << source.stats().error;
}

TEST(FuzzRegression, RawlogActionCollectionHoldingANonActionIsCorruptNotANullDereference) {
  // An action collection whose first element is an mrpt::img::TCamera: MRPT's
  // CActionCollection::serializeFrom clones the element as an action, a null pointer (SEGV).
  const std::string error =
      firstEntryCorrupt(regression("rawlog/action-collection-holding-a-camera.rawlog"));
  EXPECT_NE(error.find("action collection holds TCamera where action 0 belongs"), std::string::npos)
      << error;
}

TEST(FuzzRegression, RawlogImageOfBillionsOfPixelsIsCorruptNotAnAbort) {
  // A 3D range scan whose intensity image declares 2e9 x 2.1e9 RGB pixels: MRPT has OpenCV
  // allocate the pixels before reading them (cv::fastMalloc asked malloc for 1.26e19 bytes,
  // which ASan refused by ending the fuzzer). The failed allocation is a corrupt entry.
  const std::string error = firstEntryCorrupt(regression("rawlog/image-of-4e18-pixels.rawlog"));
  EXPECT_NE(error.find("mrpt::img::CImage"), std::string::npos) << error;
}

TEST(FuzzRegression, PcapWithANonEthernetLinkTypeIsRejectedBeforeMrptFiltersIt) {
  // Link type 65535: MRPT's filter did not compile and it filtered with an uninitialised
  // program (SEGV in libpcap).
  const std::string path = regression("pcap/link-type-65535.pcap");
  const std::string message =
      inputError([&] { VelodynePcapReader(path, VelodyneModel::kVLP16); }, path);
  EXPECT_NE(message.find("link type is 65535"), std::string::npos) << message;
}

TEST(FuzzRegression, PcapWithoutVelodynePacketsIsAnInputErrorNotAnEndlessLoop) {
  // MRPT's driver returned "no scan yet" forever, printing "Maybe the PCAP file is empty?".
  const std::string path = regression("pcap/no-velodyne-packets.pcap");
  const std::string message =
      inputError([&] { VelodynePcapScanSource(path, VelodyneModel::kVLP16); }, path);
  EXPECT_NE(message.find("holds no Velodyne packet"), std::string::npos) << message;
}

TEST(FuzzRegression, PcapWithVelodynePacketsCutByTheSnapLengthIsRejected) {
  // Captured with a 100-byte snap length: MRPT copies 1206 bytes from byte 42 of each data
  // packet, past the end of libpcap's buffer.
  const std::string path = regression("pcap/snap-length-100.pcap");
  const std::string message =
      inputError([&] { VelodynePcapReader(path, VelodyneModel::kVLP16); }, path);
  EXPECT_NE(message.find("packet 0 (byte offset 40) is a Velodyne data packet captured with 100 "
                         "of its 1248 bytes"),
            std::string::npos)
      << message;
}

TEST(FuzzRegression, PcapngBlockLibpcapRejectsIsRejectedBeforeMrptLoopsOnIt) {
  // One good packet block, then one whose trailing length differs from its leading one: libpcap
  // fails on it before returning the packet, and MRPT's driver, having seen no packet, looped
  // forever on "Maybe the PCAP file is empty?".
  const std::string path = regression("pcap/pcapng-trailer-mismatch.pcapng");
  const std::string message =
      inputError([&] { VelodynePcapScanSource(path, VelodyneModel::kVLP16); }, path);
  EXPECT_NE(message.find("trailing length differs"), std::string::npos) << message;
}

}  // namespace
}  // namespace dlo
