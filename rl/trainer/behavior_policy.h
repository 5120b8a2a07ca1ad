// Something that chooses the actions of one behavior's agents outside training: a trained network,
// or a baseline (random). Used by evaluation.
#pragma once

#include <cstdint>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rl/core/fast_actor.h"
#include "rl/env_api/step_buffers.h"
#include "rl/env_api/vector_env.h"

namespace rlt {

class BehaviorPolicy {
 public:
  virtual ~BehaviorPolicy() = default;
  // writes an action for every row of `buf` that needs one (and, when `rows` is given, whose
  // entry is 1)
  virtual void act(BehaviorBuffers& buf, const std::vector<uint8_t>* rows = nullptr) = 0;
};

// A trained actor (weights copied into a FastActor).
class NetworkPolicy : public BehaviorPolicy {
 public:
  NetworkPolicy(FastActor actor, int obs_size, bool deterministic, uint64_t seed)
      : actor_(std::move(actor)), obs_size_(obs_size), deterministic_(deterministic), rng_(seed) {}
  void act(BehaviorBuffers& buf, const std::vector<uint8_t>* rows = nullptr) override;
  // the sampling engine as text (checkpoints)
  std::string engine_state() const;
  void set_engine_state(const std::string& text);

 private:
  FastActor actor_;
  int obs_size_;
  bool deterministic_;
  std::mt19937_64 rng_;
};

// Uniform random actions that respect the masks.
class RandomPolicy : public BehaviorPolicy {
 public:
  explicit RandomPolicy(uint64_t seed) : rng_(seed) {}
  void act(BehaviorBuffers& buf, const std::vector<uint8_t>* rows = nullptr) override;

 private:
  std::mt19937_64 rng_;
};

// Does nothing: continuous actions 0 and, on each branch, the first option the mask allows.
class StillPolicy : public BehaviorPolicy {
 public:
  void act(BehaviorBuffers& buf, const std::vector<uint8_t>* rows = nullptr) override;
};

// The env's own hand-written policy (Env::write_scripted_actions) for behavior `behavior` of `env`;
// it acts for every row (the `rows` filter is not supported). Throws std::invalid_argument naming
// the env and behavior when the env has none.
class ScriptedPolicy : public BehaviorPolicy {
 public:
  ScriptedPolicy(VectorEnv& env, int behavior) : env_(env), behavior_(behavior) {}
  void act(BehaviorBuffers& buf, const std::vector<uint8_t>* rows = nullptr) override;

 private:
  VectorEnv& env_;
  int behavior_;
};

}  // namespace rlt
