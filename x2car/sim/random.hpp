// Seeded random draws that are byte-identical on every platform. std::*_distribution differ
// between standard libraries, so uniform and normal variates are built here from the raw output
// of std::mt19937_64, whose sequence the C++ standard fixes.
#pragma once

#include <cstdint>
#include <random>

namespace x2car::sim {

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}

  // The next raw 64-bit output of mt19937_64.
  std::uint64_t next() { return engine_(); }

  // Uniform in [0, 1): the top 53 bits of one raw output, scaled by 2^-53.
  double uniform01();

  // Uniform in [lo, hi); lo == hi returns lo. Throws std::invalid_argument when hi < lo.
  double uniform(double lo, double hi);

  // Normal N(mean, sigma^2) by Marsaglia's polar method (only uniform draws, log and sqrt; the
  // second variate of each pair is kept for the next call). sigma == 0 returns mean without
  // drawing. Throws std::invalid_argument when sigma < 0.
  double normal(double mean, double sigma);

  // A seed for an independent stream derived from `seed` and a stream number (SplitMix64 of
  // both), so that each sensor draws from its own stream and adding a draw to one sensor does
  // not change another's output.
  static std::uint64_t derive_seed(std::uint64_t seed, std::uint64_t stream);

 private:
  double standard_normal();

  std::mt19937_64 engine_;
  bool has_spare_ = false;
  double spare_ = 0.0;
};

}  // namespace x2car::sim
