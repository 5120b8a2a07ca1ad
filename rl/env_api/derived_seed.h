// Seeds derived from a parent seed, for the instances of a vector env, the ranks of a
// distributed run and the restarts of a training run.
//
// Adding the child's index to the parent (seed + i) makes neighbouring parents share children:
// seed 1's instance 0 would be seed 0's instance 1, so runs with seeds 1 and 2 would play 15 of
// their 16 instances' episodes alike. Mixing both through SplitMix64's finalizer (Steele, Lea
// and Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014) makes every
// (parent, child) pair's seed unrelated to the others'.
#pragma once

#include <cstdint>

namespace rlt {

// SplitMix64's output function: a bijection on 64 bits whose outputs for neighbouring inputs
// differ in about half their bits.
inline uint64_t mix_bits(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

// The seed of child `index` of `parent`.
inline uint64_t derived_seed(uint64_t parent, uint64_t index) {
  return mix_bits(mix_bits(parent) + 0x9E3779B97F4A7C15ull * (index + 1));
}

}  // namespace rlt
