#include "dlo/sim/deterministic_random.h"

#include <cmath>
#include <vector>

namespace dlo::sim {

DeterministicRng::DeterministicRng(std::initializer_list<uint32_t> seeds) {
  std::vector<uint32_t> v(seeds);
  std::seed_seq seq(v.begin(), v.end());
  engine_.seed(seq);
}

double DeterministicRng::uniform01() {
  // 27 + 26 bits, the same construction as the reference genrand_res53().
  const uint32_t a = engine_() >> 5;
  const uint32_t b = engine_() >> 6;
  return (a * 67108864.0 + b) * (1.0 / 9007199254740992.0);
}

int DeterministicRng::integer(int lo, int hi) {
  const uint64_t span = static_cast<uint64_t>(static_cast<int64_t>(hi) - lo) + 1;
  const uint64_t limit = (uint64_t{1} << 32) - ((uint64_t{1} << 32) % span);
  uint64_t x;
  do {
    x = engine_();
  } while (x >= limit);
  return static_cast<int>(lo + static_cast<int64_t>(x % span));
}

double DeterministicRng::gaussian(double mean, double sigma) {
  if (has_spare_) {
    has_spare_ = false;
    return mean + sigma * spare_;
  }
  // 1 - u keeps the logarithm finite.
  const double u1 = 1.0 - uniform01();
  const double u2 = uniform01();
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2.0 * M_PI * u2;
  spare_ = radius * std::sin(angle);
  has_spare_ = true;
  return mean + sigma * radius * std::cos(angle);
}

}  // namespace dlo::sim
