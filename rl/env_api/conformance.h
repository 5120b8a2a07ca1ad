// The environment conformance suite: library code that every environment runs in its tests.
//
// Follows PettingZoo's `pettingzoo/test/parallel_test.py` and `seed_test.py` and dm_env's specs:
// spec sanity, observations finite and inside their declared bounds, finite rewards, the slot life
// cycle of step_buffers.h (agents never come back after kLast; the ids of present agents are unique
// across all behaviors of one env), kFirst without reward, valid masks, episodes that end within
// max_episode_steps, bit-identical trajectories for the same seed (also across thread counts and
// after reseed_and_reset) and different trajectories for a different seed. Rollouts take random
// actions that obey the action masks.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rl/env_api/spec.h"

namespace rlt {

struct ConformanceOptions {
  int num_envs = 3;   // instances in each vector env
  int steps = 0;      // vector steps per rollout; 0 = two whole episodes: 2 * (max_steps + 1)
  uint64_t seed = 1;  // base seed of the envs, and seed of the random actions
  int threads = 2;    // threads of the second same-seed rollout (the first runs on one thread)
  bool expect_seed_divergence = true;  // a different seed must change the trajectory
  int max_violations = 20;             // messages kept; the rest are counted in one last line
};

// Problems of a spec alone (names, shapes, bounds, branches, max_episode_steps); empty = sane.
std::vector<std::string> check_env_spec(const EnvSpec& spec);

// Builds registered env `env_id` with `params`, checks its spec, then runs the rollouts described
// above. Returns human-readable violations, each naming the env, and where it applies the step,
// env index, behavior and slot; empty = conformant. Exceptions thrown by the env are violations.
std::vector<std::string> check_env_conformance(const std::string& env_id,
                                               const Parameters& params = {},
                                               const ConformanceOptions& opts = {});

}  // namespace rlt
