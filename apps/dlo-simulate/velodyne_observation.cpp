#include "velodyne_observation.h"

#include <mrpt/math/CMatrixFixed.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace dlo {

namespace {

using Velo = mrpt::obs::CObservationVelodyneScan;
static_assert(sizeof(Velo::TVelodyneRawPacket) == 1206, "Velodyne packet layout changed");

constexpr int kBlockBytes = 100;  // header (2) + rotation (2) + 32 returns x 3 bytes.

/// Little-endian packet bytes: the wire format, which MRPT reads through toNativeEndianness.
class PacketBytes {
 public:
  PacketBytes() { bytes_.fill(0); }
  void u16(size_t at, uint16_t v) {
    bytes_[at] = static_cast<uint8_t>(v & 0xff);
    bytes_[at + 1] = static_cast<uint8_t>(v >> 8);
  }
  void u32(size_t at, uint32_t v) {
    for (int k = 0; k < 4; ++k) bytes_[at + k] = static_cast<uint8_t>((v >> (8 * k)) & 0xff);
  }
  void u8(size_t at, uint8_t v) { bytes_[at] = v; }
  void copyTo(Velo::TVelodyneRawPacket& packet) const {
    std::memcpy(&packet, bytes_.data(), bytes_.size());
  }

 private:
  std::array<uint8_t, 1206> bytes_;
};

uint16_t rotationUnits(double azimuthDeg) {
  return static_cast<uint16_t>(std::lround(azimuthDeg * 100.0) % 36000);
}

uint16_t rangeUnits(float r) {
  if (r <= 0.0f) return 0;
  return static_cast<uint16_t>(std::min<long>(std::lround(r / kRangeUnit), 65535));
}

}  // namespace

mrpt::Clock::time_point addNanoseconds(mrpt::Clock::time_point epoch, int64_t ns) {
  // Rounded to the nearest 100 ns tick, exactly (no double on the way).
  return epoch + mrpt::Clock::duration((ns + 50) / 100);
}

mrpt::poses::CPose3D mountPose(const Eigen::Isometry3d& sensorMount) {
  mrpt::math::CMatrixDouble44 h;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) h(r, c) = sensorMount.matrix()(r, c);
  return mrpt::poses::CPose3D(h);
}

mrpt::obs::CObservationVelodyneScan::Ptr toVelodyneScan(const sim::Sweep& sweep,
                                                        const sim::SweepSimulator& simulator,
                                                        const Eigen::Isometry3d& sensorMount,
                                                        mrpt::Clock::time_point epoch,
                                                        const std::string& sensorLabel) {
  const sim::LidarModel& m = simulator.model();
  auto obs = Velo::Create();
  obs->sensorLabel = sensorLabel;
  obs->timestamp = addNanoseconds(epoch, sweep.referenceTimeNs);
  obs->originalReceivedTimestamp = obs->timestamp;
  obs->has_satellite_timestamp = true;
  obs->minRange = m.minRange;
  obs->maxRange = m.maxRange;
  obs->sensorPose = mountPose(sensorMount);

  obs->calibration.laser_corrections.resize(m.laserCount());
  for (int l = 0; l < m.laserCount(); ++l) {
    auto& c = obs->calibration.laser_corrections[l];
    c.verticalCorrection = m.elevationDeg[l];
    c.sinVertCorrection = std::sin(m.elevationDeg[l] * M_PI / 180.0);
    c.cosVertCorrection = std::cos(m.elevationDeg[l] * M_PI / 180.0);
  }

  // The decoded form, with exact per-point times.
  auto& pc = obs->point_cloud;
  pc.reserve(static_cast<size_t>(
      std::count_if(sweep.range.begin(), sweep.range.end(), [](float r) { return r > 0.0f; })));
  for (int f = 0; f < sweep.firings; ++f) {
    for (int l = 0; l < sweep.lasers; ++l) {
      const size_t idx = sweep.index(f, l);
      if (sweep.range[idx] <= 0.0f) continue;
      const Eigen::Vector3d p = simulator.sensorPoint(sweep, f, l);
      pc.x.push_back(static_cast<float>(p.x()));
      pc.y.push_back(static_cast<float>(p.y()));
      pc.z.push_back(static_cast<float>(p.z()));
      pc.intensity.push_back(sweep.intensity[idx]);
      pc.laser_id.push_back(static_cast<int16_t>(l));
      pc.timestamp.push_back(addNanoseconds(epoch, simulator.pointTimeNs(sweep, f, l)));
    }
  }

  // How firings map onto the 12 blocks of a packet, 32 returns per block.
  const int firingsPerBlock = m.type == sim::SensorType::VLP16 ? 2 : 1;
  const int blocksPerFiring = m.type == sim::SensorType::HDL64 ? 2 : 1;
  const uint8_t modelId = m.type == sim::SensorType::VLP16   ? 0x22
                          : m.type == sim::SensorType::HDL32 ? 0x21
                                                             : 0x00;
  const int packets = sweep.firings / m.firingsPerPacket;
  obs->scan_packets.resize(packets);
  for (int p = 0; p < packets; ++p) {
    PacketBytes bytes;
    const int f0 = p * m.firingsPerPacket;
    for (int b = 0; b < 12; ++b) {
      const int firing = f0 + (b / blocksPerFiring) * firingsPerBlock;
      const bool lower = blocksPerFiring == 2 && (b % 2) == 1;
      const size_t at = static_cast<size_t>(b) * kBlockBytes;
      bytes.u16(at, lower ? Velo::LOWER_BANK : Velo::UPPER_BANK);
      bytes.u16(at + 2,
                rotationUnits(simulator.azimuthDeg(simulator.pointTimeNs(sweep, firing, 0))));
      for (int k = 0; k < 32; ++k) {
        int f = firing, laser = k;
        if (firingsPerBlock == 2) {  // VLP-16: returns 16..31 are the block's second firing.
          f = firing + k / 16;
          laser = k % 16;
        } else if (lower) {
          laser = 32 + k;
        }
        const size_t idx = sweep.index(f, laser);
        bytes.u16(at + 4 + 3 * k, rangeUnits(sweep.range[idx]));
        bytes.u8(at + 6 + 3 * k, sweep.intensity[idx]);
      }
    }
    const int64_t us = (simulator.pointTimeNs(sweep, f0, 0) + 500) / 1000;
    bytes.u32(1200, static_cast<uint32_t>(us % 3600000000LL));
    bytes.u8(1204, Velo::RETMODE_STRONGEST);
    bytes.u8(1205, modelId);
    bytes.copyTo(obs->scan_packets[p]);
  }
  return obs;
}

}  // namespace dlo
