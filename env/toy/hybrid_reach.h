// HybridReach: a one-agent toy task that needs both halves of a hybrid action at once.
//
// No external reference: a test env of this toolkit, in the spirit of ML-Agents' simple test envs
// (`ml-agents/mlagents/trainers/tests/simple_test_envs.py`).
//
// Each decision the agent observes "target" = (t, onehot(c)): a value t uniform in [-1, 1] and a
// class c uniform in {0, 1, 2}. It answers with one continuous action a (clipped to [-1, 1]) and
// one discrete branch of 3 options, and gets
//     reward = 0.5 * (1 - |a - t|) + 0.5 * [choice == c]
// for that target; a fresh target is drawn after every decision. Episodes are truncated after 10
// decisions and never terminate. Episode metrics: "class_accuracy" (share of right classes) and
// "mean_abs_error" (mean |a - t|).
//
// Returns per episode, computed analytically:
// - optimal (a = t, choice = c): 10 * (0.5 + 0.5) = 10;
// - uniform random (a uniform in [-1, 1], choice uniform): E|a - t| = 2/3 for two independent
//   uniforms on [-1, 1], so 10 * (0.5 * (1 - 2/3) + 0.5 * 1/3) = 10/3 = 3.33;
// - a = 0 with the right class: 10 * (0.5 * (1 - 1/2) + 0.5) = 7.5; right a with a random class:
//   10 * (0.5 + 0.5/3) = 6.67. So a return above 8 needs both action kinds.
#pragma once

#include <cstdint>
#include <random>

#include "rl/env_api/env.h"

namespace rlt {

class HybridReach : public Env {
 public:
  static constexpr int kClasses = 3;
  static constexpr int kEpisodeSteps = 10;

  HybridReach();

  const EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t seed) override;
  void reset(StepView& out) override;
  void step(StepView& io) override;
  EpisodeMetrics episode_metrics() const override;

  // the target the next action is scored against
  float target_value() const { return target_value_; }
  int target_class() const { return target_class_; }

 private:
  void draw_target();
  void write_observation(BehaviorView& view) const;

  EnvSpec spec_;
  std::mt19937_64 engine_;
  float target_value_ = 0.f;  // t, in [-1, 1]
  int target_class_ = 0;      // c, in [0, 3)
  int elapsed_steps_ = 0;
  int right_classes_ = 0;       // decisions with choice == c in this episode
  double sum_abs_error_ = 0.0;  // sum of |a - t| in this episode
};

}  // namespace rlt
