// Uniform random numbers from an env's own std::mt19937_64 (each env instance owns its engine).
//
// The conversions are written out here instead of using std::uniform_real_distribution, whose
// output differs between standard libraries: the same seed must give the same episode everywhere
// (std::mt19937_64 itself is fully specified by the standard).
#pragma once

#include <cstdint>
#include <random>

namespace rlt {

// uniform in [0, 1): the top 53 bits of one draw
inline double uniform01(std::mt19937_64& engine) { return double(engine() >> 11) * 0x1.0p-53; }

// uniform in [low, high), as numpy's Generator.uniform computes it: low + (high - low) * u
inline double uniform(std::mt19937_64& engine, double low, double high) {
  return low + (high - low) * uniform01(engine);
}

// uniform integer in [0, n) for n >= 1 (multiply-shift; bias below 2^-32 for small n)
inline int uniform_int(std::mt19937_64& engine, int n) {
  const uint64_t top = engine() >> 32;  // 32 random bits
  return static_cast<int>((top * uint64_t(n)) >> 32);
}

}  // namespace rlt
