// Draw: a generator of the tests' own (splitmix64, Box-Muller), so that a
// hand-built machine's data are the same on every platform and standard
// library (std::normal_distribution is not).
#pragma once

#include <cmath>
#include <cstdint>

namespace thermocomp::test {

class Draw {
 public:
  explicit Draw(uint64_t seed) : s_(seed) {}
  // Uniform on [0, 1).
  double Uniform() {
    uint64_t z = (s_ += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  }
  // Standard normal: one of Box-Muller's pair.
  double Normal() {
    const double u = 1.0 - Uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2 * 3.14159265358979323846 * Uniform());
  }

 private:
  uint64_t s_;
};

}  // namespace thermocomp::test
