// Random numbers that are identical on every platform and standard library for a given seed.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <random>

namespace dlo::sim {

/**
 * std::mt19937 with hand-written distributions.
 *
 * The engine's output sequence is fixed by the C++ standard, but the distributions
 * (std::uniform_real_distribution, std::normal_distribution, ...) are not, so a simulation
 * built on them could change between libstdc++ versions. Everything here derives from raw
 * 32-bit engine outputs with explicit formulas, which makes the simulator byte-reproducible.
 */
class DeterministicRng {
 public:
  /// Seeds from several integers (e.g. {seed, frame, chunk}) through std::seed_seq, whose
  /// algorithm is specified by the standard.
  explicit DeterministicRng(std::initializer_list<uint32_t> seeds);
  explicit DeterministicRng(uint32_t seed) : DeterministicRng({seed}) {}

  /// Uniform in [0, 1) with 53 random bits.
  double uniform01();
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform01(); }
  /// Uniform integer in [lo, hi] (inclusive), by rejection so that it is unbiased.
  int integer(int lo, int hi);
  /// True with probability p.
  bool bernoulli(double p) { return uniform01() < p; }
  /// Normal(mean, sigma) by Box-Muller; the second value of each pair is cached and returned
  /// by the next call.
  double gaussian(double mean, double sigma);

 private:
  std::mt19937 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace dlo::sim
