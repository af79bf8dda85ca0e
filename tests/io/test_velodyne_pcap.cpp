// VelodynePcapReader / VelodynePcapScanSource on the real VLP-16 capture, and bad captures.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "dlo/files/error.h"
#include "dlo/mrpt/velodyne_pcap_reader.h"
#include "io_test_helpers.h"

namespace dlo {
namespace {

TEST(VelodynePcapScanSource, ReadsFourRotationsWithPointTimesFromTheRealCapture) {
  VelodynePcapScanSource source(test::sharedData("sample_velodyne_vlp16_gps.pcap"),
                                VelodyneModel::kVLP16);
  std::vector<TimedScan> scans;
  TimedScan scan;
  while (source.next(scan)) scans.push_back(scan);
  ASSERT_EQ(scans.size(), 4u);
  for (size_t i = 0; i < scans.size(); ++i) {
    SCOPED_TRACE(i);
    const TimedScan& s = scans[i];
    EXPECT_EQ(s.entry_index, i);
    EXPECT_GT(s.points.size(), 3000u);
    EXPECT_EQ(s.beams, 16);
    ASSERT_EQ(s.point_times.size(), s.points.size());
    const auto [tmin, tmax] = std::minmax_element(s.point_times.begin(), s.point_times.end());
    EXPECT_GE(*tmin, -0.001f);
    EXPECT_LE(*tmax - *tmin, 0.11f);  // one rotation at 10 Hz
    EXPECT_GT(*tmax - *tmin, 0.03f);
    for (const auto& p : s.points) ASSERT_LT(p.norm(), 130.0f);
    if (i > 0) {
      const double dt = s.timestampSeconds() - scans[i - 1].timestampSeconds();
      EXPECT_GT(dt, 0.0);
      EXPECT_LT(dt, 0.2);
    }
  }
  EXPECT_TRUE(source.stats().error.empty());
}

TEST(VelodynePcapReader, RejectsMissingFilesAndNonCaptures) {
  test::TempDir dir;
  std::ofstream(dir.path("text.pcap")) << "not a capture\n";
  for (const std::string name : {"missing.pcap", "text.pcap"}) {
    try {
      VelodynePcapReader reader(dir.path(name), VelodyneModel::kVLP16);
      FAIL() << "expected an InputError for " << name;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
}

TEST(VelodyneModel, ParsesKnownModelsOnly) {
  EXPECT_EQ(parseVelodyneModel("vlp16"), VelodyneModel::kVLP16);
  EXPECT_EQ(parseVelodyneModel("HDL32"), VelodyneModel::kHDL32);
  EXPECT_EQ(parseVelodyneModel("HDL64"), VelodyneModel::kHDL64);
  EXPECT_THROW(parseVelodyneModel("VLP32"), InputError);
}

}  // namespace
}  // namespace dlo
