#include "dlo/sim/lidar_model.h"

#include <algorithm>
#include <cctype>

namespace dlo::sim {

namespace {

// VLP-16 user manual, laser id order (interleaved): -15..+15 deg every 2 deg.
const std::vector<double> kVlp16Elevation = {-15, 1, -13, 3,  -11, 5,  -9, 7,
                                             -7,  9, -5,  11, -3,  13, -1, 15};

// HDL-32E user manual, laser id order (interleaved): -30.67..+10.67 deg every 4/3 deg.
const std::vector<double> kHdl32Elevation = {
    -30.67, -9.33,  -29.33, -8.00,  -28.00, -6.67,  -26.67, -5.33,  -25.33, -4.00,  -24.00,
    -2.67,  -22.67, -1.33,  -21.33, 0.00,   -20.00, 1.33,   -18.67, 2.67,   -17.33, 4.00,
    -16.00, 5.33,   -14.67, 6.67,   -13.33, 8.00,   -12.00, 9.33,   -10.67, 10.67};

// HDL-64E S2 nominal layout: the upper block (lasers 0-31) spans +2.0..-8.33 deg at 1/3 deg,
// the lower block (32-63) -8.83..-24.9 deg at about 1/2 deg. Individual units differ by a few
// hundredths of a degree (per-unit calibration files); the nominal table is what matters
// for the scan pattern.
std::vector<double> hdl64Elevation() {
  std::vector<double> e(64);
  for (int i = 0; i < 32; ++i) e[i] = 2.0 - i / 3.0;
  for (int i = 0; i < 32; ++i) e[32 + i] = -8.83 - i * (24.9 - 8.83) / 31.0;
  return e;
}

// Ouster OS1 (uniform beam spacing): `beams` beams spread evenly over +22.5..-22.5 deg, beam 0
// the highest, as the sensor numbers them.
std::vector<double> ouster45Elevation(int beams) {
  std::vector<double> e(beams);
  for (int i = 0; i < beams; ++i) e[i] = 22.5 - i * 45.0 / (beams - 1);
  return e;
}

// 1024 columns per revolution at 10 Hz: 97.65625 us per column, rounded to whole nanoseconds so
// that a revolution is exactly 1024 columns (99.999744 ms, 10.0000256 Hz).
constexpr int kOusterColumns = 1024;
constexpr int64_t kOusterColumnNs = 97656;

}  // namespace

LidarModel makeLidarModel(SensorType type) {
  LidarModel m;
  m.type = type;
  switch (type) {
    case SensorType::VLP16:
      // 2 firings per 110.592 us block, 2.304 us between lasers: 0.199 deg at 10 Hz.
      m.name = "VLP16";
      m.elevationDeg = kVlp16Elevation;
      m.firingPeriodNs = 55296;
      m.laserTimeOffsetNs = 2304;
      m.firingsPerPacket = 24;
      m.minRange = 0.9;
      m.maxRange = 100.0;
      break;
    case SensorType::HDL32:
      // One firing per 46.08 us block, 1.152 us between lasers: 0.166 deg at 10 Hz.
      m.name = "HDL32";
      m.elevationDeg = kHdl32Elevation;
      m.firingPeriodNs = 46080;
      m.laserTimeOffsetNs = 1152;
      m.firingsPerPacket = 12;
      m.minRange = 1.0;
      m.maxRange = 70.0;
      break;
    case SensorType::HDL64:
      // Upper and lower blocks fire together every 48 us: 0.173 deg at 10 Hz. MRPT decodes
      // all 64 returns of a firing at the block's azimuth, so lasers have no offset here.
      m.name = "HDL64";
      m.elevationDeg = hdl64Elevation();
      m.firingPeriodNs = 48000;
      m.laserTimeOffsetNs = 0;
      m.firingsPerPacket = 6;
      m.minRange = 0.9;
      m.maxRange = 120.0;
      break;
    case SensorType::OS64:
    case SensorType::OS128:
      // Every beam of a column fires at once (no stagger); 16 columns per lidar packet.
      m.name = type == SensorType::OS64 ? "OS64" : "OS128";
      m.elevationDeg = ouster45Elevation(type == SensorType::OS64 ? 64 : 128);
      m.firingPeriodNs = kOusterColumnNs;
      m.laserTimeOffsetNs = 0;
      m.firingsPerPacket = 16;
      m.rotationHz = 1e9 / static_cast<double>(kOusterColumns * kOusterColumnNs);
      m.minRange = 0.5;
      m.maxRange = 120.0;
      break;
  }
  return m;
}

std::optional<SensorType> parseSensorType(const std::string& text) {
  std::string key;
  for (char c : text) {
    if (c != '-' && c != '_') key += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  if (key == "VLP16") return SensorType::VLP16;
  if (key == "HDL32" || key == "HDL32E") return SensorType::HDL32;
  if (key == "HDL64" || key == "HDL64E") return SensorType::HDL64;
  if (key == "OS64" || key == "OS164") return SensorType::OS64;
  if (key == "OS128" || key == "OS1128") return SensorType::OS128;
  return std::nullopt;
}

}  // namespace dlo::sim
