#include "env/toy/masked_choice.h"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "rl/env_api/uniform_random.h"

namespace rlt {

MaskedChoice::MaskedChoice() {
  BehaviorSpec behavior;
  behavior.name = "MaskedChoice";
  behavior.observations.push_back({"options", {2 * kMaskSize}, ObservationKind::kVector, 0.f, 1.f});
  behavior.action.discrete_branches = {kOptions[0], kOptions[1]};
  behavior.agent_slots = 1;
  spec_.name = "MaskedChoice";
  spec_.behaviors.push_back(behavior);
  spec_.max_episode_steps = kEpisodeSteps;
}

void MaskedChoice::seed(uint64_t seed) { engine_.seed(seed); }

void MaskedChoice::draw_situation() {
  int offset = 0;
  for (int b = 0; b < kBranches; ++b) {
    const int n = kOptions[b];
    // one fair bit per option, redrawn while the branch would allow nothing
    uint64_t bits = 0;
    while (bits == 0) bits = (engine_() >> 32) & ((uint64_t{1} << n) - 1);
    int allowed_count = 0;
    for (int k = 0; k < n; ++k) {
      allowed_[offset + k] = (bits >> k) & 1;
      allowed_count += allowed_[offset + k];
    }
    // bonus: the j-th allowed option, j uniform
    int j = uniform_int(engine_, allowed_count);
    for (int k = 0; k < n; ++k) {
      if (!allowed_[offset + k]) continue;
      if (j-- == 0) {
        bonus_[b] = k;
        break;
      }
    }
    offset += n;
  }
}

void MaskedChoice::write_situation(BehaviorView& view) const {
  float* obs = view.observation(0);     // [7 + 7]: mask, then onehot of the bonus options
  uint8_t* mask = view.action_mask(0);  // [7]
  int offset = 0;
  for (int b = 0; b < kBranches; ++b) {
    for (int k = 0; k < kOptions[b]; ++k) {
      obs[offset + k] = allowed_[offset + k] ? 1.f : 0.f;
      obs[kMaskSize + offset + k] = k == bonus_[b] ? 1.f : 0.f;
      mask[offset + k] = allowed_[offset + k];
    }
    offset += kOptions[b];
  }
}

void MaskedChoice::reset(StepView& out) {
  draw_situation();
  elapsed_steps_ = 0;
  forbidden_actions_ = 0;
  bonus_hits_ = 0;

  BehaviorView& view = out[0];
  view.step_type(0) = StepType::kFirst;
  view.agent_id(0) = 0;
  view.group_id(0) = 0;
  view.reward(0) = 0.f;
  view.group_reward(0) = 0.f;
  view.terminated(0) = 0;
  write_situation(view);
}

void MaskedChoice::step(StepView& io) {
  BehaviorView& view = io[0];
  // a finished agent does not come back before the next reset
  if (!needs_action(view.step_type(0))) {
    view.step_type(0) = StepType::kAbsent;
    view.agent_id(0) = -1;
    return;
  }
  const int32_t* choice = view.discrete_action(0);  // [2]
  for (int b = 0; b < kBranches; ++b)
    if (choice[b] < 0 || choice[b] >= kOptions[b])
      throw std::invalid_argument("MaskedChoice: branch " + std::to_string(b) + " option " +
                                  std::to_string(choice[b]) + " is outside [0, " +
                                  std::to_string(kOptions[b]) + ")");

  // score each branch against the current situation
  float reward = 0.f;
  int offset = 0;
  for (int b = 0; b < kBranches; ++b) {
    if (!allowed_[offset + choice[b]]) {
      reward += kForbiddenReward;
      ++forbidden_actions_;
    } else if (choice[b] == bonus_[b]) {
      reward += kBonusReward;
      ++bonus_hits_;
    }
    offset += kOptions[b];
  }
  view.reward(0) = reward;
  ++elapsed_steps_;

  // next situation; truncated after 10 decisions
  draw_situation();
  write_situation(view);
  view.step_type(0) = elapsed_steps_ >= kEpisodeSteps ? StepType::kLast : StepType::kMid;
  view.terminated(0) = 0;
}

EpisodeMetrics MaskedChoice::episode_metrics() const {
  const int choices = std::max(elapsed_steps_, 1) * kBranches;
  return {{"forbidden_actions", static_cast<float>(forbidden_actions_)},
          {"bonus_rate", static_cast<float>(bonus_hits_) / static_cast<float>(choices)}};
}

}  // namespace rlt
