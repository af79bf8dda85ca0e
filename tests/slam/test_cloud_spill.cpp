// CloudSpill and SlamMap's spilled keyframe clouds: what goes out comes back, copies share it.
#include <gtest/gtest.h>

#include "dlo/slam/cloud_spill.h"
#include "dlo/slam/slam_map.h"

namespace dlo {
namespace {

WeightedCloud makeCloud(size_t n, float seed) {
  WeightedCloud c(n);
  for (size_t i = 0; i < n; ++i) {
    c[i] =
        WeightedPoint{Eigen::Vector3f(seed + i, -seed * i, 0.5f * i), static_cast<uint32_t>(i + 1)};
  }
  return c;
}

void expectSame(const WeightedCloud& a, const WeightedCloud& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].p, b[i].p) << i;
    EXPECT_EQ(a[i].n, b[i].n) << i;
  }
}

TEST(CloudSpill, ReadsBackEveryCloudWrittenInAnyOrder) {
  CloudSpill spill;
  const WeightedCloud a = makeCloud(1000, 1.0f), b = makeCloud(0, 2.0f), c = makeCloud(7, 3.0f);
  const CloudSlot sa = spill.write(a), sb = spill.write(b), sc = spill.write(c);
  EXPECT_EQ(sa.offset, 0u);
  EXPECT_EQ(sb.offset, 1000 * sizeof(WeightedPoint));
  EXPECT_EQ(spill.bytes(), 1007 * sizeof(WeightedPoint));
  expectSame(spill.read(sc), c);
  expectSame(spill.read(sa), a);
  expectSame(spill.read(sb), b);
}

TEST(CloudSpill, RefusesASlotBeyondWhatWasWritten) {
  CloudSpill spill;
  spill.write(makeCloud(10, 1.0f));
  EXPECT_THROW(spill.read(CloudSlot{0, 11}), std::runtime_error);
  EXPECT_THROW(spill.read(CloudSlot{16, 10}), std::runtime_error);
}

TEST(SlamMap, SpilledKeyframeCloudsLeaveMemoryAndComeBackThroughTheMapAndItsCopies) {
  SlamMap map;
  for (int i = 0; i < 3; ++i) {
    Keyframe k;
    k.id = i;
    k.cloud = makeCloud(100 + i, static_cast<float>(i));
    map.keyframes.push_back(k);
  }
  const size_t before = map.residentCloudBytes();
  map.spillKeyframeCloud(1);
  map.spillKeyframeCloud(1);  // a second time does nothing
  EXPECT_TRUE(map.keyframes[1].spilled);
  EXPECT_TRUE(map.keyframes[1].cloud.empty());
  EXPECT_EQ(map.residentCloudBytes(), before - 101 * sizeof(WeightedPoint));
  EXPECT_EQ(map.spill->bytes(), 101 * sizeof(WeightedPoint));

  WeightedCloud buffer;
  expectSame(map.keyframeCloud(1, buffer), makeCloud(101, 1.0f));
  // A resident cloud is handed out directly, not copied into the buffer.
  EXPECT_EQ(&map.keyframeCloud(2, buffer), &map.keyframes[2].cloud);

  const SlamMap copy = map;
  map.spillKeyframeCloud(0);  // the copy still reads its own keyframe 0 from memory
  expectSame(copy.keyframeCloud(1, buffer), makeCloud(101, 1.0f));
  expectSame(copy.keyframeCloud(0, buffer), makeCloud(100, 0.0f));
  expectSame(map.keyframeCloud(0, buffer), makeCloud(100, 0.0f));
}

}  // namespace
}  // namespace dlo
