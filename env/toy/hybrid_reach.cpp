#include "env/toy/hybrid_reach.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rl/env_api/uniform_random.h"

namespace rlt {

HybridReach::HybridReach() {
  BehaviorSpec behavior;
  behavior.name = "HybridReach";
  behavior.observations.push_back({"target", {1 + kClasses}, ObservationKind::kVector, -1.f, 1.f});
  behavior.action.continuous_size = 1;
  behavior.action.discrete_branches = {kClasses};
  behavior.agent_slots = 1;
  spec_.name = "HybridReach";
  spec_.behaviors.push_back(behavior);
  spec_.max_episode_steps = kEpisodeSteps;
}

void HybridReach::seed(uint64_t seed) { engine_.seed(seed); }

void HybridReach::draw_target() {
  target_value_ = static_cast<float>(uniform(engine_, -1.0, 1.0));
  target_class_ = uniform_int(engine_, kClasses);
}

void HybridReach::write_observation(BehaviorView& view) const {
  float* obs = view.observation(0);  // [1 + 3]: t, then onehot(c)
  obs[0] = target_value_;
  for (int k = 0; k < kClasses; ++k) obs[1 + k] = k == target_class_ ? 1.f : 0.f;
}

void HybridReach::reset(StepView& out) {
  draw_target();
  elapsed_steps_ = 0;
  right_classes_ = 0;
  sum_abs_error_ = 0.0;

  BehaviorView& view = out[0];
  view.step_type(0) = StepType::kFirst;
  view.agent_id(0) = 0;
  view.group_id(0) = 0;
  view.reward(0) = 0.f;
  view.group_reward(0) = 0.f;
  view.terminated(0) = 0;
  std::fill(view.action_mask(0), view.action_mask(0) + kClasses, uint8_t{1});
  write_observation(view);
}

void HybridReach::step(StepView& io) {
  BehaviorView& view = io[0];
  // a finished agent does not come back before the next reset
  if (!needs_action(view.step_type(0))) {
    view.step_type(0) = StepType::kAbsent;
    view.agent_id(0) = -1;
    return;
  }
  const float a = std::clamp(view.continuous_action(0)[0], -1.f, 1.f);
  const int choice = view.discrete_action(0)[0];
  if (choice < 0 || choice >= kClasses)
    throw std::invalid_argument("HybridReach: discrete action " + std::to_string(choice) +
                                " is outside [0, 3)");

  // score the action against the current target
  const float abs_error = std::fabs(a - target_value_);
  const bool right_class = choice == target_class_;
  view.reward(0) = 0.5f * (1.f - abs_error) + (right_class ? 0.5f : 0.f);
  sum_abs_error_ += abs_error;
  right_classes_ += right_class ? 1 : 0;
  ++elapsed_steps_;

  // next target; truncated after 10 decisions
  draw_target();
  write_observation(view);
  view.step_type(0) = elapsed_steps_ >= kEpisodeSteps ? StepType::kLast : StepType::kMid;
  view.terminated(0) = 0;
}

EpisodeMetrics HybridReach::episode_metrics() const {
  const float steps = static_cast<float>(std::max(elapsed_steps_, 1));
  return {{"class_accuracy", static_cast<float>(right_classes_) / steps},
          {"mean_abs_error", static_cast<float>(sum_abs_error_ / steps)}};
}

}  // namespace rlt
