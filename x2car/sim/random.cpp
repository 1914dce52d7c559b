#include "x2car/sim/random.hpp"

#include <cmath>
#include <stdexcept>

namespace x2car::sim {
namespace {

// SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijective mix of 64 bits.
std::uint64_t split_mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace

double Random::uniform01() {
  constexpr double kTwoToMinus53 = 1.0 / 9007199254740992.0;
  return static_cast<double>(next() >> 11) * kTwoToMinus53;
}

double Random::uniform(double lo, double hi) {
  if (!(hi >= lo)) throw std::invalid_argument("Random::uniform: hi < lo");
  return lo + (hi - lo) * uniform01();
}

double Random::normal(double mean, double sigma) {
  if (!(sigma >= 0.0)) throw std::invalid_argument("Random::normal: negative sigma");
  if (sigma == 0.0) return mean;
  return mean + sigma * standard_normal();
}

// Marsaglia polar method: (u, v) uniform in the unit disc, s = u^2 + v^2, then
// u * sqrt(-2 ln s / s) and v * sqrt(-2 ln s / s) are independent N(0, 1).
double Random::standard_normal() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  double u = 0.0;
  double v = 0.0;
  double s = 0.0;
  do {
    u = 2.0 * uniform01() - 1.0;
    v = 2.0 * uniform01() - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  const double scale = std::sqrt(-2.0 * std::log(s) / s);
  spare_ = v * scale;
  has_spare_ = true;
  return u * scale;
}

std::uint64_t Random::derive_seed(std::uint64_t seed, std::uint64_t stream) {
  return split_mix(split_mix(seed) ^ stream);
}

}  // namespace x2car::sim
