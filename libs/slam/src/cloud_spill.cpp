#include "dlo/slam/cloud_spill.h"

#include <stdexcept>
#include <string>
#include <type_traits>

namespace dlo {

// Clouds are written and read back as raw bytes within one process: WeightedPoint is three
// floats (Eigen's fixed-size storage is a plain array) and a count, without padding.
static_assert(std::is_standard_layout_v<WeightedPoint> &&
                  sizeof(WeightedPoint) == 3 * sizeof(float) + sizeof(std::uint32_t),
              "spilled clouds are written as raw bytes");

CloudSpill::CloudSpill() : file_(std::tmpfile()) {
  if (!file_) {
    throw std::runtime_error(
        "cannot create a temporary file for keyframe clouds (check TMPDIR and free space).");
  }
}

CloudSpill::~CloudSpill() {
  if (file_) std::fclose(file_);
}

CloudSlot CloudSpill::write(const WeightedCloud& cloud) {
  std::lock_guard<std::mutex> lock(mutex_);
  const CloudSlot slot{end_, cloud.size()};
  const size_t bytes = cloud.size() * sizeof(WeightedPoint);
  if (std::fseek(file_, static_cast<long>(end_), SEEK_SET) != 0 ||
      (bytes > 0 && std::fwrite(cloud.data(), 1, bytes, file_) != bytes) ||
      std::fflush(file_) != 0) {
    throw std::runtime_error("cannot write " + std::to_string(bytes) +
                             " bytes of keyframe cloud to the temporary file (disk full?).");
  }
  end_ += bytes;
  return slot;
}

WeightedCloud CloudSpill::read(const CloudSlot& slot) const {
  std::lock_guard<std::mutex> lock(mutex_);
  WeightedCloud cloud(slot.count);
  const size_t bytes = cloud.size() * sizeof(WeightedPoint);
  if (slot.offset + bytes > end_ ||
      std::fseek(file_, static_cast<long>(slot.offset), SEEK_SET) != 0 ||
      (bytes > 0 && std::fread(cloud.data(), 1, bytes, file_) != bytes)) {
    throw std::runtime_error("cannot read a keyframe cloud back from the temporary file.");
  }
  return cloud;
}

std::uint64_t CloudSpill::bytes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return end_;
}

}  // namespace dlo
