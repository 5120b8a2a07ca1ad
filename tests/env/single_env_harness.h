// Drives one env instance directly, with buffers of its own (no VectorEnv): the env tests' harness.
#pragma once

#include <vector>

#include "rl/env_api/env.h"

namespace rlt {

class SingleEnvHarness {
 public:
  explicit SingleEnvHarness(Env& env) : env_(env) {
    for (const auto& b : env.spec().behaviors) buffers_.emplace_back(b, /*num_envs=*/1);
    for (auto& b : buffers_) view_.emplace_back(&b, 0);
  }

  SingleEnvHarness(const SingleEnvHarness&) = delete;
  SingleEnvHarness& operator=(const SingleEnvHarness&) = delete;

  // what VectorEnv does around Env::reset and Env::step
  void reset() {
    for (auto& v : view_) {
      v.clear_step();
      v.clear_agents();
    }
    env_.reset(view_);
  }
  void step() {
    for (auto& v : view_) v.clear_step();
    env_.step(view_);
  }

  BehaviorBuffers& buffers(int behavior = 0) { return buffers_[behavior]; }
  const float* observation(int k = 0) { return buffers_[0].observations[k].data(); }  // [obs_size]
  float reward() const { return buffers_[0].reward[0]; }
  StepType step_type() const { return buffers_[0].step_type[0]; }
  int terminated() const { return buffers_[0].terminated[0]; }
  const uint8_t* action_mask() const { return buffers_[0].action_mask.data(); }  // [mask_size]
  void set_discrete(int branch, int option) { buffers_[0].discrete_actions[branch] = option; }
  void set_continuous(int index, float value) { buffers_[0].continuous_actions[index] = value; }

 private:
  Env& env_;
  std::vector<BehaviorBuffers> buffers_;  // one per behavior, one env
  StepView view_;
};

}  // namespace rlt
